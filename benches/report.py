"""The generated tables of BENCHMARKS.md from one run of `benches/run.sh`, read from cargo's
target directory (CARGO_TARGET_DIR when set): bench-results/run.json (the interleaved
rounds, the profile, the controller study, the Panda, each step's duration), the criterion
estimates (criterion/), simulation.md/json, baselines.json (SymPy derivation), mujoco.json,
a02.md, compile_time.md and casadi.md. Standard library only.

    python3 benches/report.py           # print every generated block
    python3 benches/report.py --write   # rewrite the blocks of BENCHMARKS.md in place

A block is the text between `<!-- generated: NAME -->` and `<!-- end: NAME -->`; nothing
else in the file is touched (the frozen sections, measured once, carry no such markers),
and no other file is written. A block whose source is missing says so instead of keeping
old numbers.
"""

import json
import os
import re
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import robot  # noqa: E402
from target_dir import CRITERION as CRIT  # noqa: E402
from target_dir import RESULTS as RES  # noqa: E402
from target_dir import ROOT  # noqa: E402
MODELS = ["seed", "four_bar", "rssr", "chain8", "chain16", "chain32"]
# Targets of issue 17 (evaluation against SymPy's strict C) and issue 6 (seed simulation).
TARGET_PORTABLE, TARGET_NATIVE, TARGET_SCIPY = 0.7, 0.5, 100.0


def load(name):
    p = os.path.join(RES, name)
    if not os.path.exists(p):
        return None
    with open(p) as f:
        return json.load(f) if name.endswith(".json") else f.read()


def crit(group, bench):
    p = os.path.join(CRIT, group, bench, "new", "estimates.json")
    if not os.path.exists(p):
        return None
    with open(p) as f:
        return json.load(f)["median"]["point_estimate"]


def fmt(ns):
    if ns is None:
        return "-"
    if ns < 1e3:
        return f"{ns:.1f} ns"
    if ns < 1e6:
        return f"{ns / 1e3:.2f} us"
    if ns < 1e9:
        return f"{ns / 1e6:.2f} ms"
    return f"{ns / 1e9:.2f} s"


def spread(s, scale=1.0, unit=fmt):
    """`median [min-max]` of a round summary."""
    if not s:
        return "-"
    return f"{unit(s['median'] * scale)} [{unit(s['min'] * scale)}-{unit(s['max'] * scale)}]"


def ratio(a, b):
    """Per-round ratios a_r / b_r of two subjects timed in the same rounds:
    {median, min, max}."""
    if not a or not b:
        return None
    r = [x / y for x, y in zip(a["rounds"], b["rounds"])]
    return dict(median=statistics.median(r), min=min(r), max=max(r))


def fr(r, digits=2):
    if r is None:
        return "-"
    return f"{r['median']:.{digits}f} [{r['min']:.{digits}f}-{r['max']:.{digits}f}]"


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(out)


class Run:
    def __init__(self, run):
        self.run = run
        self.r = run.get("rounds", {})

    def get(self, table_, subject, model):
        return self.r.get(f"{table_}|{subject}|{model}")

    def block_run(self):
        run = self.run
        m = run["machine"]
        loads = ", ".join(run.get("round_loads", []))
        dur = run.get("duration_s")
        steps = run.get("steps", {})
        rows = [[name, f"{st['seconds']:.0f}", st["load_start"], st["load_end"], st.get("invocation", 1)]
                for name, st in steps.items()]
        calls = run.get("invocations", [])
        separate = (f" The steps ran in {len(calls)} invocations of `benches/run.py` (`--only`): "
                    + "; ".join(f"{k + 1}. {', '.join(c['steps'])}, ended {c['started']}"
                                + (f" at {c['commit']}" if c.get("commit") else "") for k, c in enumerate(calls))
                    + "; the duration is their sum." if len(calls) > 1 else "")
        skipped = [f"{k}: {run[k + '_skipped']}" for k in ("mujoco", "robot") if run.get(k + "_skipped")]
        return "\n\n".join([
            "\n".join([
                f"One run of `benches/run.sh` started {run['started']} at commit {run['commit']}"
                + (f", {dur / 60:.1f} minutes in all" if dur else "") + "." + separate,
                f"Machine: {m['cpu']}, {m['nproc']} cores ({'AVX-512, ' if m['avx512'] else ''}"
                f"{'FMA' if m['fma'] else 'no FMA'}), {m['kernel']}; {m['rustc']}; {m['gcc']}; Python {m['python']}. "
                "Our portable build is rustc's default x86-64 target (SSE2, no FMA); native = `-C target-cpu=native`; "
                "SymPy's C is always gcc -O3 -march=native.",
                f"Load average (1, 5, 15 min) at the start {run['load_start']}, at the start of each round: "
                f"{loads or '-'}; at the end {run.get('load_end', '-')}. The machine is shared with other jobs: "
                "read the spreads.",
                "Skipped steps: " + (", ".join(run.get("skipped", [])) or "none") + "."
                + ("" if not skipped else " Left out inside a step: " + "; ".join(skipped) + "."),
            ]),
            "Each step's wall time (s) and the load average at its start and end:",
            table(["step", "wall (s)", "load at start", "load at end", "invocation"], rows),
        ])

    def block_evaluation(self):
        rows, five = [], []
        met_p = met_n = 0
        for m in MODELS:
            ours_p, ours_n = self.get("eval", "ours portable evaluate", m), self.get("eval", "ours native evaluate", m)
            st, st10, pr = (self.get("eval", f"C {v}", m) for v in ("strict", "strict10", "per_routine"))
            rp, rn = ratio(ours_p, st), ratio(ours_n, st)
            met_p += bool(rp and rp["median"] <= TARGET_PORTABLE)
            met_n += bool(rn and rn["median"] <= TARGET_NATIVE)
            rows.append([m, spread(ours_p), spread(ours_n), spread(st), spread(st10), spread(pr), fr(rp), fr(rn),
                         fr(ratio(ours_p, st10)), fr(ratio(ours_n, st10)), fr(ratio(ours_p, pr)), fr(ratio(ours_n, pr))])
            f_p, f_n = self.get("eval", "ours portable five", m), self.get("eval", "ours native five", m)
            five.append([m, spread(f_p), spread(f_n), spread(pr), fr(ratio(f_p, pr)), fr(ratio(f_n, pr))])
        c = self.run.get("c", {})
        ops = table(["model", "C strict: ops, libm calls", "C strict10", "C per routine"],
                    [[m] + [f"{c[m][v]['ops']}, {c[m][v]['libm']}" for v in ("strict", "strict10", "per_routine")]
                     for m in MODELS if m in c])
        return "\n\n".join([
            "ns per call, median [min-max] over the rounds; ratios are ours / C per round, median [min-max]. "
            "`evaluate_into` computes all ten outputs (M, C q', g, tau, Phi, Phi_q, Phi_t, gamma, T, Pi); *strict* C "
            "computes five (M, C q', g, Phi, Phi_q), *strict10* the same ten as ours.",
            table(["model", "ours, portable", "ours, native", "C strict (5)", "C strict10", "C per routine (5)",
                   "/ strict, portable", "/ strict, native", "/ strict10, portable", "/ strict10, native",
                   "/ per routine, portable", "/ per routine, native"], rows),
            f"Targets (issue 17): ours / strict C <= {TARGET_PORTABLE} with the portable build: met on {met_p} of 6 models; "
            f"<= {TARGET_NATIVE} native: met on {met_n} of 6.",
            "The five functions `mass_matrix`, `coriolis_forces`, `gravity`, `constraints`, `constraint_jacobian`, "
            "each called through a pointer (nothing shared between them), against SymPy's per-routine C:",
            table(["model", "ours, portable", "ours, native", "C per routine", "/ per routine, portable",
                   "/ per routine, native"], five),
            "Operation counts and libm calls of the C:",
            ops,
        ])

    def block_solve(self):
        rows = []
        for m in MODELS:
            s = self.get("solve", "ours portable", m)
            e = self.get("eval", "ours portable evaluate", m)
            rows.append([m, spread(s), spread(e), fr(ratio(s, e), 1)])
        return "\n\n".join([
            "`Dynamics::solve` through `Compiled` (evaluation, copy into the run-time buffers, checks, the augmented "
            "solve), ns per call, median [min-max] over the rounds:",
            table(["model", "solve", "evaluate_into alone", "solve / evaluate_into"], rows),
        ])

    def block_simulation(self):
        ref = self.run.get("reference")
        st = self.run.get("simulation_stats", {})
        ours = self.get("simulate", "ours portable", "seed")
        rows = []
        for name in ("ours portable", "ours native", "scipy strict", "scipy defaults"):
            s, x = self.get("simulate", name, "seed"), st.get(name, {})
            if not s:
                continue
            err = x.get("error")
            if err is None and ref and x.get("q_end"):
                err = max(abs(a - b) for a, b in zip(x["q_end"], ref))
            rhs = x.get("rhs")
            rows.append([name, spread(s, 1e9), x.get("steps", "-"), x.get("rejected", "-"), rhs or "-",
                         f"{s['median'] / rhs * 1e9:.0f} ns" if rhs else "-",
                         f"{err:.1e}" if err is not None else "-", f"{x['max_phi']:.1e}" if "max_phi" in x else "-",
                         fr(ratio(s, ours), 0) if name.startswith("scipy") else "-"])
        scipy = ratio(self.get("simulate", "scipy strict", "seed"), ours)
        met = scipy and scipy["median"] >= TARGET_SCIPY
        e = self.get("eval", "ours portable evaluate", "seed")
        s = self.get("solve", "ours portable", "seed")
        rhs = st.get("ours portable", {}).get("rhs")
        per_rhs = ours["median"] * 1e9 / rhs if ours and rhs else None
        lines = [
            "Seed crank-slider, 10 s, DOP853 at rtol = atol = 1e-10, projection, 10 samples per second. Wall time per "
            "run, median [min-max] over the rounds (each round: one untimed run, the median of three timed runs); "
            "error = max |q(10 s) - q_ref(10 s)| with q_ref from our DOP853 at 1e-13; scipy's step count excludes "
            "rejected steps (solve_ivp does not report them).",
            table(["run", "wall", "steps", "rejected", "RHS", "wall / RHS", "error at 10 s", "max abs(Phi)",
                   "scipy / ours (per round)"], rows),
            f"Target (issue 17): scipy strict / ours >= {TARGET_SCIPY:.0f}: "
            + (f"{scipy['median']:.0f} (range {scipy['min']:.0f}-{scipy['max']:.0f}), {'met' if met else 'missed'}." if scipy else "-"),
        ]
        if per_rhs and e:
            lines.append(f"Per right-hand side: {per_rhs:.0f} ns of wall time per RHS against {e['median']:.1f} ns "
                         f"for one `evaluate_into` ({per_rhs / e['median']:.1f}x) and {fmt(s['median']) if s else '-'} "
                         "for one `Dynamics::solve` (evaluation + augmented solve); the rest is the integrator, the "
                         "projection after every step and the output.")
        return "\n\n".join(lines)

    def block_profile(self):
        prof = self.run.get("profile")
        if not prof or not prof.get("parts"):
            return "No profile in this run (perf not installed, or the step skipped)."
        return ("Profile of the seed simulation (40 runs of 10 s, DOP853 at 1e-10; `perf`, self time, load "
                f"{prof['load']}): " + "; ".join(f"{p} {v:.0f} %" for p, v in prof["parts"] if v >= 1.0) + ".")

    def block_robot(self):
        out = []
        r = self.run.get("robot")
        if r:
            out.append(f"Median over {r['rounds']} runs of each program (rounds interleaved):")
            out.append(robot.table(r))
            out.append(robot.targets(r))
        else:
            out.append(self.run.get("robot_skipped", "The Panda step was skipped in this run."))
        d = self.run.get("derive_time")
        if d:
            out.append("Everything `mechanism!` does at build time (`derive_time FILE 5`, median of 5): "
                       + "; ".join(f"`{k}` {v:.3f} s" for k, v in d.items()) + ".")
        return "\n\n".join(out)

    def block_controllers(self):
        c = self.run.get("controllers")
        if not c:
            return "Not measured in this run."
        rows = []
        for m in ("seed", "four_bar"):
            for tol in ("1e-08", "1e-09", "1e-10", "1e-11"):
                pi, pr = c.get(f"{m}|{tol}|pi"), c.get(f"{m}|{tol}|predictive")
                if not pi or not pr:
                    continue
                rows.append([m, tol, pi["steps"], pi["rejected"], pi["rhs"], f"{pi['error']:.2e}", pr["steps"],
                             pr["rejected"], pr["rhs"], f"{pr['error']:.2e}", f"{pr['rhs'] / pi['rhs']:.2f}",
                             f"{pr['error'] / pi['error']:.2f}"])
        return table(["model", "rtol = atol", "PI: steps", "rejected", "RHS", "error at 10 s", "predictive: steps",
                      "rejected", "RHS", "error at 10 s", "RHS ratio", "error ratio"], rows)


def block_criterion():
    """Each generated function, and the three routes (compiled, interpreter, AD) through the
    run-time interface: criterion medians."""
    fns = ["fn_mass_matrix", "fn_coriolis_forces", "fn_gravity", "fn_constraints", "fn_constraint_jacobian",
           "fn_constraint_gamma", "evaluate_static"]
    if crit("seed", "evaluate_static") is None:
        return "Criterion was skipped in this run."
    t1 = table(["model"] + [f.replace("fn_", "") for f in fns], [[m] + [fmt(crit(m, f)) for f in fns] for m in MODELS])
    rows = []
    for m in MODELS:
        cells = [crit(m, f"evaluate_{r}") for r in ("compiled", "interpreted", "autodiff")]
        cells += [crit(m, f"solve_{r}") for r in ("compiled", "interpreted", "autodiff")]
        cells += [crit(m, f"step_rk4_{r}") for r in ("compiled", "interpreted", "autodiff")]
        cells.append(crit(m, "step_dop853_compiled"))
        rows.append([m] + [fmt(x) for x in cells])
    t2 = table(["model", "evaluate: compiled", "interpreter", "AD", "solve: compiled", "interpreter", "AD",
                "rk4 step: compiled", "interpreter", "AD", "dop853 step: compiled"], rows)
    return "\n\n".join(["Each generated method (criterion median; `evaluate_static` returns the struct by value):", t1,
                        "The three routes through the run-time `System` interface (criterion medians; one integrator "
                        "step with projection, restarted when the 10 000 s run ends):", t2])


def block_derivation():
    base = load("baselines.json") or {}
    der = base.get("derivation", {})
    if crit("derive_closed_chain", "macro_path/4") is None:
        return "The derivation benchmark was skipped in this run."
    rows = []
    for n in [4, 8, 16, 32, 64]:
        g = "derive_closed_chain"
        a, b, mp = crit(g, f"model/{n}"), crit(g, f"from_source/{n}"), crit(g, f"macro_path/{n}")
        d = der.get(str(n), {})
        lm, di = d.get("lagranges_cpu_s"), d.get("direct_cpu_s")
        rows.append([n, fmt(a), fmt(b), fmt(mp), fmt(lm * 1e9) if lm else "-", fmt(di * 1e9) if di else "-",
                     f"{lm * 1e9 / mp:.0f}x" if lm and mp else "-", f"{di * 1e9 / mp:.0f}x" if di and mp else "-",
                     d.get("lagranges_load") or d.get("direct_load") or "-"])
    return table(["N", "model API + CSE", "from source + CSE", "macro path (every body and the cache emitted)",
                  "SymPy LagrangesMethod (CPU)", "SymPy direct (CPU)", "LM / macro path", "direct / macro path",
                  "load during SymPy"], rows)


def block_mujoco():
    mj = load("mujoco.json")
    if not mj:
        return "MuJoCo was skipped or not installable in this run."
    simj = load("simulation.json") or {}
    rows = []
    for name, r in mj.get("runs", {}).items():
        st = r.get("settings", {})
        desc = ", ".join(f"{k} {v}" for k, v in st.items() if k in ("integrator", "timestep", "solref"))
        rows.append([f"MuJoCo {name} ({desc or 'defaults'})", f"{r['sim_per_wall']:.0f}", f"{r['th1_error_rad']:.1e}",
                     f"{r['max_loop_violation_m']:.1e}"])
    fb = simj.get("four_bar dop853")
    if fb:
        rows.append([f"ours, DOP853 at {fb['tol']:g}", f"{fb['sim_per_wall']:.0f}", f"{fb['error']:.1e}",
                     f"{simj.get('phi four-bar projection', {}).get('max_phi', float('nan')):.1e} (max abs(Phi))"])
    return f"MuJoCo {mj.get('mujoco_version', '?')}.\n\n" + table(
        ["run", "simulated s per wall s", "crank angle error at 10 s (rad)", "max loop violation (m)"], rows)


def block_file(name, missing):
    text = load(name)
    return text.strip() if text else missing


def blocks():
    run = load("run.json")
    out = {}
    if run:
        r = Run(run)
        out.update({"run": r.block_run(), "evaluation": r.block_evaluation(), "solve": r.block_solve(),
                    "simulation": r.block_simulation(), "profile": r.block_profile(),
                    "controllers": r.block_controllers(), "robot": r.block_robot()})
    else:
        for k in ("run", "evaluation", "solve", "simulation", "profile", "controllers", "robot"):
            out[k] = "No run.json: run `benches/run.sh`."
    skipped = set(run.get("skipped", [])) if run else set()
    out["criterion"] = block_criterion()
    out["derivation"] = block_derivation()
    out["whole-simulations"] = block_file("simulation.md", "The simulation benchmark was skipped in this run.")
    out["mujoco"] = block_mujoco()
    out["a02"] = block_file("a02.md", "A02 was skipped in this run.")
    out["compile-time"] = block_file("compile_time.md", "The compile-time measurement was skipped in this run.")
    out["casadi"] = block_file("casadi.md", "The CasADi baseline was skipped in this run.")
    for step, blocks_of_step in (("criterion", ["criterion", "whole-simulations"]), ("derivation", ["derivation"]),
                                 ("mujoco", ["mujoco"]), ("a02", ["a02"]), ("compile-time", ["compile-time"]),
                                 ("casadi", ["casadi"])):
        if step in skipped:
            for b in blocks_of_step:
                out[b] = f"The `{step}` step was skipped in this run."
    return out


def main():
    b = blocks()
    if "--write" not in sys.argv:
        for k, v in b.items():
            print(f"<!-- generated: {k} -->\n{v}\n<!-- end: {k} -->\n")
        return
    path = os.path.join(ROOT, "BENCHMARKS.md")
    with open(path) as f:
        text = f.read()
    for k, v in b.items():
        pat = re.compile(rf"(<!-- generated: {re.escape(k)} -->\n).*?(<!-- end: {re.escape(k)} -->)", re.S)
        if not pat.search(text):
            print(f"report.py: BENCHMARKS.md has no block {k!r}", file=sys.stderr)
            continue
        text = pat.sub(lambda mm: mm.group(1) + v + "\n" + mm.group(2), text)
    with open(path, "w") as f:
        f.write(text)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
