#!/usr/bin/env python3
"""Regenerate tests/fixtures/chain200_pinocchio.json: Pinocchio's M and bias of the
200-link serial chain of benches/scale/serial_chain.py (revolute joints whose axes
alternate z, y, x, 0.1 m apart, 1 kg links with a full inertia tensor), at 10 states.

Setup (Python 3.11): pip install pin numpy. Run from the repository root:
    python3 benches/baselines/pinocchio/chain_fixture.py

Model: pinocchio.buildModelFromXML(urdf) (fixed base, gravity (0, 0, -9.81)), the URDF
text exactly as `serial_chain.urdf(200)` writes it (the test builds the same text, and
checks its length against `urdf_bytes`). The states are not drawn at random but written
as formulas, so the test builds them itself (k = 0..9 the state, i = 0..199 the joint):

    q_i   = 1.5 sin(0.37 (7 k + 3 i) + 0.2)
    qd_i  = 0.5 cos(0.61 (7 k + 3 i) + 1.0)
    qdd_i = 2.0 sin(0.23 (7 k + 3 i) + 2.0)
    x_i   = cos(0.7 i + 0.3)             (the vector M is applied to)

Stored per state (200 numbers each, the full M would be 40,000): the diagonal of M
(`crba`), M x, C q' + g (`nonLinearEffects`) and tau (`rnea` at qdd). Every float is
written with repr(float), so it round-trips exactly.
"""

import json
import math
import os
import sys
from importlib import metadata

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "benches", "scale"))
import serial_chain  # noqa: E402

N = 200
STATES = 10
OUT = os.path.join(ROOT, "tests", "fixtures", "chain200_pinocchio.json")


def state(k):
    """q, qd, qdd of state k (module docs)."""
    idx = [7 * k + 3 * i for i in range(N)]
    q = np.array([1.5 * math.sin(0.37 * j + 0.2) for j in idx])
    qd = np.array([0.5 * math.cos(0.61 * j + 1.0) for j in idx])
    qdd = np.array([2.0 * math.sin(0.23 * j + 2.0) for j in idx])
    return q, qd, qdd


def main():
    text = serial_chain.urdf(N)
    model = pin.buildModelFromXML(text)
    assert model.nq == N and model.nv == N, (model.nq, model.nv)
    data = model.createData()
    x = np.array([math.cos(0.7 * i + 0.3) for i in range(N)])
    states = []
    worst = 0.0
    for k in range(STATES):
        q, qd, qdd = state(k)
        m = pin.crba(model, data, q).copy()
        m = np.triu(m) + np.triu(m, 1).T
        nle = pin.nonLinearEffects(model, data, q, qd).copy()
        tau = pin.rnea(model, data, q, qd, qdd).copy()
        # Self-check: rnea = M qdd + nle, to the round-off of sums of 200 terms.
        err = float(np.max(np.abs(tau - (m @ qdd + nle))) / max(1.0, np.max(np.abs(tau))))
        worst = max(worst, err)
        assert err < 1e-12, err
        states.append({
            "diag_M": [float(v) for v in np.diag(m)],
            "M_x": [float(v) for v in m @ x],
            "nle": [float(v) for v in nle],
            "tau": [float(v) for v in tau],
        })
    doc = {
        "source": {
            "pinocchio": pin.__version__,
            "pin_pip": metadata.version("pin"),
            "numpy": np.__version__,
            "command": "python3 benches/baselines/pinocchio/chain_fixture.py",
            "urdf": "benches/scale/serial_chain.py: serial_chain.urdf(200)",
            "states": "formulas of the module docs, k = 0..9",
            "self_check_max_rel": worst,
        },
        "n": N,
        "urdf_bytes": len(text.encode()),
        "states": states,
    }
    with open(OUT, "w") as fh:
        json.dump(doc, fh, indent=None, separators=(",", ":"))
        fh.write("\n")
    print(f"wrote {OUT}: {STATES} states, n = {N}; self-check {worst:.1e}", file=sys.stderr)


if __name__ == "__main__":
    main()
