#!/usr/bin/env python3
"""The Panda against Pinocchio, in interleaved rounds (BENCHMARKS.md, "Robot arm"). A step of
`benches/run.sh`; alone:

    python3 benches/robot.py [--rounds 5]

Our side is the timing harness (`harness robot`, benches/harness/src/robot.rs) in both builds
(portable: the default x86-64 target; native: -C target-cpu=native, in <target>/native);
Pinocchio's side is benches/baselines/pinocchio/panda_bench.cpp, built once by
benches/baselines/pinocchio/build.sh into <target>/pinocchio (or BUILD_DIR) against the
headers of `pip install pin cmeel-eigen cmeel-urdfdom-headers` in the interpreter PYTHON
names (python3 by default). The three programs run in turn, `--rounds` times: each program
run times every routine over 1000 random states in 11 rounds and reports medians. The table
gives the median over the runs and each ratio ours / Pinocchio. Pinocchio's routines: crba
(M), nonLinearEffects (C q' + g, against our `bias`), rnea (tau), aba (q''),
computeGeneralizedGravity (g), computeFrameJacobian (the hand, LOCAL_WORLD_ALIGNED).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from target_dir import ROOT, TARGET  # noqa: E402

# (label, Pinocchio routine, our routine)
ROWS = [
    ("M + C q' + g", "crba+nonLinearEffects", "mass_and_bias"),
    ("M + C q' + g + T + Pi (evaluate_into)", "crba+nonLinearEffects", "evaluate_into"),
    ("C q' + g (bias)", "nonLinearEffects", "bias"),
    ("M", "crba", "mass_matrix"),
    ("tau = M q'' + C q' + g", "rnea", "inverse_dynamics"),
    ("forward dynamics q''", "aba", "forward_dynamics"),
    ("g", "computeGeneralizedGravity", "gravity"),
    ("hand Jacobian (6 x 7)", "computeFrameJacobian_hand", "frame_jacobian"),
]


def _run(cmd, env=None):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, env=env, cwd=ROOT).stdout


def pinocchio(python="python3"):
    """Pinocchio's Panda program, built once (minutes of g++) under <target>/pinocchio, or
    None with the reason when its packages are missing."""
    bin_dir = os.environ.get("BUILD_DIR", os.path.join(TARGET, "pinocchio"))
    exe = os.path.join(bin_dir, "panda_bench")
    if not os.path.exists(exe):
        env = dict(os.environ, BUILD_DIR=bin_dir, PYTHON=python)
        r = subprocess.run(["bash", os.path.join(ROOT, "benches", "baselines", "pinocchio", "build.sh")],
                           env=env, capture_output=True, text=True, cwd=ROOT)
        if r.returncode != 0:
            return None, (r.stderr.strip().splitlines() or ["build.sh failed"])[-1]
    # The URDF given explicitly: the program's default path is the checkout it was built in.
    return [exe, os.path.join(ROOT, "mechanisms", "urdf", "panda.urdf")], None


def harness_programs():
    """Our two builds of `harness robot` (built by the caller: run.py's build step, or
    `build` below)."""
    return {
        "portable": [os.path.join(TARGET, "release", "harness"), "robot", "11"],
        "native": [os.path.join(TARGET, "native", "release", "harness"), "robot", "11"],
    }


def build():
    """Our harness in both builds (incremental: seconds when nothing changed)."""
    _run(["cargo", "build", "--release", "-p", "mechanism-harness"])
    env = dict(os.environ, RUSTFLAGS="-C target-cpu=native", CARGO_TARGET_DIR=os.path.join(TARGET, "native"))
    _run(["cargo", "build", "--release", "-p", "mechanism-harness"], env=env)


def measure(programs, rounds):
    """{program: {routine: median over the rounds of its median ns per call}}."""
    runs = {k: [] for k in programs}
    for _ in range(rounds):
        for name, cmd in programs.items():
            runs[name].append(json.loads(_run(cmd)))
    return {name: {routine: statistics.median(r[routine]["median_ns"] for r in rs) for routine in rs[0]}
            for name, rs in runs.items()}


# The targets: (label, our routine, Pinocchio's, largest ratio ours / Pinocchio).
TARGETS = [
    ("M + C q' + g <= 0.7x", "mass_and_bias", "crba+nonLinearEffects", 0.7),
    ("tau <= 0.7x", "inverse_dynamics", "rnea", 0.7),
    ("forward dynamics <= 1.0x", "forward_dynamics", "aba", 1.0),
    ("M <= 0.7x", "mass_matrix", "crba", 0.7),
]


def targets(medians):
    """One line: each target of TARGETS, met or missed in each build."""
    pin = medians["pinocchio"]
    parts = []
    for label, ours, theirs, limit in TARGETS:
        verdicts = [f"{b} {'met' if medians[b][ours] / pin[theirs] <= limit else 'missed'}"
                    for b in ("portable", "native")]
        parts.append(f"{label}: {', '.join(verdicts)}")
    return "Targets: " + "; ".join(parts) + "."


def table(medians):
    """The markdown table of `measure`'s result."""
    pin, port, nat = medians["pinocchio"], medians["portable"], medians["native"]
    lines = ["| routine | Pinocchio (ns) | ours, portable (ns) | ratio | ours, native (ns) | ratio |",
             "|---|---:|---:|---:|---:|---:|"]
    for label, theirs, ours in ROWS:
        p, a, b = pin[theirs], port[ours], nat[ours]
        lines.append(f"| {label} | {p:.0f} | {a:.0f} | {a / p:.2f}x | {b:.0f} | {b / p:.2f}x |")
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--rounds", type=int, default=5)
    args = p.parse_args()
    build()
    theirs, why = pinocchio(os.environ.get("PYTHON", "python3"))
    if theirs is None:
        print(f"Pinocchio's program could not be built: {why}", file=sys.stderr)
        return 1
    medians = measure(dict(harness_programs(), pinocchio=theirs), args.rounds)
    print(table(medians))
    print(targets(medians))
    return 0


if __name__ == "__main__":
    sys.exit(main())
