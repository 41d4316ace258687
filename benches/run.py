"""Every measurement of BENCHMARKS.md's generated tables in one run of the current tree
against the peers, then the tables (`benches/run.sh`, which creates the Python environment
first, is the one command). Nothing older than the checkout is built: the before/after
tables of past changes were measured once and are kept as text (docs/benchmark-history.md).

Steps, each recorded in <target>/bench-results/run.json with its duration and the load
average at its start and end (`--skip` leaves out any but `build`; `--only` reruns some and
keeps the others' results of the last run, and the report says which ran separately):

  build         the timing harness (benches/harness) portable and with -C target-cpu=native,
                and the bench crate's programs (incremental);
  c             SymPy's C for every model in three variants (benches/baselines/c_peer.py),
                rebuilt only when a .mech file or the generator changed;
  rounds        interleaved rounds (benches/rounds.py): evaluation (ours portable and
                native, the C variants), augmented solve, and the seed's 10 s DOP853
                simulation against scipy's DOP853 (two variants);
  controllers   steps, rejections and errors of the PI and predictive step controllers
                (deterministic, untimed);
  profile       perf profile of the seed simulation (when perf is installed);
  criterion     the criterion bench `evaluation` (each generated function, the interpreter
                and AD routes) and the whole-simulation tables (benches/criterion/benches/simulation.rs);
  derivation    the criterion bench `derivation` (closed chain N = 4..64) and SymPy's
                derivation of the same chain (N = 4, 8, 16);
  mujoco        MuJoCo's four-bar (benches/baselines/mujoco_four_bar.py);
  robot         the Panda against Pinocchio (benches/robot.py) and the Panda's derivation time;
  a02           the IFToMM A02 chain for N = 10..80 (`--bin a02`);
  compile-time  the macro's added compile time (benches/compile-time/run.sh);
  casadi        our generated code against CasADi's C from Pinocchio's algorithms on five
                robots (benches/baselines/casadi/run.sh: its own environment, checks
                against Pinocchio 4.1, operation counts, interleaved rounds).

benches/report.py then rewrites the generated blocks of BENCHMARKS.md.
"""

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "baselines"))

import perf_profile  # noqa: E402
import robot  # noqa: E402
import rounds  # noqa: E402
from target_dir import CRITERION, RESULTS, ROOT, TARGET  # noqa: E402

MODELS = ["seed", "four_bar", "rssr", "chain8", "chain16", "chain32"]
MECH = {
    "seed": "mechanisms/spatial_crank_slider.mech",
    "four_bar": "mechanisms/planar_four_bar.mech",
    "rssr": "mechanisms/spatial_four_bar.mech",
    "chain8": "benches/mechanisms/closed_chain_8.mech",
    "chain16": "benches/mechanisms/closed_chain_16.mech",
    "chain32": "benches/mechanisms/closed_chain_32.mech",
}
STEPS = ["build", "c", "rounds", "controllers", "profile", "criterion", "derivation", "mujoco", "robot", "a02",
         "compile-time", "casadi"]
# Criterion's timing for the evaluation bench: each benchmark 0.2 s warm-up, 0.5 s measured
# (its 30 samples of nanosecond calls still count millions of calls).
CRITERION_ARGS = ["--warm-up-time", "0.2", "--measurement-time", "0.5"]
# SymPy's derivation of the closed chain: both routes at these N (LagrangesMethod takes
# minutes from N = 32 on).
SYMPY_CHAINS = ["4", "8", "16"]
HARNESS = os.path.join(TARGET, "release", "harness")
HARNESS_NATIVE = os.path.join(TARGET, "native", "release", "harness")


def log(msg):
    print(f"[{datetime.datetime.now().strftime('%H:%M:%S')} load {rounds.load_avg()}] {msg}", flush=True)


def cargo(args, env=None, capture=False):
    r = subprocess.run(["cargo"] + args, cwd=ROOT, check=True, env=env, capture_output=capture, text=True)
    return r.stdout


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


def commit():
    def git(*a):
        return subprocess.run(["git"] + list(a), cwd=ROOT, capture_output=True, text=True).stdout.strip()
    dirty = git("status", "--porcelain", "--untracked-files=no")
    return git("rev-parse", "HEAD") + (" (with uncommitted changes)" if dirty else "")


def step_build(run, a):
    cargo(["build", "--release", "-p", "mechanism-harness", "-p", "mechanism-bench", "--bin", "harness", "--bin", "a02",
           "--bin", "derive_time"])
    env = dict(os.environ, RUSTFLAGS=(os.environ.get("RUSTFLAGS", "") + " -C target-cpu=native").strip(),
               CARGO_TARGET_DIR=os.path.join(TARGET, "native"))
    cargo(["build", "--release", "-p", "mechanism-harness"], env=env)


def step_c(run, a):
    import c_peer
    run["c"] = {}
    for m in MODELS:
        info = c_peer.built(os.path.join(ROOT, MECH[m]), os.path.join(RESULTS, "c", m))
        run["c"][m] = info
        log(f"C {m}: " + ", ".join(f"{v} {i['ops']} ops" for v, i in info.items()))


def state_vector(state):
    """The C inputs x = [q, q', parameters, t] of a harness `state`."""
    return state["q"] + state["qd"] + state["parameters"] + [state["t"]]


def step_rounds(run, a):
    import baselines
    import c_peer
    states = {m: rounds.harness(HARNESS, "state", m) for m in MODELS}
    seed = baselines.read_mech(os.path.join(ROOT, MECH["seed"]))
    run["reference"] = rounds.harness(HARNESS, "reference", "seed")["q_end"]
    log("lambdifying the seed for scipy")
    problems = {"scipy strict": baselines.seed_rhs_strict(seed), "scipy defaults": baselines.seed_rhs_default(seed)}
    r = rounds.Rounds()
    stats = {}
    builds = {"portable": HARNESS, "native": HARNESS_NATIVE}
    for m in MODELS:
        for build, exe in builds.items():
            for what in ("evaluate", "five"):
                r.add(("eval", f"ours {build} {what}", m), rounds.eval_subject(exe, m, what))
        for v in c_peer.VARIANTS:
            x, exe = state_vector(states[m]), run["c"][m][v]["exe"]
            r.add(("eval", f"C {v}", m), lambda exe=exe, x=x, m=m: c_peer.run(exe, x, rounds.BATCHES, rounds.CALLS[m]))
        r.add(("solve", "ours portable", m), rounds.solve_subject(HARNESS, m))
    for build, exe in builds.items():
        stats[f"ours {build}"] = {}
        r.add(("simulate", f"ours {build}", "seed"), rounds.simulate_subject(exe, "seed", 1e-10, 3, stats[f"ours {build}"]))
    for name, problem in problems.items():
        stats[name] = {}
        r.add(("simulate", name, "seed"), rounds.scipy_subject(problem, 3, run["reference"], stats[name]))
    log(f"{len(r.subjects)} subjects, {a.rounds} rounds")
    r.run(a.rounds, log=log)
    run.update(states=states, rounds=r.summary(), round_loads=r.loads, simulation_stats=stats)


def step_controllers(run, a):
    controllers = {}
    for m in ("seed", "four_bar"):
        ref = rounds.harness(HARNESS, "reference", m)["q_end"]
        for tol in (1e-8, 1e-9, 1e-10, 1e-11):
            for ctl in ("pi", "predictive"):
                s = rounds.harness(HARNESS, "simulate", m, 0, tol, ctl)
                s["error"] = max(abs(x - y) for x, y in zip(s["q_end"], ref))
                controllers[f"{m}|{tol:g}|{ctl}"] = s
    run["controllers"] = controllers


def step_profile(run, a):
    if not perf_profile.perf_available():
        log("perf not found: no profile")
        return
    run["profile"] = dict(parts=perf_profile.profile(HARNESS), load=rounds.load_avg())


def step_criterion(run, a):
    cargo(["bench", "-p", "mechanism-criterion", "--bench", "evaluation", "--"] + CRITERION_ARGS)
    cargo(["bench", "-p", "mechanism-criterion", "--bench", "simulation"])


def step_derivation(run, a):
    cargo(["bench", "-p", "mechanism-criterion", "--bench", "derivation"])
    log(f"SymPy's derivation of the chain, N = {', '.join(SYMPY_CHAINS)}")
    subprocess.run([a.venv_python, os.path.join(HERE, "baselines", "baselines.py"), "--chains", *SYMPY_CHAINS,
                    "--lagranges", *SYMPY_CHAINS], check=True)


def step_mujoco(run, a):
    if subprocess.run([a.venv_python, "-c", "import mujoco"], capture_output=True).returncode != 0:
        run["mujoco_skipped"] = "mujoco is not importable"
        log("mujoco not importable: skipped")
        return
    subprocess.run([a.venv_python, os.path.join(HERE, "baselines", "mujoco_four_bar.py"), "--repeats", "3"],
                   check=True)


def step_robot(run, a):
    theirs, why = robot.pinocchio(a.venv_python)
    if theirs is None:
        run["robot_skipped"] = f"Pinocchio's program could not be built ({why})"
        log(run["robot_skipped"])
    else:
        run["robot"] = robot.measure(dict(robot.harness_programs(), pinocchio=theirs), a.robot_rounds)
        run["robot"]["rounds"] = a.robot_rounds
    derive = os.path.join(TARGET, "release", "derive_time")
    run["derive_time"] = {}
    for mech in ("mechanisms/panda.mech", "mechanisms/five_bar.mech"):
        out = subprocess.run([derive, mech, "5"], cwd=ROOT, check=True, capture_output=True, text=True).stdout
        run["derive_time"][mech] = float(out.split(":")[-1].split()[0])


def step_a02(run, a):
    md = subprocess.run([os.path.join(TARGET, "release", "a02"), "--repeats", "3"], cwd=ROOT, check=True,
                        capture_output=True, text=True).stdout
    with open(os.path.join(RESULTS, "a02.md"), "w") as f:
        f.write(md)


def step_compile_time(run, a):
    subprocess.run([os.path.join(HERE, "compile-time", "run.sh")], check=True)


def step_casadi(run, a):
    # Pinocchio 4.1 and example-robot-data: the interpreter that has them (the system's
    # python3 here; PYTHON overrides), not necessarily this environment.
    subprocess.run([os.path.join(HERE, "baselines", "casadi", "run.sh"), "--rounds", str(a.rounds)], check=True)


# What each step writes besides run.json (removed before the step runs, so that a result of
# an earlier run cannot pass for this one's).
OUTPUTS = {
    "criterion": ["simulation.md", "simulation.json", "../criterion/seed", "../criterion/four_bar",
                  "../criterion/rssr", "../criterion/chain8", "../criterion/chain16", "../criterion/chain32"],
    "derivation": ["baselines.json", "../criterion/derive_closed_chain"],
    "mujoco": ["mujoco.json"],
    "a02": ["a02.md"],
    "compile-time": ["compile_time.md"],
    "casadi": ["casadi.md", "casadi.json"],
}
# What each step adds to run.json.
KEYS = {
    "c": ["c"], "rounds": ["states", "reference", "rounds", "round_loads", "simulation_stats"],
    "controllers": ["controllers"], "profile": ["profile"], "mujoco": ["mujoco_skipped"],
    "robot": ["robot", "robot_skipped", "derive_time"],
}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=5, help="interleaved rounds (at least 3)")
    ap.add_argument("--robot-rounds", type=int, default=5, help="runs of each Panda program")
    ap.add_argument("--skip", nargs="*", default=[], choices=STEPS[1:], help="steps to leave out")
    ap.add_argument("--only", nargs="*", choices=STEPS[1:],
                    help="run these steps (and build) only, keeping the other steps' results of the last run")
    ap.add_argument("--venv-python", default=sys.executable)
    ap.add_argument("--report-only", action="store_true", help="only regenerate BENCHMARKS.md from run.json")
    a = ap.parse_args()
    if a.rounds < 3:
        ap.error("at least 3 rounds")
    chosen = [n for n in STEPS if n == "build" or (n not in a.skip and (a.only is None or n in a.only))]
    if "rounds" in chosen and "c" not in chosen:
        chosen.insert(chosen.index("rounds"), "c")  # the rounds time the C (cached: seconds)
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, "run.json")
    if not a.report_only:
        run = None
        if a.only is not None and os.path.exists(path):
            with open(path) as f:
                run = json.load(f)
        if run is None:
            run = dict(steps={}, invocations=[])
            for name in os.listdir(RESULTS):
                if name.endswith((".json", ".md")):
                    os.remove(os.path.join(RESULTS, name))
            subprocess.run(["rm", "-rf", CRITERION], check=True)
        started = time.time()
        run.update(started=run.get("started") or datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
                   commit=commit(), machine=machine(), load_start=run.get("load_start") or rounds.load_avg())
        run["skipped"] = [n for n in STEPS if n not in chosen and n not in run["steps"]]
        for name in chosen:
            for out in OUTPUTS.get(name, []):
                subprocess.run(["rm", "-rf", os.path.join(RESULTS, out)], check=True)
            for key in KEYS.get(name, []):
                run.pop(key, None)
            log(f"step {name}")
            t0, load0 = time.time(), rounds.load_avg()
            globals()["step_" + name.replace("-", "_")](run, a)
            run["steps"][name] = dict(seconds=time.time() - t0, load_start=load0, load_end=rounds.load_avg(),
                                      invocation=len(run["invocations"]) + 1)
            with open(path, "w") as f:
                json.dump(run, f, indent=1)
        run["load_end"] = rounds.load_avg()
        run["invocations"].append(dict(started=datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
                                       steps=chosen, seconds=time.time() - started, commit=run["commit"]))
        run["duration_s"] = sum(i["seconds"] for i in run["invocations"])
        with open(path, "w") as f:
            json.dump(run, f, indent=1)
        log(f"measurements done in {(time.time() - started) / 60:.1f} min")
    subprocess.run([sys.executable, os.path.join(HERE, "report.py"), "--write"], check=True)


if __name__ == "__main__":
    main()
