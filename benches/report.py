"""Collects the criterion medians (target/criterion/*/*/new/estimates.json), the whole-simulation
tables (target/bench-results/simulation.md/json) and the baselines (target/bench-results/
baselines.json) into the markdown tables of BENCHMARKS.md. Standard library only.

    python3 benches/report.py > target/bench-results/report.md
"""

import json
import os
import platform
import subprocess

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
CRIT = os.path.join(ROOT, "target", "criterion")
RES = os.path.join(ROOT, "target", "bench-results")
MODELS = ["seed", "four_bar", "rssr", "chain8", "chain16", "chain32"]
# The issue's SymPy-C all-five times (ns), used when the baseline script has not run.
ISSUE_C = {"seed": 192.0, "four_bar": 371.0, "chain8": 1400.0}


def median(group, bench):
    p = os.path.join(CRIT, group, bench, "new", "estimates.json")
    if not os.path.exists(p):
        return None
    return json.load(open(p))["median"]["point_estimate"]


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


def ratio(a, b):
    return "-" if a is None or b is None or b == 0 else f"{a / b:.1f}x"


def machine():
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    nproc = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
    load = open("/proc/loadavg").read().split()[:3]
    return f"{cpu}, {nproc} cores, {platform.system()} {platform.release()}; load average at report time {' '.join(load)}"


def main():
    base = json.load(open(os.path.join(RES, "baselines.json"))) if os.path.exists(os.path.join(RES, "baselines.json")) else {}
    cc = base.get("c_code", {})
    print(f"Machine: {machine()}\n")

    pr = base.get("c_code_per_routine", {})
    print("### Combined evaluation of M, C q', g, Phi, Phi_q (median per call)\n")
    print("SymPy-C two ways (see \"What is compared\"): *strict* = one C function after one joint `cse` of all five; "
          "*per routine* = `sympy.utilities.codegen`'s one CSE'd routine per matrix, called in turn. Ratios are ours / C "
          "(target <= 0.25); like for like: `evaluate` vs strict, 5 separate fns vs per routine.\n")
    print("| model | ours: `evaluate` (all 10 outputs) | ours: 5 separate fns | SymPy-C strict | evaluate / strict | SymPy-C per routine | evaluate / per routine | 5 fns / per routine | interpreter | autodiff (num-dual) | interp / ours | AD / ours |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for m in MODELS:
        ev = median(m, "evaluate_static")
        sep = median(m, "five_separate_static")
        c = cc.get(m, {}).get("ns")
        src = "" if c is not None else " (issue)"
        if c is None:
            c = ISSUE_C.get(m)
        r = pr.get(m, {}).get("ns")
        it, ad = median(m, "evaluate_interpreted"), median(m, "evaluate_autodiff")
        ours_dyn = median(m, "evaluate_compiled")
        q = lambda a, b: "-" if a is None or b is None else f"{a / b:.2f}"
        print(f"| {m} | {fmt(ev)} | {fmt(sep)} | {fmt(c)}{src if c else ''} | {q(ev, c)} | {fmt(r)} | {q(ev, r)} | {q(sep, r)} | {fmt(it)} | {fmt(ad)} | {ratio(it, ours_dyn)} | {ratio(ad, ours_dyn)} |")
    print("\n(interp / ours and AD / ours compare the three routes through the same run-time `System::evaluate` interface; ours there = "
          "`Compiled<T>` adapter, which adds the copies into the caller's `Evaluation`.)\n")

    print("### Each generated function (median per call)\n")
    fns = ["fn_mass_matrix", "fn_coriolis_forces", "fn_gravity", "fn_constraints", "fn_constraint_jacobian", "fn_constraint_gamma", "evaluate_static"]
    print("| model | " + " | ".join(f.replace("fn_", "") for f in fns) + " |")
    print("|---|" + "---|" * len(fns))
    for m in MODELS:
        print(f"| {m} | " + " | ".join(fmt(median(m, f)) for f in fns) + " |")

    print("\n### Augmented solve and one integrator step (median)\n")
    print("| model | solve: ours | interp | AD | rk4 step (h = 1e-3, projection): ours | interp | AD | dop853 step (1e-10): ours |")
    print("|---|---|---|---|---|---|---|---|")
    for m in MODELS:
        cells = [median(m, f"solve_{r}") for r in ("compiled", "interpreted", "autodiff")]
        cells += [median(m, f"step_rk4_{r}") for r in ("compiled", "interpreted", "autodiff")]
        cells.append(median(m, "step_dop853_compiled"))
        print(f"| {m} | " + " | ".join(fmt(x) for x in cells) + " |")

    print("\n### Derivation of the closed chain (median)\n")
    der = base.get("derivation", {})
    issue_lm = {4: 1.7, 8: 7.7, 16: 48, 32: 408}
    issue_direct = {4: 1.0, 8: 2.7, 16: 14.8, 32: 142}
    print("| N | model API + CSE | from source + CSE | macro path (all 12 bodies emitted) | SymPy LagrangesMethod (CPU) | SymPy direct (CPU) | LM / macro path | direct / macro path |")
    print("|---|---|---|---|---|---|---|---|")
    for n in [4, 8, 16, 32, 64]:
        g = "derive_closed_chain"
        a, b, mp = median(g, f"model/{n}"), median(g, f"from_source/{n}"), median(g, f"macro_path/{n}")
        d = der.get(str(n), {})
        # CPU time where recorded: SymPy is single-threaded, so on an idle machine it equals
        # the wall time, and it is not inflated when the machine is shared.
        lm = d.get("lagranges_cpu_s", d.get("lagranges_s"))
        lm_src = "" if lm is not None else (" (issue)" if n in issue_lm else "")
        lm = lm if lm is not None else issue_lm.get(n)
        di = d.get("direct_cpu_s", d.get("direct_s"))
        di_src = "" if di is not None else (" (issue)" if n in issue_direct else "")
        di = di if di is not None else issue_direct.get(n)
        print(f"| {n} | {fmt(a)} | {fmt(b)} | {fmt(mp)} | {fmt(lm * 1e9) if lm else '-'}{lm_src} | {fmt(di * 1e9) if di else '-'}{di_src} | "
              f"{ratio(lm * 1e9 if lm else None, mp)} | {ratio(di * 1e9 if di else None, mp)} |")

    sim = os.path.join(RES, "simulation.md")
    if os.path.exists(sim):
        print("\n## Whole simulations\n")
        print(open(sim).read())
    scipy = base.get("scipy", {})
    simj = json.load(open(os.path.join(RES, "simulation.json"))) if os.path.exists(os.path.join(RES, "simulation.json")) else {}
    ours = median("simulate_10s", "seed_dop853_1e-10")
    if ours is not None:
        ours_err = simj.get("seed dop853, rtol = atol = 1e-10", {}).get("error")
        print("\n### Seed, 10 s, DOP853 at rtol = atol = 1e-10: ours against scipy\n")
        print("| run | wall | ours faster by (target 1000x) | steps | RHS evals | us per RHS | error at 10 s | max abs(Phi) |")
        print("|---|---|---|---|---|---|---|---|")
        print(f"| ours (criterion median) | {fmt(ours)} | - | - | - | - | {ours_err:.1e} | - |")
        for key, label in (("seed_dop853_1e-10", "scipy, lambdify(cse=True), preallocated KKT"),
                           ("seed_dop853_1e-10_lambdify_default", "scipy, lambdify defaults, np.block per call")):
            sc = scipy.get(key)
            if sc:
                err = f"{sc['error']:.1e}" if sc.get("error") is not None else "-"
                print(f"| {label} | {sc['wall_s']:.3f} s | {sc['wall_s'] * 1e9 / ours:.0f}x | {sc['steps']} | {sc['rhs']} | "
                      f"{sc.get('us_per_rhs', sc['wall_s'] * 1e6 / sc['rhs']):.1f} | {err} | {sc['max_phi']:.1e} |")
        print(f"| scipy (issue) | 1.55 s | {1.55e9 / ours:.0f}x | - | - | - | - | - |")
    for k in ("four_bar_dop853_1e-9", "four_bar_dop853_1e-8"):
        t = median("simulate_10s", k)
        if t is not None:
            print(f"\nFour-bar 10 s, {k} (criterion; a looser tolerance than the 1e-7 rad table above needs): "
                  f"{fmt(t)} = {10 / (t * 1e-9):.0f} simulated s per wall s.")

    mj_path = os.path.join(RES, "mujoco.json")
    if os.path.exists(mj_path):
        mj = json.load(open(mj_path))
        print(f"\n### Four-bar, 10 s: MuJoCo {mj.get('mujoco_version', '?')} against ours\n")
        print("| run | simulated s per wall s | crank angle error at 10 s (rad) | max loop violation (m) |")
        print("|---|---|---|---|")
        for name, r in mj.get("runs", {}).items():
            st = r.get("settings", {})
            desc = ", ".join(f"{k} {v}" for k, v in st.items() if k in ("integrator", "timestep", "solref"))
            print(f"| MuJoCo {name} ({desc or 'defaults'}) | {r['sim_per_wall']:.0f} (rollout: {r.get('sim_per_wall_rollout', float('nan')):.0f}) | "
                  f"{r['th1_error_rad']:.1e} | {r['max_loop_violation_m']:.1e} |")
        fb = simj.get("four_bar dop853")
        if fb:
            print(f"| ours, DOP853 at {fb['tol']:g} (projection; simulation.json) | {fb['sim_per_wall']:.0f} | {fb['error']:.1e} | "
                  f"{simj.get('phi four-bar projection', {}).get('max_phi', float('nan')):.1e} (max abs(Phi)) |")

if __name__ == "__main__":
    main()
