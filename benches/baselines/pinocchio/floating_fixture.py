#!/usr/bin/env python3
"""Regenerate tests/fixtures/solo12_floating_pinocchio.json and
tests/fixtures/talos_floating_pinocchio.json: independent Pinocchio reference data for two
floating-base robots, Solo12 (mechanisms/urdf/solo12.urdf, 12 joints) and Talos
(mechanisms/urdf/talos_reduced.urdf, 32 joints of which the two grippers are locked at
q = 0: 30 joints).

Setup (Python 3.11):
    pip install pin example-robot-data cmeel-eigen
Run from the repository root:
    python3 benches/baselines/pinocchio/floating_fixture.py

Model: pinocchio.buildModelFromUrdf(urdf, pinocchio.JointModelFreeFlyer()), the grippers
locked with buildReducedModel; gravity Pinocchio's default (0, 0, -9.81). Layout:
q = [root position (3), quaternion x, y, z, w, joints], v = [root linear velocity, angular
velocity (root frame), joint rates].
Every float is written with repr(float), so it round-trips exactly.
"""

import os
import sys
from importlib import metadata

import numpy as np
import pinocchio as pin

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from panda_fixture import ROOT, dumps, mat, vec  # noqa: E402

SEED = 20261128
N_STATES = 24
DT = 0.1  # the step of the integrate check

ROBOTS = {
    "solo12": {
        "urdf": "mechanisms/urdf/solo12.urdf",
        "lock": [],
        "joints": 12,
        "jacobians": ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT", "base_link"],
    },
    "talos": {
        "urdf": "mechanisms/urdf/talos_reduced.urdf",
        "lock": ["gripper_left_joint", "gripper_right_joint"],
        "joints": 30,
        "jacobians": ["left_sole_link", "right_sole_link", "gripper_left_base_link",
                      "gripper_right_base_link", "rgbd_link", "base_link"],
    },
}


def build_model(spec):
    full = pin.buildModelFromUrdf(os.path.join(ROOT, spec["urdf"]), pin.JointModelFreeFlyer())
    ids = [full.getJointId(n) for n in spec["lock"]]
    assert all(0 < i < full.njoints for i in ids), ids
    model = pin.buildReducedModel(full, ids, pin.neutral(full)) if ids else full
    nj = spec["joints"]
    # No continuous joint (their q would be (cos, sin)): NQ = 7 + joints, NV = 6 + joints.
    assert model.nq == 7 + nj and model.nv == 6 + nj, (model.nq, model.nv)
    assert model.names[1] == "root_joint"
    assert np.all(model.armature == 0.0)
    return model


def random_state(model, rng):
    lo = model.lowerPositionLimit[7:].copy()
    hi = model.upperPositionLimit[7:].copy()
    assert np.all(np.isfinite(lo) & np.isfinite(hi) & (lo < hi))
    quat = rng.normal(size=4)
    quat /= np.linalg.norm(quat)
    q = np.concatenate([rng.uniform(-1.0, 1.0, 3), quat, rng.uniform(lo, hi)])
    v = rng.uniform(-2.0, 2.0, model.nv)
    a = rng.uniform(-5.0, 5.0, model.nv)
    tau_in = rng.uniform(-20.0, 20.0, model.nv)
    return q, v, a, tau_in


def one_state(model, data, q, v, a, tau_in, frames, jac_frames, worst):
    M_raw = pin.crba(model, data, q).copy()
    M = np.triu(M_raw) + np.triu(M_raw, 1).T
    nle = pin.nonLinearEffects(model, data, q, v).copy()
    g = pin.computeGeneralizedGravity(model, data, q).copy()
    tau = pin.rnea(model, data, q, v, a).copy()
    ddq = pin.aba(model, data, q, v, tau_in).copy()
    pin.framesForwardKinematics(model, data, q)
    placements = {n: {"R": mat(data.oMf[f].rotation), "p": vec(data.oMf[f].translation)}
                  for n, f in frames.items()}
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    jacobians = {n: mat(pin.getFrameJacobian(model, data, frames[n], pin.LOCAL_WORLD_ALIGNED))
                 for n in jac_frames}
    moved = pin.integrate(model, q, v * DT)
    ag = pin.ccrba(model, data, q, v).copy()
    com = pin.centerOfMass(model, data, q).copy()
    e = float(np.max(np.abs(ag @ v - data.hg.vector)))
    worst["ccrba_hg"] = max(worst["ccrba_hg"], e)
    assert e < 1e-12, e
    # Self-checks: Pinocchio's routines agree with one another.
    assert np.all(np.linalg.eigvalsh(M) > 0.0)
    e = float(np.max(np.abs(tau - (M @ a + nle))))
    worst["rnea_vs_M"] = max(worst["rnea_vs_M"], e)
    assert e < 1e-9, e
    e = float(np.max(np.abs(M @ ddq + nle - tau_in)))
    worst["aba_inv"] = max(worst["aba_inv"], e)
    assert e < 1e-8, e
    assert abs(np.linalg.norm(moved[3:7]) - 1.0) < 1e-14
    return {
        "q": vec(q), "v": vec(v), "a": vec(a), "tau_in": vec(tau_in), "M": mat(M),
        "nle": vec(nle), "g": vec(g), "tau": vec(tau), "aba": vec(ddq),
        "placements": placements, "jacobians": jacobians, "integrate": vec(moved),
        "Ag": mat(ag), "com": vec(com),
        "cond_M": float(np.linalg.cond(M)),
    }


def fixture(name, spec, rng):
    model = build_model(spec)
    data = model.createData()
    # The BODY frames: one per URDF link (the fixed ones merged into their joint's body).
    frames = {f.name: i for i, f in enumerate(model.frames) if f.type == pin.FrameType.BODY}
    for n in spec["jacobians"]:
        assert n in frames, n
    worst = {"rnea_vs_M": 0.0, "aba_inv": 0.0, "ccrba_hg": 0.0}
    states = [one_state(model, data, *random_state(model, rng), frames, spec["jacobians"], worst)
              for _ in range(N_STATES)]
    doc = {
        "source": {
            "pinocchio": pin.__version__,
            "pin_pip": metadata.version("pin"),
            "example_robot_data": metadata.version("example-robot-data"),
            "numpy": np.__version__,
            "urdf": spec["urdf"],
            "command": "python3 benches/baselines/pinocchio/floating_fixture.py",
            "model": "buildModelFromUrdf(urdf, JointModelFreeFlyer()); locked at 0: "
                     + (", ".join(spec["lock"]) or "none"),
            "seed": SEED,
            "sampling": "numpy.random.default_rng(seed), shared by the robots in order; "
                        "per state: quaternion = normal(4) normalised, position "
                        "uniform(-1,1,3), joints uniform(lower,upper), v uniform(-2,2), "
                        "a uniform(-5,5), tau_in uniform(-20,20)",
            "conventions": {
                "M": "crba(q), lower triangle filled, row-major",
                "nle": "nonLinearEffects(q, v) = C(q,v) v + g(q)",
                "g": "computeGeneralizedGravity(q)",
                "tau": "rnea(q, v, a)",
                "aba": "aba(q, v, tau_in)",
                "placements": "oMf of every BODY frame: R (row-major), p",
                "jacobians": "getFrameJacobian(.., LOCAL_WORLD_ALIGNED) of the named frames",
                "integrate": f"integrate(q, v * {DT})",
                "Ag": "ccrba(q, v): the centroidal momentum matrix, [linear; angular about "
                      "the centre of mass], world axes, row-major",
                "com": "centerOfMass(q), world",
                "cond_M": "numpy.linalg.cond(M), 2-norm",
            },
            "self_check_max_abs": worst,
        },
        "gravity": vec(model.gravity.linear),
        "joints": list(model.names)[2:],
        "dt": DT,
        "states": states,
    }
    out = os.path.join(ROOT, "tests", "fixtures", f"{name}_floating_pinocchio.json")
    with open(out, "w") as fh:
        fh.write(dumps(doc))
        fh.write("\n")
    print(f"wrote {out}: {N_STATES} states; self-check max |err| {worst}", file=sys.stderr)


def main():
    rng = np.random.default_rng(SEED)
    for name, spec in ROBOTS.items():
        fixture(name, spec, rng)


if __name__ == "__main__":
    main()
