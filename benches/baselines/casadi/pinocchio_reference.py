"""Pinocchio 4.1's side of the CasADi baseline (run by casadi_bench.py with the interpreter
that has `pin` 4.1 and `example-robot-data`): the robot's model with its locked joints fixed
at q = 0 (`buildReducedModel`), random states, and the reference values every program is
checked against:

    python pinocchio_reference.py ROBOTS.json OUT_DIR [STATES]

Per robot, OUT_DIR/<name>/reference.json: the joint names in Pinocchio's order, the states
(q inside the joint limits, clipped to +-3 rad where a joint has none; q' in (-2, 2) rad/s,
q'' in (-5, 5) rad/s^2, tau in (-20, 20) N m; a fixed seed), and at each state M (`crba`,
its upper triangle mirrored), C q' + g (`rnea` with q'' = 0), tau (`rnea`) and q'' (`aba`).
"""

import json
import os
import sys

import numpy as np
import pinocchio as pin


def model(urdf, lock):
    full = pin.buildModelFromUrdf(urdf)
    ids = [full.getJointId(j) for j in lock]
    return pin.buildReducedModel(full, ids, pin.neutral(full)) if ids else full


def main():
    robots = json.load(open(sys.argv[1]))
    out_dir = sys.argv[2]
    count = int(sys.argv[3]) if len(sys.argv) > 3 else 64
    for name, r in robots.items():
        m = model(r["urdf"], r["lock"])
        data = m.createData()
        rng = np.random.default_rng(20261128)
        lo = np.maximum(m.lowerPositionLimit, -3.0)
        hi = np.minimum(m.upperPositionLimit, 3.0)
        states, ref = [], dict(mass=[], bias=[], tau=[], qdd=[])
        for _ in range(count):
            q = lo + (hi - lo) * rng.random(m.nq)
            v = rng.uniform(-2, 2, m.nv)
            a = rng.uniform(-5, 5, m.nv)
            tau = rng.uniform(-20, 20, m.nv)
            mass = pin.crba(m, data, q)
            mass = np.triu(mass) + np.triu(mass, 1).T
            states.append(dict(q=q.tolist(), v=v.tolist(), a=a.tolist(), tau=tau.tolist()))
            ref["mass"].append(mass.flatten().tolist())
            ref["bias"].append(pin.rnea(m, data, q, v, np.zeros(m.nv)).tolist())
            ref["tau"].append(pin.rnea(m, data, q, v, a).tolist())
            ref["qdd"].append(pin.aba(m, data, q, v, tau).tolist())
        d = os.path.join(out_dir, name)
        os.makedirs(d, exist_ok=True)
        joints = [m.names[j] for j in range(1, m.njoints)]
        with open(os.path.join(d, "reference.json"), "w") as f:
            json.dump(dict(pinocchio=pin.__version__, joints=joints, states=states, reference=ref), f)
        print(f"{name}: {m.nq} joints, {count} states (Pinocchio {pin.__version__})")


if __name__ == "__main__":
    main()
