#!/usr/bin/env python3
"""Floating-base robots against Pinocchio, in interleaved rounds: Solo12 and Talos (30
joints, the grippers locked), both with a free-flyer root.

    python3 benches/floating_robot.py [--rounds 5]

Our side is the timing harness (`harness floating <robot> 11`, benches/harness/src/
floating.rs) in the portable build (the default x86-64 target; also the native one,
-C target-cpu=native in <target>/native, when built); Pinocchio's side is
benches/baselines/pinocchio/floating_bench.cpp, built by benches/baselines/pinocchio/build.sh
into <target>/pinocchio (or BUILD_DIR). Each program run times every routine over 1000
random states in 11 rounds and reports medians; the programs run in turn, `--rounds` times;
the table gives the median over the runs and each ratio ours / Pinocchio. Pinocchio's
routines: crba + nonLinearEffects (against our mass_and_bias), nonLinearEffects (bias),
crba (mass_matrix), rnea (inverse_dynamics), aba (forward_dynamics), ccrba
(centroidal_momentum_matrix; Pinocchio's also computes the centroidal momentum and the
centre of mass), computeRNEADerivatives (inverse_dynamics_derivatives; Pinocchio's also
computes dtau/da = M), computeABADerivatives (forward_dynamics_derivatives).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from target_dir import ROOT, TARGET  # noqa: E402

ROBOTS = {
    "solo12": ["mechanisms/urdf/solo12.urdf"],
    "talos": ["mechanisms/urdf/talos_reduced.urdf", "gripper_left_joint", "gripper_right_joint"],
}

# (label, Pinocchio routine, our routine)
ROWS = [
    ("M + C v + g", "crba+nonLinearEffects", "mass_and_bias"),
    ("C v + g (bias)", "nonLinearEffects", "bias"),
    ("M", "crba", "mass_matrix"),
    ("tau = M a + C v + g", "rnea", "inverse_dynamics"),
    ("forward dynamics a", "aba", "forward_dynamics"),
    ("centroidal momentum matrix", "ccrba", "centroidal_momentum_matrix"),
    ("dtau/dq, dtau/dv", "computeRNEADerivatives", "inverse_dynamics_derivatives"),
    ("da/dq, da/dv, M^-1", "computeABADerivatives", "forward_dynamics_derivatives"),
]


def _run(cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=ROOT).stdout


def programs(robot):
    bin_dir = os.environ.get("BUILD_DIR", os.path.join(TARGET, "pinocchio"))
    urdf, *lock = ROBOTS[robot]
    out = {"pinocchio": [os.path.join(bin_dir, "floating_bench"), os.path.join(ROOT, urdf), *lock]}
    for build, path in (("portable", "release"), ("native", os.path.join("native", "release"))):
        exe = os.path.join(TARGET, path, "harness")
        if os.path.exists(exe):
            out[build] = [exe, "floating", robot, "11"]
    return out


def measure(progs, rounds):
    runs = {k: [] for k in progs}
    for _ in range(rounds):
        for name, cmd in progs.items():
            runs[name].append(json.loads(_run(cmd)))
    return {name: {r: statistics.median(x[r]["median_ns"] for x in rs) for r in rs[0]}
            for name, rs in runs.items()}


def table(medians):
    builds = [b for b in ("portable", "native") if b in medians]
    head = "| routine | Pinocchio (ns) |" + "".join(f" ours, {b} (ns) | ratio |" for b in builds)
    lines = [head, "|---|---:|" + "---:|---:|" * len(builds)]
    pin = medians["pinocchio"]
    for label, theirs, ours in ROWS:
        cells = "".join(f" {medians[b][ours]:.0f} | {medians[b][ours] / pin[theirs]:.2f}x |"
                        for b in builds)
        lines.append(f"| {label} | {pin[theirs]:.0f} |{cells}")
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--rounds", type=int, default=5)
    args = p.parse_args()
    for robot in ROBOTS:
        load = os.getloadavg()[0]
        medians = measure(programs(robot), args.rounds)
        print(f"\n{robot} (load average at the start {load:.1f}, {args.rounds} interleaved rounds)\n")
        print(table(medians))


if __name__ == "__main__":
    main()
