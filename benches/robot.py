#!/usr/bin/env python3
"""The Panda against Pinocchio, in one run with interleaved rounds (BENCHMARKS.md, "Robot
arm").

    python3 benches/robot.py [--rounds 5]

Builds the harness twice (portable: the default x86-64 target; native: -C target-cpu=native,
in target/native) and Pinocchio's C++ baseline (benches/baselines/pinocchio/build.sh, which
needs `pip install pin cmeel-eigen cmeel-urdfdom-headers`), then runs the three programs in
turn, `--rounds` times: each program run times every routine over the same kind of 1000
random states in 11 rounds and reports medians. The table gives the median over the runs
and each ratio ours / Pinocchio. Pinocchio's routines: crba (M), nonLinearEffects
(C q' + g), rnea (tau), aba (q''), computeGeneralizedGravity (g), computeFrameJacobian
(the hand, LOCAL_WORLD_ALIGNED).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# (label, Pinocchio routine(s), our routine)
ROWS = [
    ("M + C q' + g", ["crba+nonLinearEffects"], "mass_and_bias"),
    ("M + C q' + g + T + Pi (evaluate_into)", ["crba+nonLinearEffects"], "evaluate_into"),
    ("M", ["crba"], "mass_matrix"),
    ("tau = M q'' + C q' + g", ["rnea"], "inverse_dynamics"),
    ("forward dynamics q''", ["aba"], "forward_dynamics"),
    ("g", ["computeGeneralizedGravity"], "gravity"),
    ("hand Jacobian (6 x 7)", ["computeFrameJacobian_hand"], "frame_jacobian"),
]


def run(cmd, env=None):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, env=env, cwd=ROOT)
    return out.stdout


def build():
    run(["cargo", "build", "--release", "-p", "mechanism-harness"])
    env = dict(os.environ, RUSTFLAGS="-C target-cpu=native",
               CARGO_TARGET_DIR=os.path.join(ROOT, "target", "native"))
    run(["cargo", "build", "--release", "-p", "mechanism-harness"], env=env)
    bin_dir = os.environ.get("BUILD_DIR", os.path.join(os.environ.get("TMPDIR", "/tmp"),
                                                        "mechanism-pinocchio-bench"))
    # Pinocchio's baseline takes minutes to compile: built once, kept in BUILD_DIR.
    if not os.path.exists(os.path.join(bin_dir, "panda_bench")):
        run(["bash", "benches/baselines/pinocchio/build.sh"])
    return {
        "portable": [os.path.join(ROOT, "target", "release", "harness"), "robot", "11"],
        "native": [os.path.join(ROOT, "target", "native", "release", "harness"), "robot", "11"],
        "pinocchio": [os.path.join(bin_dir, "panda_bench")],
    }


def pin_routine(results, name):
    return results[name]["median_ns"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--rounds", type=int, default=5)
    args = p.parse_args()
    programs = build()
    runs = {k: [] for k in programs}
    for _ in range(args.rounds):
        for name, cmd in programs.items():
            runs[name].append(json.loads(run(cmd)))
    med = lambda name, f: statistics.median(f(r) for r in runs[name])
    print("| routine | Pinocchio (ns) | ours, portable (ns) | ratio | ours, native (ns) | ratio |")
    print("|---|---:|---:|---:|---:|---:|")
    for label, pin_names, ours in ROWS:
        pin = med("pinocchio", lambda r: pin_routine(r, pin_names[0]))
        port = med("portable", lambda r: r[ours]["median_ns"])
        nat = med("native", lambda r: r[ours]["median_ns"])
        print(f"| {label} | {pin:.0f} | {port:.0f} | {port / pin:.2f}x | {nat:.0f} | {nat / pin:.2f}x |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
