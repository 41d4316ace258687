"""A batch of inverse dynamics through Python: the Panda (from its URDF, fingers locked),
20,000 random states, `model.inverse_dynamics(Q, V, A)` of the `mechanism` package (one
call, the rows on all cores without the GIL) against Pinocchio's `rnea` in a Python loop,
and the per-call cost of one state on both sides. BENCHMARKS.md, "Python".

Both need one interpreter: a virtual environment that sees the system's Pinocchio
(`pip install pin` elsewhere) and has the package installed:

    python3 -m venv --system-site-packages target/bench-venv
    target/bench-venv/bin/pip install ./python
    target/bench-venv/bin/python benches/python_batch.py [--rounds 5] [--states 20000]

Rounds are interleaved: in each, every subject runs once, in an order that rotates from
round to round, and the load average is read; the table gives the median over the rounds
and [min-max], the ratio is taken per round. The two sides' results are compared first
(the largest difference relative to the largest torque).
"""

import argparse
import os
import pathlib
import statistics
import time

import numpy as np
import pinocchio as pin

import mechanism

ROOT = pathlib.Path(__file__).resolve().parents[1]
URDF = ROOT / "mechanisms" / "urdf" / "panda.urdf"
FINGERS = ["panda_finger_joint1", "panda_finger_joint2"]


def pinocchio_model():
    full = pin.buildModelFromUrdf(str(URDF))
    locked = [full.getJointId(j) for j in FINGERS]
    model = pin.buildReducedModel(full, locked, pin.neutral(full))
    return model, model.createData()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--states", type=int, default=20000)
    ap.add_argument("--single", type=int, default=2000, help="calls of one state per round")
    args = ap.parse_args()

    ours = mechanism.load(str(URDF), lock=FINGERS)
    model, data = pinocchio_model()
    assert list(model.names)[1:] == ours.coordinates
    rng = np.random.default_rng(2026)
    lo, hi = model.lowerPositionLimit, model.upperPositionLimit
    Q = rng.uniform(lo, hi, (args.states, 7))
    V = rng.uniform(-2, 2, (args.states, 7))
    A = rng.uniform(-5, 5, (args.states, 7))

    def ours_batch():
        return ours.inverse_dynamics(Q, V, A)

    def pin_loop():
        out = np.empty_like(Q)
        for k in range(len(Q)):
            out[k] = pin.rnea(model, data, Q[k], V[k], A[k])
        return out

    def ours_single():
        for k in range(args.single):
            ours.inverse_dynamics(Q[k], V[k], A[k])

    def pin_single():
        for k in range(args.single):
            pin.rnea(model, data, Q[k], V[k], A[k])

    U, P = ours_batch(), pin_loop()
    rel = np.abs(U - P).max() / np.abs(P).max()
    print(f"agreement: max |ours - rnea| / max |rnea| = {rel:.1e} over {args.states} states")

    subjects = {"ours, one batch call": ours_batch, "Pinocchio, Python loop": pin_loop,
                "ours, one state per call": ours_single, "Pinocchio, one state per call": pin_single}
    names = list(subjects)
    times = {n: [] for n in names}
    loads = []
    for r in range(args.rounds):
        loads.append(" ".join(f"{x:.2f}" for x in os.getloadavg()))
        order = names[r % len(names):] + names[: r % len(names)]
        for n in order:
            t = time.perf_counter()
            subjects[n]()
            times[n].append(time.perf_counter() - t)

    def fmt(values, per):
        med = statistics.median(values) / per * 1e6
        return f"{med:.3f} [{min(values) / per * 1e6:.3f}-{max(values) / per * 1e6:.3f}]"

    ratio = [o / p for o, p in zip(times[names[0]], times[names[1]])]
    single = [o / p for o, p in zip(times[names[2]], times[names[3]])]
    print(f"\n{args.rounds} interleaved rounds; load average (1, 5, 15 min) at each round's start: "
          + "; ".join(loads) + f"; {os.cpu_count()} cores\n")
    print("| subject | states per round | us per state, median [min-max] | total per round, median (ms) |")
    print("|---|---:|---:|---:|")
    for n in names:
        per = args.states if n in names[:2] else args.single
        print(f"| {n} | {per} | {fmt(times[n], per)} | {statistics.median(times[n]) * 1e3:.1f} |")
    print(f"\nbatch / Pinocchio's loop, per round: median {statistics.median(ratio):.3f}x "
          f"[{min(ratio):.3f}-{max(ratio):.3f}] (target at most 0.25x)")
    print(f"one state per call, ours / Pinocchio's: median {statistics.median(single):.2f}x "
          f"[{min(single):.2f}-{max(single):.2f}]")


if __name__ == "__main__":
    main()
