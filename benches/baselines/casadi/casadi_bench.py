#!/usr/bin/env python3
"""Our generated code against CasADi's code from Pinocchio's algorithms (issue 50), on the
Panda, UR5 (as imported and with its angles snapped), the KUKA iiwa, Solo12 (its base
fixed) and Talos (30 coordinates, the grippers locked). `benches/baselines/casadi/run.sh`
sets up the environments and runs this; alone:

    python3 casadi_bench.py --casadi-python VENV/bin/python [--pin-python python3]
                            [--rounds 5] [--robots panda ur5 ...] [--states 64]

Steps, each rerun from scratch (so that the numbers are those of the checked-out tree):
  1. Pinocchio 4.1 (`pinocchio_reference.py`, in --pin-python): random states and the
     reference M, C q' + g, tau and q'' at each;
  2. CasADi (`casadi_codegen.py`, in --casadi-python with its Pinocchio 2.6): C from
     `CasadiKinDyn(urdf).crba()`, `.rnea()`, `.aba()` (and C q' + g as rnea with q'' = 0,
     M with it in one function), each with `cse: True`, compiled with `gcc -O3
     -march=native` (native) and `gcc -O3` (portable) around casadi_main.c;
  3. ours: a crate of the robots' `mechanism!(urdf = ..)` around ours.rs, built with
     `cargo build --release` (portable) and with `-C target-cpu=native` (native);
  4. both sides checked against Pinocchio at every state: the largest error relative to
     the reference's largest entry (at least 1), in the table, and logged where it exceeds
     1e-12 (M, C q' + g, tau; q'': 1e-12 cond(M), a solve's bound). Our import writes
     angles within 1e-12 rad of pi as `pi` (2e-13 rad from `3.14159265359`), and the
     snapped variants move angles by up to 1e-9 rad: their frames differ from the URDF's by
     that much, and so do their values (the header of each import states by how much);
  5. operation counts: CasADi's SX instructions other than inputs, outputs and constants;
     ours, the arithmetic of each routine's program (mechanism_codegen's op_counts);
  6. interleaved rounds (benches/rounds.py): every (robot, side, build, routine) timed once
     per round, thread CPU per call, the median of 5 batches; the table gives the median
     over the rounds.
Writes <target>/bench-results/casadi.json and casadi.md (BENCHMARKS.md's `casadi` block).
The KUKA iiwa: the URDF at $IIWA_URDF, else `kuka_iiwa/model.urdf` of the `pybullet`
wheel's pybullet_data (the lbr_iiwa description, BSD-2), fetched once with `pip download`.
"""

import argparse
import glob
import json
import math
import os
import struct
import subprocess
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", ".."))
import rounds  # noqa: E402
from target_dir import RESULTS, ROOT, TARGET  # noqa: E402

WORK = os.path.join(TARGET, "casadi")
GRIPPERS = [f"gripper_{side}_{j}" for side in ("left", "right") for j in (
    "joint", "inner_double_joint", "fingertip_1_joint", "fingertip_2_joint", "motor_single_joint",
    "inner_single_joint", "fingertip_3_joint")]
# (our routine, CasADi's function, the output compared, label)
ROUTINES = [
    ("mass_matrix", "crba", "mass", "M"),
    ("bias", "bias", "bias", "C q' + g (bias)"),
    ("cqg_id", "bias", "bias", "C q' + g (inverse_dynamics, q'' = 0)"),
    ("mass_and_bias", "mass_bias", "mass_bias", "M and C q' + g (mass_and_bias)"),
    ("inverse_dynamics", "rnea", "tau", "inverse dynamics"),
    ("forward_dynamics", "aba", "qdd", "forward dynamics"),
]
# Our routines' programs (ours counts), and CasADi's functions, whose operations each row counts.
OUR_OPS = {"mass_matrix": ["mass_matrix"], "bias": ["bias"],
           "cqg_id": ["inverse_dynamics"], "mass_and_bias": ["mass_and_bias"],
           "inverse_dynamics": ["inverse_dynamics"], "forward_dynamics": ["forward_dynamics"]}
# Pinocchio 4.1's C++ (pinocchio_main.cpp), timed native only: its routines are named as
# CasADi's functions.
PINOCCHIO_FLAGS = [
    "-O3", "-march=native", "-DNDEBUG", "-std=c++17", "-DEIGEN_MAX_ALIGN_BYTES=16",
    "-DEIGEN_MALLOC_ALREADY_ALIGNED=1", "-DBOOST_MPL_LIMIT_LIST_SIZE=30", "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30",
    "-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS", "-DBOOST_FUSION_INVOKE_MAX_ARITY=12", "-DPINOCCHIO_WITH_URDFDOM",
    "-DPINOCCHIO_URDFDOM_HEADERS_MAJOR_VERSION=3", "-DPINOCCHIO_URDFDOM_HEADERS_MINOR_VERSION=0",
    "-DPINOCCHIO_URDFDOM_HEADERS_PATCH_VERSION=0", "-Wno-stringop-overread"]
BATCHES = 5


def log(msg):
    print(f"[casadi load {rounds.load_avg()}] {msg}", flush=True)


def sh(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, **kw).stdout


def robots_dir(pin_python):
    code = ('import cmeel, os; print(os.path.join(cmeel.__path__[0], "..", "cmeel.prefix", "share", '
            '"example-robot-data", "robots"))')
    return os.path.abspath(sh([pin_python, "-c", code]).strip())


def iiwa_urdf(casadi_python):
    """Drake's or any iiwa URDF at $IIWA_URDF, else pybullet_data's kuka_iiwa/model.urdf."""
    if os.environ.get("IIWA_URDF"):
        return os.path.abspath(os.environ["IIWA_URDF"]), os.environ["IIWA_URDF"]
    out = os.path.join(WORK, "downloads", "kuka_iiwa_model.urdf")
    if not os.path.exists(out):
        d = os.path.join(WORK, "downloads")
        os.makedirs(d, exist_ok=True)
        sh([casadi_python, "-m", "pip", "download", "-q", "--no-deps", "--only-binary", ":all:", "-d", d,
            "pybullet"])
        wheel = sorted(glob.glob(os.path.join(d, "pybullet-*.whl")))[-1]
        with zipfile.ZipFile(wheel) as z, open(out, "wb") as f:
            f.write(z.read("pybullet_data/kuka_iiwa/model.urdf"))
    return out, "pybullet_data/kuka_iiwa/model.urdf (pybullet wheel)"


def robots(a):
    erd = robots_dir(a.pin_python)
    iiwa, iiwa_source = iiwa_urdf(a.casadi_python)
    all_robots = {
        "panda": dict(urdf=os.path.join(ROOT, "mechanisms", "urdf", "panda.urdf"),
                      lock=["panda_finger_joint1", "panda_finger_joint2"], snap=None,
                      source="mechanisms/urdf/panda.urdf"),
        "ur5": dict(urdf=os.path.join(ROOT, "mechanisms", "urdf", "ur5_robot.urdf"), lock=[], snap=None,
                    source="mechanisms/urdf/ur5_robot.urdf"),
        "ur5_snapped": dict(urdf=os.path.join(ROOT, "mechanisms", "urdf", "ur5_robot.urdf"), lock=[], snap=1e-9,
                            source="mechanisms/urdf/ur5_robot.urdf, snap_angles = 1e-9"),
        "iiwa": dict(urdf=iiwa, lock=[], snap=None, source=iiwa_source),
        "iiwa_snapped": dict(urdf=iiwa, lock=[], snap=1e-9, source=iiwa_source + ", snap_angles = 1e-9"),
        "solo12": dict(urdf=os.path.join(erd, "solo_description", "robots", "solo12.urdf"), lock=[], snap=None,
                       source="example-robot-data solo_description/robots/solo12.urdf, base fixed"),
        "talos30": dict(urdf=os.path.join(erd, "talos_data", "robots", "talos_full_v2.urdf"), lock=GRIPPERS,
                        snap=None, source="example-robot-data talos_data/robots/talos_full_v2.urdf, grippers locked"),
    }
    return {k: all_robots[k] for k in a.robots}


def write_states(path, states, order, names):
    """The states in `order` (coordinate names) from Pinocchio's `names`, as doubles."""
    idx = [names.index(j) for j in order]
    with open(path, "wb") as f:
        for s in states:
            row = []
            for key in ("q", "v", "a", "tau"):
                row += [s[key][i] for i in idx]
            f.write(struct.pack(f"{len(row)}d", *row))


def read_check(text, order, names):
    """{routine: [[values per state in Pinocchio's order]]} from a program's check output."""
    n = len(order)
    back = [order.index(j) for j in names]  # position in the program's order of Pinocchio's i

    def permute(v):
        if len(v) == n:
            return [v[back[i]] for i in range(n)]
        if len(v) == n * n:
            return [v[back[i] * n + back[j]] for i in range(n) for j in range(n)]
        return permute(v[:n * n]) + permute(v[n * n:])
    out = {}
    for line in text.splitlines():
        parts = line.split()
        out.setdefault(parts[0], []).append(permute([float(x) for x in parts[2:]]))
    return out


def cond(mass, n):
    """cond(M) in the 2-norm (numpy's), the factor by which a solve with M may amplify the
    relative round-off of M and of the right-hand side."""
    import numpy as np  # the benches' environment has numpy
    m = np.array(mass).reshape(n, n)
    return float(np.linalg.cond(m))


def error(ours, ref):
    scale = max(1.0, max(abs(x) for x in ref))
    return max(abs(x - y) for x, y in zip(ours, ref)) / scale


def check(name, side, got, ref, n):
    """The largest relative error of each compared output over the states."""
    res = {}
    for routine, outputs in got.items():
        key = {"mass_matrix": "mass", "crba": "mass", "cqg_id": "bias", "bias": "bias",
               "mass_and_bias": "mass_bias", "mass_bias": "mass_bias", "inverse_dynamics": "tau",
               "rnea": "tau", "forward_dynamics": "qdd", "aba": "qdd"}[routine]
        worst, limit_ok = 0.0, True
        for s, v in enumerate(outputs):
            r = ref["mass"][s] + ref["bias"][s] if key == "mass_bias" else ref[key][s]
            e = error(v, r)
            tol = 1e-12 * (cond(ref["mass"][s], n) if key == "qdd" else 1.0)
            limit_ok &= e <= tol
            worst = max(worst, e)
        res[routine] = dict(error=worst, ok=limit_ok)
        if not limit_ok:
            log(f"{name} {side} {routine}: relative error {worst:.1e} above the bound")
    return res


def build_casadi(name, meta_dir, n):
    exes = {}
    for build, flags in (("native", ["-O3", "-march=native"]), ("portable", ["-O3"])):
        exe = os.path.join(meta_dir, f"casadi_{build}")
        sh(["gcc"] + flags + [f"-DNQ={n}", "-I", meta_dir, os.path.join(HERE, "casadi_main.c"),
                              os.path.join(meta_dir, "casadi.c"), "-lm", "-o", exe])
        exes[build] = exe
    return exes


def build_pinocchio(pin_python):
    """pinocchio_main.cpp against the pip packages' headers and libraries (the flags of
    benches/baselines/pinocchio/build.sh: the algorithms instantiated here at -O3
    -march=native, the URDF parser from libpinocchio_parsers.so). Rebuilt when the source
    is newer than the program (the compilation takes minutes)."""
    exe = os.path.join(WORK, "pinocchio_main")
    src = os.path.join(HERE, "pinocchio_main.cpp")
    if os.path.exists(exe) and os.path.getmtime(exe) > os.path.getmtime(src):
        return exe
    p = sh([pin_python, "-c", "import sysconfig, os; print(os.path.join(sysconfig.get_paths()['purelib'], "
            "'cmeel.prefix'))"]).strip()
    inc = [f"-I{p}/include", f"-I{p}/include/eigen3", f"-I{p}/include/urdfdom_headers", f"-I{p}/include/urdfdom"]
    libs = [f"-L{p}/lib", f"-Wl,-rpath,{p}/lib", "-lpinocchio_parsers", "-lpinocchio_default", "-lurdfdom_model",
            "-lconsole_bridge", "-lboost_filesystem", "-lboost_serialization"]
    sh(["g++"] + PINOCCHIO_FLAGS + inc + ["-c", src, "-o", exe + ".o"])
    sh(["g++", exe + ".o", "-o", exe] + libs)
    return exe


def build_ours(rs):
    crate = os.path.join(WORK, "ours")
    os.makedirs(os.path.join(crate, "src"), exist_ok=True)
    with open(os.path.join(crate, "Cargo.toml"), "w") as f:
        f.write(f"""[package]
name = "casadi-ours"
version = "0.0.0"
edition = "2024"
publish = false

[workspace]

[dependencies]
mechanism = {{ package = "mechanism-dynamics", path = "{ROOT}", default-features = false, features = ["std"] }}
mechanism-codegen = {{ path = "{ROOT}/codegen" }}

# The README's advice for large mechanisms built with --release: the derivation optimised.
[profile.release.package.mechanism-codegen]
opt-level = 3
""")
    decls, arms = [], []
    for name, r in rs.items():
        lock = ", ".join(f'"{j}"' for j in r["lock"])
        snap = f", snap_angles = {r['snap']}" if r["snap"] else ""
        decls.append(f'    pub mod {name} {{\n        mechanism::mechanism!(urdf = "{r["urdf"]}", lock = [{lock}], '
                     f'name = Robot{snap});\n    }}')
        arms.append(f'        "{name}" => run(&robots::{name}::Robot::default(), &args[2..]),')
    with open(os.path.join(HERE, "ours.rs")) as f:
        body = f.read()
    main = (body + "\nmod robots {\n" + "\n".join(decls) + "\n}\n\nfn main() {\n"
            "    let args: Vec<String> = std::env::args().collect();\n"
            "    if args[1] == \"counts\" {\n        return counts(&args[2], &args[3], &args[4..]);\n    }\n"
            "    match args[1].as_str() {\n" + "\n".join(arms) + "\n        other => panic!(\"unknown robot {other}\"),\n"
            "    }\n}\n")
    with open(os.path.join(crate, "src", "main.rs"), "w") as f:
        f.write(main)
    exes = {}
    for build, flags, target in (("portable", "", "target"), ("native", "-C target-cpu=native", "target-native")):
        env = dict(os.environ, CARGO_TARGET_DIR=os.path.join(WORK, target), RUSTFLAGS=flags)
        subprocess.run(["cargo", "build", "-q", "--release"], cwd=crate, env=env, check=True)
        exes[build] = os.path.join(WORK, target, "release", "casadi-ours")
    return exes


def calls_for(n):
    """Calls per batch: a few milliseconds of the slowest routine."""
    return max(200, 40000 // (n * n))


def table(res):
    lines = []
    for name, r in res["robots"].items():
        lines.append(f"**{name}** ({r['n']} coordinates; {r['source']}):\n")
        lines.append("| routine | ops ours | ops CasADi | native: ours (ns) | CasADi (ns) | ratio "
                     "| Pinocchio (ns) | ratio | portable: ours (ns) | CasADi (ns) | ratio "
                     "| max error ours / CasADi / Pinocchio |")
        lines.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
        for ours, theirs, _, label in ROUTINES:
            t = r["times"]
            cells = []
            for build in ("native", "portable"):
                a, b = t[f"ours {build}|{ours}"], t[f"casadi {build}|{theirs}"]
                cells += [f"{a:.0f}", f"{b:.0f}", f"{a / b:.2f}x"]
                if build == "native":
                    p = t[f"pinocchio native|{theirs}"]
                    cells += [f"{p:.0f}", f"{a / p:.2f}x"]
            ops_text = f"{r['ops']['ours'][ours]}"
            chk = r["check"]
            err = (f"{chk['ours'][ours]['error']:.0e} / {chk['casadi'][theirs]['error']:.0e} / "
                   f"{chk['pinocchio'][theirs]['error']:.0e}")
            lines.append(f"| {label} | {ops_text} | {r['ops']['casadi'][theirs]} | " + " | ".join(cells) + f" | {err} |")
        lines.append("")
    lines.append(f"Thread CPU per call, median over {res['rounds']} interleaved rounds of the median of "
                 f"{BATCHES} batches; states: {res['states']} random states per robot. Load average at the "
                 f"rounds' starts: {', '.join(res['loads'])} ({os.cpu_count()} cores). CasADi "
                 f"{res['casadi_version']} with its Pinocchio 2.6; Pinocchio {res['pinocchio']}'s C++ (crba, "
                 f"nonLinearEffects, both for M and C q' + g, rnea, aba) built -O3 -march=native only; all "
                 f"checked against Pinocchio {res['pinocchio']}'s Python.")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--casadi-python", required=True)
    ap.add_argument("--pin-python", default=os.environ.get("PYTHON", "python3"))
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--states", type=int, default=64)
    ap.add_argument("--robots", nargs="*",
                    default=["panda", "ur5", "ur5_snapped", "iiwa", "iiwa_snapped", "solo12", "talos30"])
    a = ap.parse_args()
    os.makedirs(WORK, exist_ok=True)
    os.makedirs(RESULTS, exist_ok=True)
    rs = robots(a)
    spec = os.path.join(WORK, "robots.json")
    with open(spec, "w") as f:
        json.dump({k: dict(urdf=v["urdf"], lock=v["lock"]) for k, v in rs.items()}, f)
    log("Pinocchio 4.1: states and references")
    sh([a.pin_python, os.path.join(HERE, "pinocchio_reference.py"), spec, WORK, str(a.states)])
    log("CasADi: C from Pinocchio's algorithms")
    prefix = sh([a.casadi_python, "-c", "import cmeel, os; print(os.path.join(cmeel.__path__[0], '..', "
                 "'cmeel.prefix', 'lib'))"]).strip()
    cenv = dict(os.environ, LD_LIBRARY_PATH=prefix + ":" + os.environ.get("LD_LIBRARY_PATH", ""))
    log(sh([a.casadi_python, os.path.join(HERE, "casadi_codegen.py"), spec, WORK], env=cenv).strip())
    casadi_version = sh([a.casadi_python, "-c", "import casadi; print(casadi.__version__)"], env=cenv).strip()
    log("ours: building the robots' crate, portable and native")
    ours = build_ours(rs)
    log("Pinocchio 4.1: its C++ routines")
    pin_exe = build_pinocchio(a.pin_python)
    res = dict(robots={}, rounds=a.rounds, states=a.states, casadi_version=casadi_version)
    r = rounds.Rounds()
    for name, robot in rs.items():
        d = os.path.join(WORK, name)
        ref = json.load(open(os.path.join(d, "reference.json")))
        meta = json.load(open(os.path.join(d, "meta.json")))
        res["pinocchio"] = ref["pinocchio"]
        names, n = ref["joints"], len(ref["joints"])
        our_order = sh([ours["portable"], name, "names"]).split()
        casadi_exes = build_casadi(name, d, n)
        states = {"ours": os.path.join(d, "states_ours.bin"), "casadi": os.path.join(d, "states_casadi.bin"),
                  "pinocchio": os.path.join(d, "states_pinocchio.bin")}
        write_states(states["ours"], ref["states"], our_order, names)
        write_states(states["casadi"], ref["states"], meta["joints"], names)
        write_states(states["pinocchio"], ref["states"], names, names)
        pin_cmd = [pin_exe, robot["urdf"]] + robot["lock"] + ["--"]
        checks = dict(ours=check(name, "ours", read_check(sh([ours["portable"], name, "check", states["ours"],
                                                                str(a.states)]), our_order, names),
                                 ref["reference"], n),
                      casadi=check(name, "casadi", read_check(sh([casadi_exes["native"], "check", states["casadi"],
                                                                    str(a.states)]), meta["joints"], names),
                                   ref["reference"], n),
                      pinocchio=check(name, "pinocchio", read_check(sh(pin_cmd + ["check", states["pinocchio"],
                                                                         str(a.states)]), names, names),
                                      ref["reference"], n))
        counts = json.loads(sh([ours["portable"], "counts", robot["urdf"], str(robot["snap"] or "none")]
                               + robot["lock"]))
        ops = dict(ours={k: sum(counts[p] for p in v) for k, v in OUR_OPS.items()},
                   casadi={k: v["ops"] for k, v in meta["functions"].items()})
        res["robots"][name] = dict(n=n, source=robot["source"], check=checks, ops=ops, times={})
        calls = str(calls_for(n))
        for build in ("portable", "native"):
            for ours_routine, theirs, _, _ in ROUTINES:
                r.add((name, f"ours {build}", ours_routine),
                      lambda e=ours[build], nm=name, o=ours_routine, s=states["ours"]:
                      [float(x) for x in sh([e, nm, "time", o, s, str(a.states), str(BATCHES), calls]).split()])
            for fn in meta["functions"]:
                r.add((name, f"casadi {build}", fn),
                      lambda e=casadi_exes[build], f=fn, s=states["casadi"]:
                      [float(x) for x in sh([e, "time", f, s, str(a.states), str(BATCHES), calls]).split()])
        for fn in meta["functions"]:
            r.add((name, "pinocchio native", fn),
                  lambda c=pin_cmd, f=fn, s=states["pinocchio"]:
                  [float(x) for x in sh(c + ["time", f, s, str(a.states), str(BATCHES), calls]).split()])
    log(f"{len(r.subjects)} subjects, {a.rounds} rounds")
    r.run(a.rounds, log=log)
    for key, v in r.summary().items():
        name, side, routine = key.split("|")
        res["robots"][name]["times"][f"{side}|{routine}"] = v["median"]
    res["loads"] = r.loads
    with open(os.path.join(RESULTS, "casadi.json"), "w") as f:
        json.dump(res, f, indent=1)
    md = table(res)
    with open(os.path.join(RESULTS, "casadi.md"), "w") as f:
        f.write(md + "\n")
    print(md)


if __name__ == "__main__":
    main()
