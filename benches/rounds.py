"""Interleaved rounds: every subject (our harness builds, SymPy's C, scipy) is timed once per
round, the rounds one after another, so that a slow minute of this shared machine hits all
subjects alike. A subject's value in a round is the median of its batches (or runs); the
report gives the median over the rounds and their spread (min-max). The load average is
recorded at the start of every round.
"""

import json
import statistics
import subprocess
import sys

# Calls per batch: about 10 ms of our evaluation per batch on this machine.
CALLS = {"seed": 200_000, "four_bar": 200_000, "rssr": 200_000, "chain8": 60_000, "chain16": 12_000, "chain32": 3_000}
SOLVE_CALLS = {"seed": 50_000, "four_bar": 50_000, "rssr": 50_000, "chain8": 15_000, "chain16": 3_000, "chain32": 1_000}
BATCHES = 5


def load_avg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def harness(exe, *args):
    """One harness call; its JSON output."""
    out = subprocess.run([exe] + [str(a) for a in args], check=True, capture_output=True, text=True).stdout
    return json.loads(out)


class Rounds:
    """Subjects keyed by (table, subject, model): callables returning one round's batch
    values; `run` times them all in every round."""

    def __init__(self):
        self.subjects = []  # (key, fn)
        self.values = {}  # key -> [round values]
        self.raw = {}  # key -> [[batch values]]
        self.loads = []

    def add(self, key, fn):
        self.subjects.append((key, fn))

    def run(self, rounds, log=print):
        for r in range(rounds):
            self.loads.append(load_avg())
            log(f"round {r + 1}/{rounds}, load {self.loads[-1]}")
            # Rotate the order each round, so no subject always follows the same one.
            k = r % max(1, len(self.subjects))
            for key, fn in self.subjects[k:] + self.subjects[:k]:
                batch = fn()
                self.raw.setdefault(key, []).append(batch)
                self.values.setdefault(key, []).append(statistics.median(batch))
        return self

    def summary(self):
        """{key as 'table|subject|model': {median, min, max, rounds}}."""
        out = {}
        for key, v in self.values.items():
            out["|".join(key)] = dict(median=statistics.median(v), min=min(v), max=max(v), rounds=v)
        return out


def eval_subject(exe, model, what):
    return lambda: harness(exe, "eval", model, what, BATCHES, CALLS[model])["ns"]


def solve_subject(exe, model):
    return lambda: harness(exe, "solve", model, BATCHES, SOLVE_CALLS[model])["ns"]


def simulate_subject(exe, model, tol, runs, sink):
    """Our simulation: `runs` timed runs after one untimed; stats kept in `sink`."""
    def f():
        r = harness(exe, "simulate", model, runs, tol)
        sink.update({k: r[k] for k in ("steps", "rejected", "rhs", "q_end", "max_phi")})
        return r["wall_s"]
    return f


def scipy_subject(problem, runs, reference, sink):
    """scipy's DOP853 on an already lambdified problem: one untimed solve, then `runs`."""
    sys.path.insert(0, __file__.rsplit("/", 1)[0] + "/baselines")
    from baselines import seed_solve

    def f():
        seed_solve(problem, 1e-10, reference)
        walls = []
        for _ in range(runs):
            r = seed_solve(problem, 1e-10, reference)
            walls.append(r["wall_s"])
        sink.update({k: r[k] for k in ("steps", "rhs", "error", "max_phi", "q_end")})
        return walls
    return f
