#!/usr/bin/env python3
"""Regenerate tests/fixtures/{panda,ur5,solo12}_derivatives.json: Pinocchio's derivatives
of the dynamics, the independent reference for `inverse_dynamics_derivatives` and
`forward_dynamics_derivatives` (tests/mechanisms/derivatives_pinocchio.rs).

Setup (Python 3.11):
    pip install pin example-robot-data cmeel-eigen
Run from the repository root:
    python3 benches/baselines/pinocchio/derivatives_fixture.py

Models (the same as `mechanism import` writes them, and as derivatives_bench.cpp builds):
- panda: mechanisms/urdf/panda.urdf by pinocchio.buildModelFromUrdf (mimic ignored -> 9
  dof), then panda_finger_joint1/2 locked at q = 0 by buildReducedModel -> 7 dof
  (mechanisms/panda.mech: `mechanism import --lock panda_finger_joint1 --lock
  panda_finger_joint2`);
- ur5: mechanisms/urdf/ur5_robot.urdf -> 6 dof (the URDF's root link `world` is the world);
- solo12: mechanisms/urdf/solo12.urdf without a root joint: `base_link` fixed to the world,
  as `mechanism import` fixes the root link without `--floating` -> 12 dof
  (the free-flyer Solo12 is floating_derivatives_fixture.py's).
Fixed joints are merged into their parents by both. Gravity: (0, 0, -9.81) on both sides.

Per state (24, numpy.random.default_rng(SEED) drawn in this order: q uniform inside the
joint limits clipped to [-pi, pi], qd in (-2, 2), qdd in (-5, 5), tau in (-20, 20)):
- computeRNEADerivatives(q, qd, qdd) -> dtau_dq, dtau_dv (the third, dtau_da, is M);
- computeABADerivatives(q, qd, tau) -> ddq_dq, ddq_dv, Minv (full, symmetric);
- rnea(q, qd, qdd) and aba(q, qd, tau) for the values themselves.
Matrices row-major. Every float is written with repr(float), so it round-trips exactly.
The script checks Pinocchio against itself: dtau_dq and dtau_dv against central
differences of rnea, ddq_dq = -Minv dtau_dq at (q, qd, aba(q, qd, tau)), and Minv M = 1.
"""

import json
import os
import sys
from importlib import metadata

import numpy as np
import pinocchio as pin

SEED = 20261126
N_STATES = 24
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
ROBOTS = {
    "panda": ("panda.urdf", ["panda_finger_joint1", "panda_finger_joint2"], 7),
    "ur5": ("ur5_robot.urdf", [], 6),
    "solo12": ("solo12.urdf", [], 12),
}


def build_model(urdf, lock, nv):
    full = pin.buildModelFromUrdf(os.path.join(ROOT, "mechanisms", "urdf", urdf))
    if lock:
        ids = [full.getJointId(n) for n in lock]
        assert all(0 < i < full.njoints for i in ids), ids
        q_lock = pin.neutral(full)
        assert all(q_lock[full.joints[i].idx_q] == 0.0 for i in ids)
        model = pin.buildReducedModel(full, ids, q_lock)
    else:
        model = full
    assert model.nq == nv and model.nv == nv, (urdf, model.nq, model.nv)
    assert np.all(model.armature == 0.0)
    assert np.allclose(model.gravity.linear, [0.0, 0.0, -9.81], rtol=0, atol=0)
    return model


def mat(m):
    return [[float(x) for x in row] for row in np.asarray(m)]


def vec(v):
    return [float(x) for x in np.asarray(v).ravel()]


def state(model, data, rng, checks):
    nv = model.nv
    lo = np.maximum(model.lowerPositionLimit, -np.pi)
    hi = np.minimum(model.upperPositionLimit, np.pi)
    q = rng.uniform(lo, hi)
    qd = rng.uniform(-2.0, 2.0, nv)
    qdd = rng.uniform(-5.0, 5.0, nv)
    tau = rng.uniform(-20.0, 20.0, nv)

    dtau_dq, dtau_dv, dtau_da = (x.copy() for x in pin.computeRNEADerivatives(model, data, q, qd, qdd))
    tau_id = pin.rnea(model, data, q, qd, qdd).copy()
    ddq_dq, ddq_dv, minv = (x.copy() for x in pin.computeABADerivatives(model, data, q, qd, tau))
    ddq = pin.aba(model, data, q, qd, tau).copy()

    # Self-checks: Pinocchio against central differences of its own rnea (h = 1e-6: the
    # truncation h^2 |tau'''| ~ 1e-11, the round-off eps |tau| / h ~ 1e-9 of the scale).
    h = 1e-6
    scale = max(1.0, float(np.max(np.abs(dtau_dq))), float(np.max(np.abs(dtau_dv))))
    for k in range(nv):
        e = np.zeros(nv)
        e[k] = h
        fd_q = (pin.rnea(model, data, q + e, qd, qdd) - pin.rnea(model, data, q - e, qd, qdd)) / (2 * h)
        fd_v = (pin.rnea(model, data, q, qd + e, qdd) - pin.rnea(model, data, q, qd - e, qdd)) / (2 * h)
        err = max(float(np.max(np.abs(fd_q - dtau_dq[:, k]))), float(np.max(np.abs(fd_v - dtau_dv[:, k]))))
        checks["rnea_fd"] = max(checks["rnea_fd"], err / scale)
    assert checks["rnea_fd"] < 1e-7, checks
    m = np.triu(dtau_da) + np.triu(dtau_da, 1).T
    checks["minv_m"] = max(checks["minv_m"], float(np.max(np.abs(minv @ m - np.eye(nv)))))
    assert checks["minv_m"] < 1e-9, checks
    # ABA's derivatives are -M^-1 times RNEA's at the forward dynamics' q''.
    dq2, dv2, _ = pin.computeRNEADerivatives(model, data, q, qd, ddq)
    e = max(float(np.max(np.abs(ddq_dq + minv @ dq2))), float(np.max(np.abs(ddq_dv + minv @ dv2))))
    checks["aba_vs_rnea"] = max(checks["aba_vs_rnea"], e / max(1.0, float(np.max(np.abs(ddq_dq)))))
    assert checks["aba_vs_rnea"] < 1e-9, checks
    return {
        "q": vec(q), "qd": vec(qd), "qdd": vec(qdd), "tau": vec(tau),
        "rnea": vec(tau_id), "dtau_dq": mat(dtau_dq), "dtau_dv": mat(dtau_dv),
        "aba": vec(ddq), "ddq_dq": mat(ddq_dq), "ddq_dv": mat(ddq_dv), "minv": mat(minv),
    }


def main():
    for robot, (urdf, lock, nv) in ROBOTS.items():
        model = build_model(urdf, lock, nv)
        data = model.createData()
        rng = np.random.default_rng(SEED)
        checks = {"rnea_fd": 0.0, "minv_m": 0.0, "aba_vs_rnea": 0.0}
        states = [state(model, data, rng, checks) for _ in range(N_STATES)]
        doc = {
            "source": {
                "pinocchio": pin.__version__,
                "pin_pip": metadata.version("pin"),
                "example_robot_data": metadata.version("example-robot-data"),
                "numpy": np.__version__,
                "urdf": f"mechanisms/urdf/{urdf}",
                "locked": lock,
                "command": "python3 benches/baselines/pinocchio/derivatives_fixture.py",
                "seed": SEED,
                "sampling": "numpy.random.default_rng(seed); per state in order: "
                            "q=uniform(max(lower,-pi),min(upper,pi)), qd=uniform(-2,2,n), "
                            "qdd=uniform(-5,5,n), tau=uniform(-20,20,n)",
                "conventions": {
                    "dtau_dq, dtau_dv": "computeRNEADerivatives(q, qd, qdd), row-major",
                    "ddq_dq, ddq_dv, minv": "computeABADerivatives(q, qd, tau), row-major",
                    "rnea": "rnea(q, qd, qdd)", "aba": "aba(q, qd, tau)",
                },
                "self_check_max_relative": checks,
            },
            "joints": list(model.names)[1:],
            "states": states,
        }
        out = os.path.join(ROOT, "tests", "fixtures", f"{robot}_derivatives.json")
        with open(out, "w") as fh:
            fh.write(dumps(doc))
            fh.write("\n")
        print(f"wrote {out}: {N_STATES} states, nv={nv}; self-checks {checks}", file=sys.stderr)


def dumps(obj, indent=0):
    """JSON writer: floats via repr(float), numeric rows on one line."""
    pad = "  " * indent
    if isinstance(obj, float):
        assert np.isfinite(obj)
        return repr(obj)
    if isinstance(obj, (bool, int, str)) or obj is None:
        return json.dumps(obj)
    if isinstance(obj, dict):
        items = [f'{pad}  {json.dumps(k)}: {dumps(v, indent + 1)}' for k, v in obj.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(obj, (list, tuple)):
        if all(isinstance(x, (float, int, str)) for x in obj):
            return "[" + ", ".join(dumps(x) for x in obj) + "]"
        if all(isinstance(x, list) for x in obj):
            return "[" + ", ".join(dumps(x, indent + 1) for x in obj) + "]"
        items = [f"{pad}  {dumps(x, indent + 1)}" for x in obj]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    raise TypeError(type(obj))


if __name__ == "__main__":
    main()
