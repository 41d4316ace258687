"""The derivatives of the dynamics from Python (the book's "Derivatives of the dynamics"):

- the Franka Panda imported from its URDF (fingers locked) against Pinocchio 4.1's
  computeRNEADerivatives (dtau_dq, dtau_dv) and computeABADerivatives (ddq_dq, ddq_dv, Minv)
  at the 24 random states of tests/fixtures/panda_derivatives.json (written by Pinocchio's
  Python, benches/baselines/pinocchio/derivatives_fixture.py, so CI needs no Pinocchio), one
  state at a time and as one batch; and, where `pinocchio` imports, at fresh random states
  against Pinocchio called here;
- the five-bar leg (two loop rows) against central differences of the model's own
  forward dynamics (the augmented solve) along every coordinate of q, v and tau;
- dtau/dp against central differences of the inverse dynamics in the parameters.

Tolerances. Pinocchio: 1e-10 of each matrix's largest entry (at least 1), the Rust test's
(tests/mechanisms/derivatives_pinocchio.rs): both sides sum O(100) products in f64 (about
1e-14 relative), and the forward dynamics' derivatives pass through M^-1 with cond(M) < 1e4
at these states. Central differences D(h) = (f(x + h e) - f(x - h e)) / 2h: truncation
h^2/6 |f'''| ~ 2e-9 of the derivative's scale at h = 1e-4 for these trigonometric dynamics,
round-off eps |f| cond / h below 1e-8 of it; tau enters affinely (h = 1, no truncation).
The bound, 1e-6 of the largest entry, is 100 times those; a wrong sign, term or column is
O(1) of it.
"""

import numpy as np
import pytest

import mechanism


def close(ours, theirs, what, tol=1e-10):
    theirs = np.asarray(theirs, dtype=float)
    scale = max(1.0, np.abs(theirs).max())
    err = np.abs(np.asarray(ours) - theirs).max()
    assert err <= tol * scale, f"{what}: max |ours - reference| = {err:e} (scale {scale:e})"


@pytest.fixture(scope="module")
def panda(root):
    return mechanism.load(str(root / "mechanisms" / "urdf" / "panda.urdf"),
                          lock=["panda_finger_joint1", "panda_finger_joint2"])


@pytest.fixture(scope="module")
def fixture(root):
    import json
    with open(root / "tests" / "fixtures" / "panda_derivatives.json") as f:
        return json.load(f)


def test_the_fixture_is_in_our_coordinate_order(panda, fixture):
    assert panda.coordinates == fixture["joints"]


@pytest.mark.parametrize("batch", [False, True], ids=["one state at a time", "one batch"])
def test_panda_derivatives_match_pinocchio(panda, fixture, batch):
    states = fixture["states"]
    assert len(states) == 24
    n = panda.n
    Q, V, A, T = (np.array([s[k] for s in states]) for k in ("q", "qd", "qdd", "tau"))
    if batch:
        dq, dv = panda.inverse_dynamics_derivatives(Q, V, A)
        fq, fv, minv = panda.forward_dynamics_derivatives(Q, V, T)
        assert dq.shape == (24, n, n) and minv.shape == (24, n, n)
    else:
        inverse = [panda.inverse_dynamics_derivatives(q, v, a) for q, v, a in zip(Q, V, A)]
        forward = [panda.forward_dynamics_derivatives(q, v, t) for q, v, t in zip(Q, V, T)]
        dq, dv = ([d[k] for d in inverse] for k in range(2))
        fq, fv, minv = ([d[k] for d in forward] for k in range(3))
        assert dq[0].shape == (n, n)
    for k, s in enumerate(states):
        close(dq[k], s["dtau_dq"], f"dtau/dq at state {k}")
        close(dv[k], s["dtau_dv"], f"dtau/dv at state {k}")
        close(fq[k], s["ddq_dq"], f"ddq/dq at state {k}")
        close(fv[k], s["ddq_dv"], f"ddq/dv at state {k}")
        close(minv[k], s["minv"], f"Minv at state {k}")


def test_panda_derivatives_match_pinocchio_called_here(panda, root):
    pin = pytest.importorskip("pinocchio")
    full = pin.buildModelFromUrdf(str(root / "mechanisms" / "urdf" / "panda.urdf"))
    lock = [full.getJointId(j) for j in ("panda_finger_joint1", "panda_finger_joint2")]
    model = pin.buildReducedModel(full, lock, pin.neutral(full))
    data = model.createData()
    assert [model.names[j] for j in range(1, model.njoints)] == panda.coordinates
    rng = np.random.default_rng(51)
    for k in range(8):
        q = rng.uniform(np.maximum(model.lowerPositionLimit, -np.pi),
                        np.minimum(model.upperPositionLimit, np.pi))
        v, a, tau = rng.uniform(-2, 2, 7), rng.uniform(-5, 5, 7), rng.uniform(-20, 20, 7)
        dq, dv, _ = pin.computeRNEADerivatives(model, data, q, v, a)
        ours = panda.inverse_dynamics_derivatives(q, v, a)
        close(ours[0], dq, f"dtau/dq at state {k}")
        close(ours[1], dv, f"dtau/dv at state {k}")
        fq, fv, minv = (np.array(x) for x in pin.computeABADerivatives(model, data, q, v, tau))
        minv = np.triu(minv) + np.triu(minv, 1).T  # Pinocchio fills the upper triangle
        ours = panda.forward_dynamics_derivatives(q, v, tau)
        for mine, theirs, what in zip(ours, (fq, fv, minv), ("ddq/dq", "ddq/dv", "Minv")):
            close(mine, theirs, f"{what} at state {k}")


def central(f, x, k, h):
    e = np.zeros_like(x)
    e[k] = h
    return (f(x + e) - f(x - e)) / (2 * h)


@pytest.fixture(scope="module")
def leg():
    """The five-bar leg and a state on its constraints (a moment of a run)."""
    leg = mechanism.load("five_bar")
    run = leg.simulate(t_end=0.2, samples_per_second=10.0)
    tau = 0.3 * np.sin(np.arange(1.0, leg.n + 1))
    return leg, run.q[-1], run.qd[-1], tau


def test_constrained_derivatives_match_central_differences(leg):
    leg, q, v, tau = leg
    d = leg.constrained_dynamics_derivatives(q, v, tau)
    assert d["dqdd_dq"].shape == (4, 4) and d["dlambda_dq"].shape == (2, 4)
    # q'' is the model's forward dynamics (the same augmented system, solved again).
    close(d["qdd"], leg.forward_dynamics(q, v, tau), "q''", tol=1e-12)
    # The tuple form gives the same derivatives of q''.
    for mine, key in zip(leg.forward_dynamics_derivatives(q, v, tau), ("dqdd_dq", "dqdd_dv", "dqdd_dtau")):
        np.testing.assert_array_equal(mine, d[key])
    # Each column against central differences of q'' (the forward dynamics) and of lambda
    # (the solve's multipliers): every direction of q and v (the rows have full rank, so
    # both are smooth off the constraints too) and of tau.
    fq = lambda x: leg.forward_dynamics(x, v, tau)  # noqa: E731
    fv = lambda x: leg.forward_dynamics(q, x, tau)  # noqa: E731
    ft = lambda x: leg.forward_dynamics(q, v, x)  # noqa: E731
    lq = lambda x: leg.constrained_dynamics_derivatives(x, v, tau)["lambda"]  # noqa: E731
    lv = lambda x: leg.constrained_dynamics_derivatives(q, x, tau)["lambda"]  # noqa: E731
    lt = lambda x: leg.constrained_dynamics_derivatives(q, v, x)["lambda"]  # noqa: E731
    for key, f, x, h in [("dqdd_dq", fq, q, 1e-4), ("dqdd_dv", fv, v, 1e-4), ("dqdd_dtau", ft, tau, 1.0),
                         ("dlambda_dq", lq, q, 1e-4), ("dlambda_dv", lv, v, 1e-4),
                         ("dlambda_dtau", lt, tau, 1.0)]:
        numeric = np.column_stack([central(f, x, k, h) for k in range(leg.n)])
        close(d[key], numeric, key, tol=1e-6)


def test_constrained_derivatives_of_a_batch_are_those_of_each_state(leg):
    leg, q, v, tau = leg
    Q, V, T = np.array([q, q]), np.array([v, v]), np.array([tau, 2 * tau])
    batch = leg.constrained_dynamics_derivatives(Q, V, T)
    assert batch["dlambda_dq"].shape == (2, 2, 4)
    for r in range(2):
        one = leg.constrained_dynamics_derivatives(Q[r], V[r], T[r])
        for key, value in one.items():
            np.testing.assert_array_equal(batch[key][r], value)


def test_parameter_derivatives_match_central_differences(leg):
    leg, q, v, _ = leg
    a = np.linspace(-1.0, 1.0, leg.n)
    names = [name for name, _ in leg.parameters]
    d = leg.inverse_dynamics_parameter_derivatives(q, v, a)
    assert d.shape == (leg.n, len(names)) and len(names) > 0
    for k, (name, value) in enumerate(leg.parameters):
        h = 1e-4 * max(1.0, abs(value))
        up, down = (mechanism.load("five_bar", set={name: value + s * h}) for s in (1, -1))
        numeric = (up.inverse_dynamics(q, v, a) - down.inverse_dynamics(q, v, a)) / (2 * h)
        close(d[:, k], numeric, f"du/d{name}", tol=1e-6)


def test_the_derivatives_reject_a_wrong_shape(panda):
    with pytest.raises(mechanism.InputError, match="shape"):
        panda.inverse_dynamics_derivatives(np.zeros(7), np.zeros(7), np.zeros(6))
