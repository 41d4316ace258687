#!/usr/bin/env python3
"""Regenerate tests/fixtures/panda_pinocchio.json: independent Pinocchio
reference data for the Franka Panda arm (mechanisms/urdf/panda.urdf).

Setup (Python 3.11):
    pip install pin example-robot-data cmeel-eigen
Run from the repository root:
    python3 benches/baselines/pinocchio/panda_fixture.py

Model: panda.urdf loaded with pinocchio.buildModelFromUrdf (no meshes, mimic
tags ignored -> 9 dof), then the two prismatic finger joints are locked at
q = 0 with pinocchio.buildReducedModel (fingers become fixed bodies rigidly
attached to panda_joint7, inertia kept) -> 7 dof, joints panda_joint1..7.
Gravity: Pinocchio default (0, 0, -9.81).

Every float is written with repr(float), so it round-trips exactly.
"""

import json
import os
import sys
from importlib import metadata

import numpy as np
import pinocchio as pin

SEED = 20261126
N_STATES = 24
LINK_FRAMES = [f"panda_link{i}" for i in range(1, 9)] + ["panda_hand"]
JAC_FRAME = "panda_hand"
FINGER_JOINTS = ["panda_finger_joint1", "panda_finger_joint2"]

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
URDF = os.path.join(ROOT, "mechanisms", "urdf", "panda.urdf")
OUT = os.path.join(ROOT, "tests", "fixtures", "panda_pinocchio.json")


def build_model():
    full = pin.buildModelFromUrdf(URDF)
    assert full.nq == 9 and full.nv == 9, (full.nq, full.nv)
    lock_ids = [full.getJointId(n) for n in FINGER_JOINTS]
    assert all(0 < i < full.njoints for i in lock_ids), lock_ids
    q_lock = pin.neutral(full)
    for jid in lock_ids:
        iq = full.joints[jid].idx_q
        assert q_lock[iq] == 0.0, (full.names[jid], q_lock[iq])
    model = pin.buildReducedModel(full, lock_ids, q_lock)
    assert model.nq == 7 and model.nv == 7, (model.nq, model.nv)
    names = list(model.names)[1:]
    assert names == [f"panda_joint{i}" for i in range(1, 8)], names
    # Pinocchio's algorithms used here ignore model.damping / friction, and
    # the URDF parser leaves the rotor armature at zero.
    assert np.all(model.armature == 0.0)
    return full, model


def vec(v):
    return [float(x) for x in np.asarray(v).ravel()]


def mat(m):
    m = np.asarray(m)
    return [[float(x) for x in row] for row in m]


def main():
    full, model = build_model()
    data = model.createData()
    lo = model.lowerPositionLimit.copy()
    hi = model.upperPositionLimit.copy()

    frame_ids = {}
    for name in LINK_FRAMES:
        fid = model.getFrameId(name, pin.FrameType.BODY)
        assert fid < model.nframes, name
        frame_ids[name] = fid
    jac_id = frame_ids[JAC_FRAME]

    rng = np.random.default_rng(SEED)
    states = []
    max_err = {"sym": 0.0, "rnea_vs_M": 0.0, "aba_inv": 0.0, "damp": 0.0}
    for _ in range(N_STATES):
        q = rng.uniform(lo, hi)
        qd = rng.uniform(-2.0, 2.0, model.nv)
        qdd = rng.uniform(-5.0, 5.0, model.nv)
        tau_in = rng.uniform(-20.0, 20.0, model.nv)

        M_raw = pin.crba(model, data, q).copy()
        M = np.triu(M_raw) + np.triu(M_raw, 1).T  # fill the lower triangle
        if np.any(np.tril(M_raw, -1) != 0.0):  # binding already returned it full
            max_err["sym"] = max(max_err["sym"], float(np.max(np.abs(M_raw - M_raw.T))))
        nle = pin.nonLinearEffects(model, data, q, qd).copy()
        g = pin.computeGeneralizedGravity(model, data, q).copy()
        tau = pin.rnea(model, data, q, qd, qdd).copy()
        ddq = pin.aba(model, data, q, qd, tau_in).copy()

        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacements(model, data)
        placements = {}
        for name, fid in frame_ids.items():
            oMf = data.oMf[fid]
            placements[name] = {"R": mat(oMf.rotation), "p": vec(oMf.translation)}
        pin.computeJointJacobians(model, data, q)
        J = pin.getFrameJacobian(model, data, jac_id, pin.LOCAL_WORLD_ALIGNED).copy()
        J2 = pin.computeFrameJacobian(model, data, q, jac_id, pin.LOCAL_WORLD_ALIGNED)
        assert np.max(np.abs(J - J2)) < 1e-12
        assert J.shape == (6, 7)

        # ---- self-checks -------------------------------------------------
        assert max_err["sym"] < 1e-12
        assert np.all(np.linalg.eigvalsh(M) > 0.0), "M not positive definite"
        e = float(np.max(np.abs(tau - (M @ qdd + nle))))
        max_err["rnea_vs_M"] = max(max_err["rnea_vs_M"], e)
        assert e < 1e-10, e
        assert np.max(np.abs(g - pin.rnea(model, data, q, np.zeros(7), np.zeros(7)))) < 1e-12
        e = float(np.max(np.abs(pin.aba(model, data, q, qd, tau) - qdd)))
        max_err["aba_inv"] = max(max_err["aba_inv"], e)
        assert e < 1e-9, e
        assert np.max(np.abs(M @ ddq + nle - tau_in)) < 1e-9
        # no joint damping in rnea: C(q, qd) qd is quadratic in qd
        e = float(np.max(np.abs(pin.rnea(model, data, q, qd, qdd)
                                - pin.rnea(model, data, q, -qd, qdd))))
        max_err["damp"] = max(max_err["damp"], e)
        assert e < 1e-10, e
        # Jacobian check against a finite difference of the hand placement
        h = 1e-7
        v = qd  # direction (does not draw from rng)
        def hand(qq):
            pin.framesForwardKinematics(model, data, qq)
            return data.oMf[jac_id].copy()
        Tp, Tm = hand(q + h * v), hand(q - h * v)
        lin = (Tp.translation - Tm.translation) / (2 * h)
        ang = pin.log3(Tp.rotation @ Tm.rotation.T) / (2 * h)
        assert np.max(np.abs(J @ v - np.concatenate([lin, ang]))) < 1e-5

        states.append({
            "q": vec(q), "qd": vec(qd), "qdd": vec(qdd), "tau_in": vec(tau_in),
            "M": mat(M), "nle": vec(nle), "g": vec(g), "tau": vec(tau),
            "aba": vec(ddq), "placements": placements,
            "jacobian_panda_hand": mat(J),
        })

    doc = {
        "source": {
            "pinocchio": pin.__version__,
            "pin_pip": metadata.version("pin"),
            "example_robot_data": metadata.version("example-robot-data"),
            "numpy": np.__version__,
            "urdf": "mechanisms/urdf/panda.urdf",
            "command": "python3 benches/baselines/pinocchio/panda_fixture.py",
            "model": "pinocchio.buildModelFromUrdf(urdf) (mimic=False), then "
                     "pinocchio.buildReducedModel(model, [panda_finger_joint1, "
                     "panda_finger_joint2], pinocchio.neutral(model)) (fingers locked at q=0)",
            "seed": SEED,
            "sampling": "numpy.random.default_rng(seed); per state in order: "
                        "q=uniform(lower,upper), qd=uniform(-2,2,7), "
                        "qdd=uniform(-5,5,7), tau_in=uniform(-20,20,7)",
            "conventions": {
                "M": "crba(q), lower triangle filled, row-major",
                "nle": "nonLinearEffects(q, qd) = C(q,qd) qd + g(q)",
                "g": "computeGeneralizedGravity(q)",
                "tau": "rnea(q, qd, qdd)",
                "aba": "aba(q, qd, tau_in) (forward dynamics, qdd)",
                "placements": "oMf after forwardKinematics + updateFramePlacements: "
                              "R row-major 3x3, p = origin in world",
                "jacobian_panda_hand": "6x7 frame Jacobian, LOCAL_WORLD_ALIGNED: rows 0-2 "
                                       "linear velocity of the frame origin in world axes, "
                                       "rows 3-5 angular velocity in world axes",
                "damping": "URDF <dynamics damping> is NOT applied (Pinocchio ignores it here)",
            },
            "self_check_max_abs": max_err,
        },
        "gravity": vec(model.gravity.linear),
        "joints": list(model.names)[1:],
        "limits": {"lower": vec(lo), "upper": vec(hi),
                   "velocity": vec(model.velocityLimit),
                   "effort": vec(model.effortLimit)},
        "frames": [fr.name for fr in model.frames],
        "states": states,
    }
    with open(OUT, "w") as fh:
        fh.write(dumps(doc))
        fh.write("\n")
    print(f"wrote {OUT}: {N_STATES} states, nq={model.nq}; self-check max |err| {max_err}",
          file=sys.stderr)


def dumps(obj, indent=0):
    """JSON writer: floats via repr(float), short numeric lists on one line."""
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
        items = [f"{pad}  {dumps(x, indent + 1)}" for x in obj]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    raise TypeError(type(obj))


if __name__ == "__main__":
    main()
