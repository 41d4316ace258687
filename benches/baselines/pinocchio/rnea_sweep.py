#!/usr/bin/env python3
"""tau = M q'' + C q' + g of every robot of example-robot-data, imported by `mechanism
import` with no option, against Pinocchio's `rnea` (RELIABILITY.md, "Against Pinocchio on
every robot it loads alike").

Setup (Python 3.11):
    pip install pin example-robot-data cmeel-eigen
    cargo build --release
Run from the repository root:
    python3 benches/baselines/pinocchio/rnea_sweep.py [NAME_FILTER ...]

For each URDF: `mechanism import` (a refusal is printed and the robot skipped); files with
`<mimic>` (Pinocchio's reader ignores the coupling), joints of more than one coordinate and
names our importer rewrites are skipped. At two random states (q uniform within the joint
limits, or in [-pi, pi] without; q' and q'' standard normal) our tau is the first row of
`mechanism inverse X.mech --drive 'j = q_j + v_j*t + a_j/2*t^2' ...` (t = 0), matched by
joint name; the line printed is max |ours - rnea| / max |rnea|.
"""

import csv
import glob
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
BIN = os.environ.get("MECHANISM", os.path.join(ROOT, "target", "release", "mechanism"))
SEED = 7


def robots_folder():
    """example-robot-data's `robots` folder (pip installs it under cmeel.prefix/share), or
    the folder the environment variable ROBOTS names."""
    if os.environ.get("ROBOTS"):
        return os.environ["ROBOTS"]
    for path in sys.path:
        share = os.path.join(path, "cmeel.prefix", "share", "example-robot-data", "robots")
        if os.path.isdir(share):
            return share
    raise SystemExit("example-robot-data's robots folder not found")


def ours(mech, names, q, v, a, out):
    drives = []
    for n, qi, vi, ai in zip(names, q, v, a):
        qi, vi, ai = float(qi), float(vi), float(ai)
        drives += ["--drive", f"{n} = {qi!r} + {vi!r}*t + {0.5 * ai!r}*t*t"]
    cmd = [BIN, "inverse", mech, "--t-end", "0.01", "--out", out, "--no-animation",
           "--figures", "none"] + drives
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    if p.returncode:
        raise RuntimeError(p.stderr.strip()[:200])
    with open(os.path.join(out, "inverse.csv")) as fh:
        row = next(csv.DictReader(fh))
    assert float(row["t"]) == 0.0
    return np.array([float(row["tau_" + n]) for n in names])


def main():
    rng = np.random.default_rng(SEED)
    only = sys.argv[1:]
    work = tempfile.mkdtemp(prefix="rnea_sweep_")
    for urdf in sorted(glob.glob(os.path.join(robots_folder(), "**", "*.urdf"), recursive=True)):
        key = os.path.relpath(urdf, robots_folder())
        if only and not any(o in key for o in only):
            continue
        mech = os.path.join(work, "robot.mech")
        p = subprocess.run([BIN, "import", urdf, "--out", mech], capture_output=True, text=True)
        if p.returncode:
            print(f"{key}: import refused: {p.stderr.strip()[:120]}")
            continue
        if "<mimic" in open(urdf).read():
            print(f"{key}: skipped (<mimic>)")
            continue
        model = pin.buildModelFromUrdf(urdf)
        data = model.createData()
        names = [model.names[i] for i in range(1, model.njoints)]
        if not names or any(model.joints[i].nv != 1 for i in range(1, model.njoints)):
            print(f"{key}: skipped (no joint, or a joint of several coordinates)")
            continue
        ourn = re.findall(r"joint = \w+\((\w+),", open(mech).read())
        if sorted(ourn) != sorted(names):
            print(f"{key}: skipped (joint names rewritten by the importer)")
            continue
        index = {n: k for k, n in enumerate(names)}
        perm = [index[n] for n in ourn]
        worst = 0.0
        for _ in range(2):
            th, q = [], np.zeros(model.nq)
            for i in range(1, model.njoints):
                joint, iq = model.joints[i], model.joints[i].idx_q
                if joint.nq == 1:
                    lo, hi = model.lowerPositionLimit[iq], model.upperPositionLimit[iq]
                    if not (np.isfinite(lo) and np.isfinite(hi) and 0 < hi - lo < 20):
                        lo, hi = -np.pi, np.pi
                    x = lo + (hi - lo) * rng.random()
                    q[iq] = x
                else:  # continuous: (cos, sin)
                    x = -np.pi + 2 * np.pi * rng.random()
                    q[iq], q[iq + 1] = np.cos(x), np.sin(x)
                th.append(x)
            v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
            theirs = pin.rnea(model, data, q, v, a)[perm]
            mine = ours(mech, ourn, np.array(th)[perm], v[perm], a[perm], work)
            worst = max(worst, np.max(np.abs(mine - theirs)) / max(1e-12, np.max(np.abs(theirs))))
        print(f"{key}: {len(names)} joints, max |tau - rnea| / max |rnea| = {worst:.2e}")


if __name__ == "__main__":
    main()
