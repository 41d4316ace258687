#!/usr/bin/env python3
"""Regenerate tests/fixtures/g1_pinocchio.json: independent Pinocchio reference data for
the Unitree G1 humanoid (mechanisms/urdf/g1_29dof_rev_1_0.urdf), a tree of 29 revolute
joints whose two arms branch from a torso that itself moves (three waist joints).

Setup (Python 3.11):
    pip install pin example-robot-data cmeel-eigen
Run from the repository root:
    python3 benches/baselines/pinocchio/g1_fixture.py

Model: pinocchio.buildModelFromUrdf with no root joint (the pelvis fixed to the world, as
`mechanism import` writes it); gravity Pinocchio's default (0, 0, -9.81).
Every float is written with repr(float), so it round-trips exactly.
"""

import os
import sys
from importlib import metadata

import numpy as np
import pinocchio as pin

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from panda_fixture import ROOT, dumps, mat, vec  # noqa: E402

SEED = 20261127
N_STATES = 8

URDF = os.path.join(ROOT, "mechanisms", "urdf", "g1_29dof_rev_1_0.urdf")
OUT = os.path.join(ROOT, "tests", "fixtures", "g1_pinocchio.json")


def main():
    model = pin.buildModelFromUrdf(URDF)
    assert model.nq == 29 and model.nv == 29, (model.nq, model.nv)
    assert np.all(model.armature == 0.0)
    data = model.createData()
    lo, hi = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
    assert np.all(np.isfinite(lo) & np.isfinite(hi) & (lo < hi))
    rng = np.random.default_rng(SEED)
    states = []
    worst = {"rnea_vs_M": 0.0, "aba_inv": 0.0}
    for _ in range(N_STATES):
        q = rng.uniform(lo, hi)
        qd = rng.uniform(-2.0, 2.0, model.nv)
        qdd = rng.uniform(-5.0, 5.0, model.nv)
        M_raw = pin.crba(model, data, q).copy()
        M = np.triu(M_raw) + np.triu(M_raw, 1).T
        nle = pin.nonLinearEffects(model, data, q, qd).copy()
        g = pin.computeGeneralizedGravity(model, data, q).copy()
        tau = pin.rnea(model, data, q, qd, qdd).copy()
        # Free motion (no joint torque): the accelerations gravity and the rates give.
        free = pin.aba(model, data, q, qd, np.zeros(model.nv)).copy()
        # Self-checks: Pinocchio's routines agree with one another.
        assert np.all(np.linalg.eigvalsh(M) > 0.0)
        e = float(np.max(np.abs(tau - (M @ qdd + nle))))
        worst["rnea_vs_M"] = max(worst["rnea_vs_M"], e)
        assert e < 1e-10, e
        e = float(np.max(np.abs(M @ free + nle)))
        worst["aba_inv"] = max(worst["aba_inv"], e)
        assert e < 1e-9, e
        states.append({
            "q": vec(q), "qd": vec(qd), "qdd": vec(qdd), "M": mat(M), "nle": vec(nle),
            "g": vec(g), "tau": vec(tau), "aba_free": vec(free),
            "cond_M": float(np.linalg.cond(M)),
        })
    doc = {
        "source": {
            "pinocchio": pin.__version__,
            "pin_pip": metadata.version("pin"),
            "example_robot_data": metadata.version("example-robot-data"),
            "numpy": np.__version__,
            "urdf": "mechanisms/urdf/g1_29dof_rev_1_0.urdf",
            "command": "python3 benches/baselines/pinocchio/g1_fixture.py",
            "model": "pinocchio.buildModelFromUrdf(urdf), no root joint (pelvis fixed)",
            "seed": SEED,
            "sampling": "numpy.random.default_rng(seed); per state in order: "
                        "q=uniform(lower,upper), qd=uniform(-2,2,29), qdd=uniform(-5,5,29)",
            "conventions": {
                "M": "crba(q), lower triangle filled, row-major",
                "nle": "nonLinearEffects(q, qd) = C(q,qd) qd + g(q)",
                "g": "computeGeneralizedGravity(q)",
                "tau": "rnea(q, qd, qdd)",
                "aba_free": "aba(q, qd, 0): qdd with no joint torque",
                "cond_M": "numpy.linalg.cond(M), 2-norm",
            },
            "self_check_max_abs": worst,
        },
        "gravity": vec(model.gravity.linear),
        "joints": list(model.names)[1:],
        "states": states,
    }
    with open(OUT, "w") as fh:
        fh.write(dumps(doc))
        fh.write("\n")
    print(f"wrote {OUT}: {N_STATES} states; self-check max |err| {worst}", file=sys.stderr)


if __name__ == "__main__":
    main()
