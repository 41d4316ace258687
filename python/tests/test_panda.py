"""The Franka Panda imported from its URDF at run time (the fingers locked) against
Pinocchio 4.1 at the 24 random states of tests/fixtures/panda_pinocchio.json (written by
benches/baselines/pinocchio/panda_fixture.py, so CI needs no Pinocchio): M (`crba`),
C q' + g (`nonLinearEffects`), g, tau (`rnea`), q'' (`aba`), the link frames' placements
and the hand's Jacobian (`LOCAL_WORLD_ALIGNED`).

Tolerance: 1e-12 of each quantity's largest entry (at least 1), as the Rust test of the
same fixture: Pinocchio's own identities hold to 2e-14 there, both sides sum O(100)
products in f64, and the forward dynamics is scaled by cond(M) < 1e3 at these states."""

import numpy as np
import pytest

import mechanism


def close(ours, theirs, what):
    theirs = np.asarray(theirs, dtype=float)
    scale = max(1.0, np.abs(theirs).max())
    err = np.abs(np.asarray(ours) - theirs).max()
    assert err <= 1e-12 * scale, f"{what}: max |ours - Pinocchio| = {err:e} (scale {scale})"


@pytest.fixture(scope="module")
def panda(root):
    return mechanism.load(str(root / "mechanisms" / "urdf" / "panda.urdf"),
                          lock=["panda_finger_joint1", "panda_finger_joint2"])


def test_the_urdf_imports_with_pinocchios_joints(panda, panda_fixture):
    assert panda.coordinates == panda_fixture["joints"]
    assert panda.m == 0


@pytest.mark.parametrize("batch", [False, True], ids=["one state at a time", "one batch"])
def test_dynamics_and_frames_match_pinocchio(panda, panda_fixture, batch):
    states = panda_fixture["states"]
    assert len(states) >= 20
    Q = np.array([s["q"] for s in states])
    V = np.array([s["qd"] for s in states])
    A = np.array([s["qdd"] for s in states])
    T = np.array([s["tau_in"] for s in states])
    Z = np.zeros_like(Q)
    if batch:
        M, B, G = panda.mass_matrix(Q), panda.bias(Q, V), panda.bias(Q, Z)
        U, F = panda.inverse_dynamics(Q, V, A), panda.forward_dynamics(Q, V, T)
        J = panda.frame_jacobian("panda_hand", Q)
        X = {f: panda.frame_placement(f, Q) for f in states[0]["placements"]}
    else:
        M = [panda.mass_matrix(q) for q in Q]
        B = [panda.bias(q, v) for q, v in zip(Q, V)]
        G = [panda.bias(q, z) for q, z in zip(Q, Z)]
        U = [panda.inverse_dynamics(q, v, a) for q, v, a in zip(Q, V, A)]
        F = [panda.forward_dynamics(q, v, t) for q, v, t in zip(Q, V, T)]
        J = [panda.frame_jacobian("panda_hand", q) for q in Q]
        X = {f: [panda.frame_placement(f, q) for q in Q] for f in states[0]["placements"]}
    for k, s in enumerate(states):
        close(M[k], s["M"], f"M at state {k}")
        close(B[k], s["nle"], f"C q' + g at state {k}")
        close(G[k], s["g"], f"g at state {k}")
        close(U[k], s["tau"], f"tau at state {k}")
        close(F[k], s["aba"], f"q'' at state {k}")
        close(J[k], s["jacobian_panda_hand"], f"J(hand) at state {k}")
        for frame, p in s["placements"].items():
            close(X[frame][k][:3, :3], p["R"], f"R({frame}) at state {k}")
            close(X[frame][k][:3, 3], p["p"], f"p({frame}) at state {k}")
            np.testing.assert_array_equal(X[frame][k][3], [0, 0, 0, 1])
