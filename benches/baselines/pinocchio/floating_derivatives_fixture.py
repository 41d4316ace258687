#!/usr/bin/env python3
"""Regenerate tests/fixtures/solo12_floating_derivatives.json: Pinocchio's derivatives of
the dynamics of Solo12 with a free-flyer root, the independent reference for the floating
base's `inverse_dynamics_derivatives` and `forward_dynamics_derivatives`
(tests/mechanisms/floating_derivatives.rs).

Setup (Python 3.11):
    pip install pin example-robot-data cmeel-eigen
Run from the repository root:
    python3 benches/baselines/pinocchio/floating_derivatives_fixture.py

Model: pinocchio.buildModelFromUrdf(mechanisms/urdf/solo12.urdf, JointModelFreeFlyer()),
as `mechanism import --floating` (and `mechanism!(urdf = .., floating = true)`) reads it:
NQ = 19, NV = 18. Gravity (0, 0, -9.81).

Layout: q = [root position (3), quaternion x, y, z, w, joints], v = [root linear velocity,
angular velocity (root frame), joint rates]. A derivative by q is by the tangent:
column k is d/de f(integrate(q, e e_k)) at e = 0.

Per state (24, numpy.random.default_rng(SEED) drawn in this order: quaternion normal(4)
normalised, position uniform(-1, 1, 3), joints uniform(lower, upper), v in (-2, 2),
a in (-5, 5), tau in (-20, 20)):
- computeRNEADerivatives(q, v, a) -> dtau_dq, dtau_dv (the third, dtau_da, is M);
- computeABADerivatives(q, v, tau) -> ddq_dq, ddq_dv, Minv (full, symmetric);
- rnea(q, v, a) and aba(q, v, tau).
Matrices row-major, joints in Pinocchio's order (`joints` names them). Every float is
written with repr(float), so it round-trips exactly.
The script checks Pinocchio against itself: dtau_dq and dtau_dv against central differences
of rnea on the manifold (pinocchio.integrate), ddq_dq = -Minv dtau_dq at
(q, v, aba(q, v, tau)), and Minv M = 1.
"""

import os
import sys
from importlib import metadata

import numpy as np
import pinocchio as pin

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from panda_fixture import ROOT, dumps, mat, vec  # noqa: E402

SEED = 20261129
N_STATES = 24
URDF = "mechanisms/urdf/solo12.urdf"


def state(model, data, rng, checks):
    nv = model.nv
    quat = rng.normal(size=4)
    quat /= np.linalg.norm(quat)
    lo, hi = model.lowerPositionLimit[7:], model.upperPositionLimit[7:]
    q = np.concatenate([rng.uniform(-1.0, 1.0, 3), quat, rng.uniform(lo, hi)])
    v = rng.uniform(-2.0, 2.0, nv)
    a = rng.uniform(-5.0, 5.0, nv)
    tau = rng.uniform(-20.0, 20.0, nv)

    dtau_dq, dtau_dv, dtau_da = (x.copy() for x in pin.computeRNEADerivatives(model, data, q, v, a))
    tau_id = pin.rnea(model, data, q, v, a).copy()
    ddq_dq, ddq_dv, minv = (x.copy() for x in pin.computeABADerivatives(model, data, q, v, tau))
    minv = np.triu(minv) + np.triu(minv, 1).T
    ddq = pin.aba(model, data, q, v, tau).copy()

    # Self-checks: central differences of rnea on the manifold (h = 1e-6: truncation
    # h^2 |tau'''| ~ 1e-11, round-off eps |tau| / h ~ 1e-9 of the scale).
    h = 1e-6
    scale = max(1.0, float(np.max(np.abs(dtau_dq))), float(np.max(np.abs(dtau_dv))))
    for k in range(nv):
        e = np.zeros(nv)
        e[k] = h
        up, down = pin.integrate(model, q, e), pin.integrate(model, q, -e)
        fd_q = (pin.rnea(model, data, up, v, a) - pin.rnea(model, data, down, v, a)) / (2 * h)
        fd_v = (pin.rnea(model, data, q, v + e, a) - pin.rnea(model, data, q, v - e, a)) / (2 * h)
        err = max(float(np.max(np.abs(fd_q - dtau_dq[:, k]))), float(np.max(np.abs(fd_v - dtau_dv[:, k]))))
        checks["rnea_fd"] = max(checks["rnea_fd"], err / scale)
    assert checks["rnea_fd"] < 1e-7, checks
    m = np.triu(dtau_da) + np.triu(dtau_da, 1).T
    checks["minv_m"] = max(checks["minv_m"], float(np.max(np.abs(minv @ m - np.eye(nv)))))
    assert checks["minv_m"] < 1e-9, checks
    dq2, dv2, _ = pin.computeRNEADerivatives(model, data, q, v, ddq)
    e = max(float(np.max(np.abs(ddq_dq + minv @ dq2))), float(np.max(np.abs(ddq_dv + minv @ dv2))))
    checks["aba_vs_rnea"] = max(checks["aba_vs_rnea"], e / max(1.0, float(np.max(np.abs(ddq_dq)))))
    assert checks["aba_vs_rnea"] < 1e-9, checks
    return {
        "q": vec(q), "v": vec(v), "a": vec(a), "tau": vec(tau),
        "rnea": vec(tau_id), "dtau_dq": mat(dtau_dq), "dtau_dv": mat(dtau_dv),
        "aba": vec(ddq), "ddq_dq": mat(ddq_dq), "ddq_dv": mat(ddq_dv), "minv": mat(minv),
    }


def main():
    model = pin.buildModelFromUrdf(os.path.join(ROOT, URDF), pin.JointModelFreeFlyer())
    assert model.nq == 19 and model.nv == 18 and model.names[1] == "root_joint"
    assert np.all(model.armature == 0.0)
    assert np.allclose(model.gravity.linear, [0.0, 0.0, -9.81], rtol=0, atol=0)
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
            "urdf": URDF,
            "model": "buildModelFromUrdf(urdf, JointModelFreeFlyer())",
            "command": "python3 benches/baselines/pinocchio/floating_derivatives_fixture.py",
            "seed": SEED,
            "sampling": "numpy.random.default_rng(seed); per state in order: quaternion "
                        "normal(4) normalised, position uniform(-1,1,3), joints "
                        "uniform(lower,upper), v uniform(-2,2), a uniform(-5,5), "
                        "tau uniform(-20,20)",
            "conventions": {
                "dtau_dq, dtau_dv": "computeRNEADerivatives(q, v, a), row-major; by q: "
                                    "the tangent, column k = d/de rnea(integrate(q, e e_k))",
                "ddq_dq, ddq_dv, minv": "computeABADerivatives(q, v, tau), row-major",
                "rnea": "rnea(q, v, a)", "aba": "aba(q, v, tau)",
            },
            "self_check_max_relative": checks,
        },
        "joints": list(model.names)[2:],
        "states": states,
    }
    out = os.path.join(ROOT, "tests", "fixtures", "solo12_floating_derivatives.json")
    with open(out, "w") as fh:
        fh.write(dumps(doc))
        fh.write("\n")
    print(f"wrote {out}: {N_STATES} states; self-checks {checks}", file=sys.stderr)


if __name__ == "__main__":
    main()
