"""Every measurement of BENCHMARKS.md in one run, then the tables (`benches/run.sh`, which
creates the Python environment first, is the one command).

Steps, each recorded in target/bench-results/run.json with the load average:
 1. builds: the timing harness (benches/harness) portable and with -C target-cpu=native, and
    at the commits of benches/changes.toml (before/after tables);
 2. SymPy's C for every model in three variants (benches/baselines/c_peer.py), from the
    harness's assembled state;
 3. interleaved rounds (benches/rounds.py): evaluation (ours portable and native, the C
    variants, the revisions), augmented solve, and the seed's 10 s DOP853 simulation
    against scipy's DOP853 (two variants);
 4. perf profiles of the seed simulation at each change's `before` commit and now;
 5. the criterion benches (each generated function, interpreter and AD routes, derivation,
    the whole-simulation tables), SymPy's derivation times, MuJoCo, A02 and the macro's
    compile time;
 6. benches/report.py rewrites the generated blocks of BENCHMARKS.md.
"""

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import time
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
RESULTS = os.path.join(ROOT, "target", "bench-results")
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "baselines"))

import perf_profile  # noqa: E402
import revisions  # noqa: E402
import rounds  # noqa: E402

MODELS = ["seed", "four_bar", "rssr", "chain8", "chain16", "chain32"]
MECH = {
    "seed": "mechanisms/spatial_crank_slider.mech",
    "four_bar": "mechanisms/planar_four_bar.mech",
    "rssr": "mechanisms/spatial_four_bar.mech",
    "chain8": "benches/mechanisms/closed_chain_8.mech",
    "chain16": "benches/mechanisms/closed_chain_16.mech",
    "chain32": "benches/mechanisms/closed_chain_32.mech",
}
STEPS = ["criterion", "derivation", "mujoco", "a02", "compile-time"]


def log(msg):
    print(f"[{datetime.datetime.now().strftime('%H:%M:%S')} load {rounds.load_avg()}] {msg}", flush=True)


def cargo(args, env=None):
    subprocess.run(["cargo"] + args, cwd=ROOT, check=True, env=env)


def machine():
    def out(cmd):
        try:
            return subprocess.run(cmd, capture_output=True, text=True).stdout.strip().splitlines()[0]
        except (OSError, IndexError):
            return "?"
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    flags = next((l for l in open("/proc/cpuinfo") if l.startswith("flags")), "")
    return dict(cpu=cpu, nproc=out(["nproc"]), kernel=f"{platform.system()} {platform.release()}",
                rustc=out(["rustc", "-V"]), gcc=out(["gcc", "--version"]), python=platform.python_version(),
                avx512="avx512f" in flags, fma=" fma" in flags)


def builds(changes, log):
    """{"portable": exe, "native": exe, "revs": {sha: {"portable": exe, "native": exe}}}."""
    log("building the harness (portable, native)")
    cargo(["build", "--release", "-p", "mechanism-harness"])
    native_dir = os.path.join(ROOT, "target", "native")
    env = dict(os.environ, RUSTFLAGS=(os.environ.get("RUSTFLAGS", "") + " -C target-cpu=native").strip(),
               CARGO_TARGET_DIR=native_dir)
    cargo(["build", "--release", "-p", "mechanism-harness"], env=env)
    b = dict(portable=os.path.join(ROOT, "target", "release", "harness"),
             native=os.path.join(native_dir, "release", "harness"), revs={})
    for c in changes:
        for rev in (c["before"], c["after"]):
            full = revisions.sha(rev)
            entry = b["revs"].setdefault(full, {})
            if revisions.head_is(rev):
                entry.update(portable=b["portable"], native=b["native"])
                continue
            if "portable" not in entry:
                entry["portable"] = revisions.build(rev, log=log)
            if c.get("native") and "native" not in entry:
                entry["native"] = revisions.build(rev, native=True, log=log)
    return b


def peers_c(states, log):
    """{model: {variant: build info}} of SymPy's C, built from the .mech files."""
    import baselines
    import c_peer
    out = {}
    for m in MODELS:
        model = baselines.read_mech(os.path.join(ROOT, MECH[m]))
        out[m] = {}
        for v in c_peer.VARIANTS:
            t0 = time.perf_counter()
            info = c_peer.build(model, v, os.path.join(RESULTS, "c", m, v))
            info["build_s"] = time.perf_counter() - t0
            out[m][v] = info
            log(f"C {v} {m}: {info['ops']} ops, libm {info['libm']} ({info['build_s']:.1f} s)")
    return out


def state_vector(state):
    """The C inputs x = [q, q', parameters, t] of a harness `state`."""
    return state["q"] + state["qd"] + state["parameters"] + [state["t"]]


def measure(b, changes, rounds_n, log):
    """The interleaved rounds; returns the run.json entries."""
    import baselines
    import c_peer
    states = {m: rounds.harness(b["portable"], "state", m) for m in MODELS}
    c = peers_c(states, log)
    seed = baselines.read_mech(os.path.join(ROOT, MECH["seed"]))
    reference = rounds.harness(b["portable"], "reference", "seed")["q_end"]
    log("lambdifying the seed for scipy")
    problems = {"scipy strict": baselines.seed_rhs_strict(seed), "scipy defaults": baselines.seed_rhs_default(seed)}

    r = rounds.Rounds()
    rev_of = {}
    for ch in changes:
        for which in ("before", "after"):
            rev_of[revisions.sha(ch[which])] = ch[which]
    stats = {}
    for m in MODELS:
        for build in ("portable", "native"):
            for what in ("evaluate", "five"):
                r.add(("eval", f"ours {build} {what}", m), rounds.eval_subject(b[build], m, what))
        for v in c_peer.VARIANTS:
            x = state_vector(states[m])
            exe = c[m][v]["exe"]
            r.add(("eval", f"C {v}", m), lambda exe=exe, x=x, m=m: c_peer.run(exe, x, rounds.BATCHES, rounds.CALLS[m]))
        r.add(("solve", "ours portable", m), rounds.solve_subject(b["portable"], m))
    for build in ("portable", "native"):
        stats[f"ours {build}"] = {}
        r.add(("simulate", f"ours {build}", "seed"),
              rounds.simulate_subject(b[build], "seed", 1e-10, 3, stats[f"ours {build}"]))
    for name, problem in problems.items():
        stats[name] = {}
        r.add(("simulate", name, "seed"), rounds.scipy_subject(problem, 3, reference, stats[name]))
    for full, exes in b["revs"].items():
        label = f"rev {full[:12]}"
        for build, exe in exes.items():
            if exe in (b["portable"], b["native"]):
                continue  # the current tree, measured above
            measures = set().union(*[set(ch["measure"]) for ch in changes
                                     if revisions.sha(ch["before"]) == full or revisions.sha(ch["after"]) == full])
            if "eval" in measures:
                for m in MODELS:
                    r.add(("eval", f"{label} {build} evaluate", m), rounds.eval_subject(exe, m, "evaluate"))
            if "solve" in measures and build == "portable":
                for m in MODELS:
                    r.add(("solve", f"{label} portable", m), rounds.solve_subject(exe, m))
            if "simulate" in measures:
                stats[f"{label} {build}"] = {}
                r.add(("simulate", f"{label} {build}", "seed"),
                      rounds.simulate_subject(exe, "seed", 1e-10, 3, stats[f"{label} {build}"]))
    log(f"{len(r.subjects)} subjects, {rounds_n} rounds")
    r.run(rounds_n, log=log)
    log("step-size controllers: steps, rejections and errors (deterministic, untimed)")
    controllers = {}
    for m in ("seed", "four_bar"):
        ref = reference if m == "seed" else rounds.harness(b["portable"], "reference", m)["q_end"]
        for tol in (1e-8, 1e-9, 1e-10, 1e-11):
            for ctl in ("pi", "predictive"):
                s = rounds.harness(b["portable"], "simulate", m, 0, tol, ctl)
                s["error"] = max(abs(x - y) for x, y in zip(s["q_end"], ref))
                controllers[f"{m}|{tol:g}|{ctl}"] = s
    return dict(controllers=controllers, states=states, c={m: {v: {k: x for k, x in i.items() if k != "exe"} for v, i in c[m].items()} for m in c},
                rounds=r.summary(), round_loads=r.loads, simulation_stats=stats, reference=reference,
                revisions={full: {"rev": rev_of.get(full, full[:12]), "builds": sorted(e),
                                  "prefix": "ours" if e.get("portable") == b["portable"] else f"rev {full[:12]}"}
                           for full, e in b["revs"].items()})


def profiles(b, changes, log):
    """perf profiles of the seed simulation: now, and at every change's `before` commit."""
    out = {}
    if not perf_profile.perf_available():
        log("perf not found: no profiles")
        return out
    targets = {"now": b["portable"]}
    for ch in changes:
        exes = b["revs"].get(revisions.sha(ch["before"]), {})
        if "portable" in exes:
            targets[ch["before"]] = exes["portable"]
    for name, exe in targets.items():
        log(f"profile of the seed simulation at {name}")
        out[name] = dict(parts=perf_profile.profile(exe), load=rounds.load_avg())
    return out


def long_tail(skip, venv_python, log):
    """The criterion benches and the other peers; each step's load average."""
    loads = {}
    if "criterion" not in skip:
        for bench in ("evaluation", "simulation"):
            log(f"criterion bench {bench}")
            loads[bench] = rounds.load_avg()
            cargo(["bench", "-p", "mechanism-bench", "--bench", bench])
    if "derivation" not in skip:
        log("criterion bench derivation")
        loads["derivation"] = rounds.load_avg()
        cargo(["bench", "-p", "mechanism-bench", "--bench", "derivation"])
        log("SymPy derivation of the chain (LagrangesMethod at N = 32 takes minutes)")
        loads["sympy derivation"] = rounds.load_avg()
        subprocess.run([venv_python, os.path.join(HERE, "baselines", "baselines.py"), "--chains", "4", "8", "16", "32",
                        "--lagranges", "4", "8", "16", "32"], check=True)
    if "mujoco" not in skip:
        ok = subprocess.run([venv_python, "-c", "import mujoco"], capture_output=True).returncode == 0
        if ok:
            log("MuJoCo four-bar")
            loads["mujoco"] = rounds.load_avg()
            subprocess.run([venv_python, os.path.join(HERE, "baselines", "mujoco_four_bar.py")], check=True)
        else:
            log("mujoco not importable: skipped")
    if "a02" not in skip:
        log("A02 (N four-bar)")
        loads["a02"] = rounds.load_avg()
        md = subprocess.run(["cargo", "run", "--release", "-q", "-p", "mechanism-bench", "--bin", "a02"], cwd=ROOT,
                            check=True, capture_output=True, text=True).stdout
        with open(os.path.join(RESULTS, "a02.md"), "w") as f:
            f.write(md)
    if "compile-time" not in skip:
        log("the macro's compile time")
        loads["compile-time"] = rounds.load_avg()
        subprocess.run([os.path.join(HERE, "compile-time", "run.sh")], check=True)
    return loads


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=7, help="interleaved rounds (at least 5)")
    ap.add_argument("--skip", nargs="*", default=[], choices=STEPS, help="steps of item 5 to leave out")
    ap.add_argument("--venv-python", default=sys.executable)
    ap.add_argument("--report-only", action="store_true", help="only regenerate BENCHMARKS.md from run.json")
    ap.add_argument("--models", nargs="*", default=MODELS, choices=MODELS,
                    help="a subset, for a quick check (the tables then lack the others)")
    a = ap.parse_args()
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, "run.json")
    if not a.report_only:
        if a.rounds < 5:
            ap.error("at least 5 rounds")
        MODELS[:] = a.models
        started = time.time()
        with open(os.path.join(HERE, "changes.toml"), "rb") as f:
            changes = tomllib.load(f)["change"]
        run = dict(started=datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
                   commit=revisions.sha("HEAD"), machine=machine(), load_start=rounds.load_avg(), changes=changes)
        b = builds(changes, log)
        run.update(measure(b, changes, a.rounds, log))
        run["profiles"] = profiles(b, changes, log)
        with open(path, "w") as f:
            json.dump(run, f, indent=1)
        run["long_tail_loads"] = long_tail(set(a.skip), a.venv_python, log)
        run["skipped"] = a.skip
        run["load_end"] = rounds.load_avg()
        run["duration_s"] = time.time() - started
        with open(path, "w") as f:
            json.dump(run, f, indent=1)
        log(f"measurements done in {run['duration_s'] / 60:.1f} min")
    subprocess.run([sys.executable, os.path.join(HERE, "report.py"), "--write"], check=True)


if __name__ == "__main__":
    main()
