"""A floating-base robot from Python: Solo12 loaded from its URDF with `floating=True`
(a `FloatingModel`) against Pinocchio 4.1's free flyer at the 24 random states of
tests/fixtures/solo12_floating_pinocchio.json (written by
benches/baselines/pinocchio/floating_fixture.py, so CI needs no Pinocchio): M (crba),
C v + g (nonLinearEffects), g, rnea, aba and integrate; a tumbling brick declared with
`joint = floating(..)` simulated with its energy kept; and the bad inputs.

Tolerance 1e-12 of each quantity's largest entry (at least 1), as the Rust test of the same
fixture (tests/mechanisms/floating_pinocchio.rs): both sides sum O(100) products of O(1)
terms in f64; the forward dynamics' solve may lose cond(M) (below 1e4 on Solo12) times the
round-off of M, about 1e-12 at worst.
"""

import json

import numpy as np
import pytest

import mechanism


@pytest.fixture(scope="module")
def solo(root):
    return mechanism.load(str(root / "mechanisms" / "urdf" / "solo12.urdf"), floating=True)


@pytest.fixture(scope="module")
def fixture(root):
    with open(root / "tests" / "fixtures" / "solo12_floating_pinocchio.json") as f:
        return json.load(f)


def close(ours, theirs, what, tol=1e-12):
    theirs = np.asarray(theirs)
    scale = max(1.0, float(np.max(np.abs(theirs))))
    err = float(np.max(np.abs(np.asarray(ours) - theirs)))
    assert err <= tol * scale, f"{what}: max |ours - Pinocchio| = {err:e} (scale {scale})"


def test_solo12_floating_matches_pinocchio(solo, fixture):
    assert isinstance(solo, mechanism.FloatingModel)
    assert (solo.nq, solo.nv) == (19, 18)
    assert solo.configuration[:7] == [
        "root_joint_x", "root_joint_y", "root_joint_z",
        "root_joint_qx", "root_joint_qy", "root_joint_qz", "root_joint_qw",
    ]
    # Pinocchio numbers the joints depth-first, the importer in the file's order: matched by
    # name (the root's entries in place).
    v_of = list(range(6)) + [solo.velocities.index(j) for j in fixture["joints"]]
    q_of = list(range(7)) + [solo.velocities.index(j) + 1 for j in fixture["joints"]]
    dt = fixture["dt"]
    for s in fixture["states"]:
        q = np.zeros(19)
        q[q_of] = s["q"]
        theirs_v = lambda x: np.asarray(x)[v_of]  # noqa: E731
        v, a, tau = np.zeros(18), np.zeros(18), np.zeros(18)
        v[v_of], a[v_of], tau[v_of] = s["v"], s["a"], s["tau_in"]
        m = solo.mass_matrix(q)
        close(m[np.ix_(v_of, v_of)], s["M"], "M")
        close(theirs_v(solo.bias(q, v)), s["nle"], "C v + g")
        close(theirs_v(solo.gravity(q)), s["g"], "g")
        close(theirs_v(solo.inverse_dynamics(q, v, a)), s["tau"], "rnea")
        close(theirs_v(solo.forward_dynamics(q, v, tau)), s["aba"], "aba")
        moved = solo.integrate(q, v * dt, 1.0)
        close(moved[q_of], s["integrate"], "integrate")


def test_a_falling_solo12_keeps_its_energy_and_its_unit_quaternion(solo):
    q0 = solo.neutral()
    q0[2] = 0.4
    v0 = np.zeros(18)
    v0[5] = 1.5  # spinning about z as it falls
    v0[6 + 1] = 3.0
    run = solo.simulate(0.5, q0=q0, v0=v0, step=1e-3, every=50)
    assert run["q"].shape == (11, 19) and run["v"].shape == (11, 18)
    assert run["configuration"] == solo.configuration
    energy = [solo.kinetic_energy(q, v) + solo.potential_energy(q) for q, v in zip(run["q"], run["v"])]
    # RK4 at h = 1e-3 keeps T + Pi of the free fall to about 1e-12 J (the CLI's figure).
    assert max(abs(e - energy[0]) for e in energy) < 1e-8 * max(1.0, abs(energy[0]))
    norms = np.linalg.norm(run["q"][:, 3:7], axis=1)
    assert np.max(np.abs(norms - 1.0)) < 1e-14
    # Free fall: the centre of mass drops by g t^2 / 2 (no force but gravity).
    assert run["t"][-1] == pytest.approx(0.5)


BRICK = """
pub struct Brick;
parameters { g = 9.81; m = 3.0 positive; }
gravity = [0, 0, -g];
link body {
    joint = floating(base);
    mass = m;
    inertia = [[0.2, 0.01, -0.02], [0.01, 0.35, 0.03], [-0.02, 0.03, 0.5]];
}
"""


def test_a_declared_free_body_tumbles_with_its_energy_kept():
    brick = mechanism.from_source(BRICK, name="brick.mech", set={"m": 2.0})
    assert isinstance(brick, mechanism.FloatingModel)
    assert dict(brick.parameters)["m"] == 2.0
    assert brick.configuration[6] == "base_qw"
    # A free body: M = diag(m, m, m, I) at the neutral pose, and a = -M^-1 g = gravity.
    m = brick.mass_matrix(brick.neutral())
    assert np.allclose(m[:3, :3], 2.0 * np.eye(3), rtol=0, atol=1e-15)
    a = brick.forward_dynamics(brick.neutral(), np.zeros(6))
    assert np.allclose(a, [0, 0, -9.81, 0, 0, 0], rtol=0, atol=1e-14)
    v0 = np.array([0.0, 0.0, 2.0, 1.0, 0.0, 1.5])
    run = brick.simulate(1.0, v0=v0, step=1e-3, every=100)
    energy = [brick.kinetic_energy(q, v) + brick.potential_energy(q) for q, v in zip(run["q"], run["v"])]
    assert max(abs(e - energy[0]) for e in energy) < 1e-9 * energy[0]


def test_bad_inputs_to_a_floating_model(solo, root):
    q = solo.neutral()
    with pytest.raises(mechanism.InputError, match="q has 18 entries, not 19"):
        solo.mass_matrix(q[:-1])
    with pytest.raises(mechanism.InputError, match="must be finite"):
        solo.bias(q, np.full(18, np.nan))
    bad = q.copy()
    bad[6] = 2.0
    with pytest.raises(mechanism.MechanismError, match="has norm 2, not 1"):
        solo.simulate(0.1, q0=bad)
    with pytest.raises(mechanism.InputError, match="apply to a URDF file"):
        mechanism.load("panda", floating=True)
    # The test arm's massless base would make M singular: refused at import, naming it.
    with pytest.raises(mechanism.DeclarationError, match="the floating base `base_link` is massless"):
        mechanism.load(str(root / "codegen" / "tests" / "urdf" / "arm.urdf"), floating=True)


def test_solo12_floating_derivatives_match_pinocchio(solo, root):
    """computeRNEADerivatives and computeABADerivatives with the free flyer, at the 24 states
    of tests/fixtures/solo12_floating_derivatives.json, to 1e-10 of each matrix's largest
    entry (the Rust test's tolerance: the forward dynamics' pass through M^-1)."""
    with open(root / "tests" / "fixtures" / "solo12_floating_derivatives.json") as f:
        fixture = json.load(f)
    v_of = list(range(6)) + [solo.velocities.index(j) for j in fixture["joints"]]
    q_of = list(range(7)) + [solo.velocities.index(j) + 1 for j in fixture["joints"]]
    pin_order = np.ix_(v_of, v_of)
    for s in fixture["states"]:
        q = np.zeros(19)
        q[q_of] = s["q"]
        v, a, tau = np.zeros(18), np.zeros(18), np.zeros(18)
        v[v_of], a[v_of], tau[v_of] = s["v"], s["a"], s["tau"]
        dq, dv = solo.inverse_dynamics_derivatives(q, v, a)
        close(dq[pin_order], s["dtau_dq"], "dtau/dq", 1e-10)
        close(dv[pin_order], s["dtau_dv"], "dtau/dv", 1e-10)
        da_dq, da_dv, m_inverse = solo.forward_dynamics_derivatives(q, v, tau)
        close(da_dq[pin_order], s["ddq_dq"], "da/dq", 1e-10)
        close(da_dv[pin_order], s["ddq_dv"], "da/dv", 1e-10)
        close(m_inverse[pin_order], s["minv"], "M^-1", 1e-10)
