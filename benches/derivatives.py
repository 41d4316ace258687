#!/usr/bin/env python3
"""The derivatives of the dynamics against Pinocchio's, in interleaved rounds
(BENCHMARKS.md, "Derivatives of the dynamics"):

    python3 benches/derivatives.py [--rounds 5] [--robots panda,solo12,ur5] [--no-build]
                                   [--builds portable,native]

With CASADI_VENV naming a virtual environment with `cmeel-casadi-kin-dyn` (as
benches/baselines/casadi/run.sh makes one), CasADi's automatic differentiation joins:
benches/baselines/casadi/derivatives_codegen.py writes `jacobian` of its rnea and aba SX
functions (cse), compiled with gcc -O3 -march=native around derivatives_main.c, timed in the
same rounds. The operation counts of our derivative programs and of each form the compile
stage chooses among come from codegen/examples/derivative_ops.rs.

Our side is the timing harness (`harness derivatives <robot>`, benches/harness/src/derivatives.rs)
in both builds (portable: the default x86-64 target; native: -C target-cpu=native, in
<target>/native); Pinocchio's side is benches/baselines/pinocchio/derivatives_bench.cpp, built
once by benches/baselines/pinocchio/build.sh into <target>/pinocchio (or BUILD_DIR) against the
headers of `pip install pin cmeel-eigen cmeel-urdfdom-headers` in the interpreter PYTHON names
(python3 by default). Interleaved rounds: in each of `--rounds` rounds the three programs of
every robot run in turn (the order rotated each round, the load average recorded at its
start); each program run times every routine over 1000 random states in 11 rounds, in this
thread's CPU time per call (CLOCK_THREAD_CPUTIME_ID on both sides), and reports medians. The
table gives the median over the rounds and each ratio ours / Pinocchio. Pairs:
inverse_dynamics_derivatives / computeRNEADerivatives (dtau/dq, dtau/dq'; Pinocchio's also fills
M as dtau/dq''), forward_dynamics_derivatives / computeABADerivatives (dq''/dq, dq''/dq', M^-1;
ours computes q'' first; a second row times the trait's default for the same, which forms M and
b and factors M densely at run time), and for scale inverse_dynamics / rnea, forward_dynamics / aba.
"""

import argparse
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import json  # noqa: E402
import statistics  # noqa: E402

from robot import build  # noqa: E402
from rounds import load_avg  # noqa: E402
from target_dir import ROOT, TARGET  # noqa: E402

URDFS = {"panda": "panda.urdf", "ur5": "ur5_robot.urdf", "solo12": "solo12.urdf"}

# (label, Pinocchio routine, our routine)
ROWS = [
    ("dtau/dq, dtau/dq'", "computeRNEADerivatives", "inverse_dynamics_derivatives"),
    ("dq''/dq, dq''/dq', M^-1", "computeABADerivatives", "forward_dynamics_derivatives"),
    ("the same, dense at run time", "computeABADerivatives", "forward_dynamics_derivatives_dense"),
    ("tau (for scale)", "rnea", "inverse_dynamics"),
    ("q'' (for scale)", "aba", "forward_dynamics"),
]


def pinocchio(python="python3"):
    """Pinocchio's derivatives program, built once (minutes of g++) under <target>/pinocchio,
    or None with the reason when its packages are missing."""
    bin_dir = os.environ.get("BUILD_DIR", os.path.join(TARGET, "pinocchio"))
    exe = os.path.join(bin_dir, "derivatives_bench")
    if not os.path.exists(exe):
        env = dict(os.environ, BUILD_DIR=bin_dir, PYTHON=python, TARGETS="derivatives_bench")
        r = subprocess.run(["bash", os.path.join(ROOT, "benches", "baselines", "pinocchio", "build.sh")],
                           env=env, capture_output=True, text=True, cwd=ROOT)
        if r.returncode != 0:
            return None, (r.stderr.strip().splitlines() or ["build.sh failed"])[-1]
    return exe, None


LOCKS = {"panda": ["panda_finger_joint1", "panda_finger_joint2"], "ur5": [], "solo12": []}


def casadi(robot):
    """CasADi's derivatives program of `robot` and its operation counts, built once under
    <target>/casadi-derivatives, or (None, reason) without CASADI_VENV."""
    venv = os.environ.get("CASADI_VENV")
    if not venv:
        return None, "CASADI_VENV not set"
    py = os.path.join(venv, "bin", "python")
    here = os.path.join(ROOT, "benches", "baselines", "casadi")
    out = os.path.join(TARGET, "casadi-derivatives", robot)
    lib = subprocess.run([py, "-c", "import cmeel, os; print(os.path.join(cmeel.__path__[0], '..', "
                          "'cmeel.prefix', 'lib'))"], check=True, capture_output=True, text=True).stdout.strip()
    env = dict(os.environ, LD_LIBRARY_PATH=lib + ":" + os.environ.get("LD_LIBRARY_PATH", ""), PYTHONPATH=here)
    urdf = os.path.join(ROOT, "mechanisms", "urdf", URDFS[robot])
    meta = json.loads(subprocess.run([py, os.path.join(here, "derivatives_codegen.py"), robot, urdf, out]
                                     + LOCKS[robot], check=True, capture_output=True, text=True, env=env).stdout)
    exe = os.path.join(out, "casadi_derivatives")
    subprocess.run(["gcc", "-O3", "-march=native", f"-DNQ={meta['nq']}", "-I", out,
                    os.path.join(here, "derivatives_main.c"), os.path.join(out, "casadi_derivatives.c"),
                    "-lm", "-o", exe], check=True)
    return exe, meta["ops"]


def our_ops(robot):
    """Operation counts of our derivative programs and of each form (derivative_ops)."""
    exe = os.path.join(TARGET, "release", "examples", "derivative_ops")
    urdf = os.path.join(ROOT, "mechanisms", "urdf", URDFS[robot])
    return json.loads(subprocess.run([exe, urdf] + LOCKS[robot], check=True, capture_output=True,
                                     text=True).stdout)


def programs(robot, exe, builds):
    """The programs of one robot: Pinocchio's and our harness in each of `builds`."""
    dirs = {"portable": os.path.join(TARGET, "release"), "native": os.path.join(TARGET, "native", "release")}
    out = {b: [os.path.join(dirs[b], "harness"), "derivatives", robot, "11"] for b in builds}
    out["pinocchio"] = [exe, robot, os.path.join(ROOT, "mechanisms", "urdf", URDFS[robot])]
    return out


CASADI = {"computeRNEADerivatives": "rnea_derivatives", "computeABADerivatives": "aba_derivatives"}


def table(robot, medians):
    """The markdown rows of one robot."""
    pin = medians["pinocchio"]
    cas = medians.get("casadi")
    lines = []
    for label, theirs, ours in ROWS:
        p = pin[theirs]
        c = f"{cas[CASADI[theirs]]:.0f}" if cas and theirs in CASADI and "dense" not in ours else "-"
        cells = []
        for build in ("portable", "native"):
            t = medians.get(build, {}).get(ours)
            cells += [f"{t:.0f}", f"{t / p:.2f}x"] if t is not None else ["-", "-"]
        lines.append(f"| {robot} | {label} | {p:.0f} | {c} | " + " | ".join(cells) + " |")
    return lines


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--robots", default="panda,solo12,ur5")
    p.add_argument("--no-build", action="store_true", help="use the harness builds as they are")
    p.add_argument("--builds", default="portable,native", help="our harness builds to time")
    args = p.parse_args()
    if not args.no_build:
        build()
        subprocess.run(["cargo", "build", "--release", "-p", "mechanism-codegen", "--example", "derivative_ops"],
                       check=True, cwd=ROOT)
    exe, why = pinocchio(os.environ.get("PYTHON", "python3"))
    if exe is None:
        print(f"Pinocchio's program could not be built: {why}", file=sys.stderr)
        return 1
    robots = args.robots.split(",")
    subjects, ops = [], {}
    for robot in robots:
        progs = programs(robot, exe, args.builds.split(","))
        cas, cas_ops = casadi(robot)
        if cas:
            progs["casadi"] = [cas]
        else:
            print(f"CasADi left out: {cas_ops}", file=sys.stderr)
        ops[robot] = (our_ops(robot), cas_ops if cas else None)
        subjects += [(robot, name, cmd) for name, cmd in progs.items()]
    runs, loads = {}, []
    for r in range(args.rounds):
        loads.append(load_avg())
        print(f"round {r + 1}/{args.rounds}, load {loads[-1]}", file=sys.stderr, flush=True)
        k = r % len(subjects)
        for robot, name, cmd in subjects[k:] + subjects[:k]:
            out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
            runs.setdefault(robot, {}).setdefault(name, []).append(json.loads(out))
    lines = ["| robot | routine | Pinocchio (ns) | CasADi AD, native (ns) | ours, portable (ns) | ratio "
             "| ours, native (ns) | ratio |",
             "|---|---|---:|---:|---:|---:|---:|---:|"]
    for robot in robots:
        medians = {name: {routine: statistics.median(run[routine]["median_ns"] for run in rs) for routine in rs[0]}
                   for name, rs in runs[robot].items()}
        lines += table(robot, medians)
    lines += ["", "Operations per call (additions, multiplications, divisions, calls):", "",
              "| robot | n | tau | M + C q' + g | dtau/dq, dtau/dq' (emitted) | M q'' + C q' + g - tau | traced "
              "recursion | analytical recursion | CasADi AD: rnea's | CasADi AD: aba's | dq''/dx, M^-1 (emitted) "
              "| dq''/dx, M^-1 (dense default) |",
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for robot in robots:
        o, c = ops[robot]
        f = o["forms"]
        cells = [f"{f[k]:,}" if k in f else "-" for k in ("M q'' + C q' + g - tau", "traced recursion",
                                                          "analytical recursion")]
        cc = [f"{c[k]:,}" if c else "-" for k in ("rnea_derivatives", "aba_derivatives")]
        cc += [f"{o[k]:,}" for k in ("forward_dynamics_derivatives", "dense_route")]
        lines.append(f"| {robot} | {o['n']} | {o['inverse_dynamics']:,} | {o['mass_and_bias']:,} | "
                     f"{o['inverse_dynamics_derivatives']:,} | " + " | ".join(cells + cc) + " |")
    print("\n".join(lines))
    print(f"Load average (1, 5, 15 min) at the start of each round: {'; '.join(loads)}; after: {load_avg()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
