#!/usr/bin/env python3
"""The derivation of long serial chains as they grow (issue 54): for each N, the chain of
`serial_chain.py` (N revolute links, axes alternating z, y, x) imported with `mechanism
import` and printed with `mechanism equations`, under `/usr/bin/time -v` (wall time, peak
resident memory), and the operations of the derived M, g, C q' + g and inverse dynamics
(`role_ops --derived`: each lowered alone, CSE and factoring, no parameter cache). With
`--casadi-python VENV/bin/python` (the CasADi baseline's environment, see
benches/baselines/casadi/run.sh) also the operations of Pinocchio's own algorithms traced
by CasADi (crba, rnea with q'' = 0, rnea, aba; `cse: True`), per link.

    cargo build --release -p mechanism-dynamics --bin mechanism
    cargo build --release -p mechanism-bench --bin role_ops
    python3 benches/scale/chain_growth.py [--sizes 50 100 200 300 500] [--casadi-python PY]

Writes a markdown table to stdout and the figures to <target>/bench-results/chain_growth.json.
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)
import serial_chain  # noqa: E402
from target_dir import RESULTS, TARGET  # noqa: E402

CASADI_COUNT = r"""
import sys, casadi as cs
from casadi_kin_dyn.casadi_kin_dyn import CasadiKinDyn
NOT = {cs.OP_INPUT, cs.OP_OUTPUT, cs.OP_CONST, cs.OP_PARAMETER}
kd = CasadiKinDyn(open(sys.argv[1]).read(), CasadiKinDyn.JointType.OMIT, False, {})
n = kd.nv()
q, v, a, tau = (cs.SX.sym(s, n) for s in "qvat")
o = {"cse": True}
fs = {"M": cs.Function("crba", [q], [kd.crba()(q)], o),
      "bias": cs.Function("bias", [q, v], [kd.rnea()(q, v, cs.SX.zeros(n))], o),
      "inverse_dynamics": cs.Function("rnea", [q, v, a], [kd.rnea()(q, v, a)], o),
      "forward_dynamics": cs.Function("aba", [q, v, tau], [kd.aba()(q, v, tau)], o)}
print({k: sum(1 for i in range(f.n_instructions()) if f.instruction_id(i) not in NOT) for k, f in fs.items()})
"""


def timed(cmd):
    """(seconds of wall time, peak resident MB) of `cmd` under /usr/bin/time -v."""
    p = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{p.stderr[-2000:]}")
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", p.stderr).group(1)
    seconds = sum(float(x) * 60 ** k for k, x in enumerate(reversed(wall.split(":"))))
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr).group(1))
    return seconds, rss_kb / 1024, len(p.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", nargs="*", type=int, default=[50, 100, 200, 300, 500])
    ap.add_argument("--casadi-python")
    a = ap.parse_args()
    cli = os.path.join(TARGET, "release", "mechanism")
    role_ops = os.path.join(TARGET, "release", "role_ops")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in a.sizes:
            urdf, mech = os.path.join(tmp, f"chain{n}.urdf"), os.path.join(tmp, f"chain{n}.mech")
            with open(urdf, "w") as f:
                f.write(serial_chain.urdf(n))
            with open("/proc/loadavg") as f:
                load = f.read().split()[0]
            subprocess.run([cli, "import", urdf, "--out", mech], check=True, capture_output=True)
            seconds, mb, chars = timed([cli, "equations", mech])
            out = subprocess.run([role_ops, "--derived", mech], check=True, capture_output=True, text=True).stdout
            cells = out.strip().splitlines()[-1].strip("|").split("|")
            ops = dict(zip(["M", "g", "bias", "inverse_dynamics"], (int(c) for c in cells[2:6])))
            row = dict(n=n, seconds=seconds, peak_mb=mb, printed_chars=chars, load=load, ops=ops)
            if a.casadi_python:
                code = subprocess.run([a.casadi_python, "-c", CASADI_COUNT, urdf], check=True, capture_output=True,
                                      text=True, env=casadi_env(a.casadi_python)).stdout
                row["casadi_ops"] = eval(code)  # a dict literal printed by the script above
            rows.append(row)
            print(f"chain {n}: {seconds:.2f} s, {mb:.0f} MB, ops {ops}, load {load}", file=sys.stderr, flush=True)
    os.makedirs(RESULTS, exist_ok=True)
    with open(os.path.join(RESULTS, "chain_growth.json"), "w") as f:
        json.dump(rows, f, indent=1)
    print(table(rows))


def casadi_env(python):
    prefix = subprocess.run([python, "-c", "import cmeel, os; print(os.path.join(cmeel.__path__[0], '..', "
                             "'cmeel.prefix', 'lib'))"], check=True, capture_output=True, text=True).stdout.strip()
    return dict(os.environ, LD_LIBRARY_PATH=prefix + ":" + os.environ.get("LD_LIBRARY_PATH", ""))


def table(rows):
    lines = ["| links | `mechanism equations` wall (s) | peak memory (MB) | load | ops M | ops g | ops C q' + g "
             "| ops inverse dynamics | per link: M / n | C q' + g / n | inverse dynamics / n |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        o, n = r["ops"], r["n"]
        lines.append(f"| {n} | {r['seconds']:.2f} | {r['peak_mb']:.0f} | {r['load']} | {o['M']} | {o['g']} "
                     f"| {o['bias']} | {o['inverse_dynamics']} | {o['M'] / n:.0f} | {o['bias'] / n:.0f} "
                     f"| {o['inverse_dynamics'] / n:.0f} |")
    if any("casadi_ops" in r for r in rows):
        lines += ["", "Operations per link, ours / Pinocchio's algorithms traced by CasADi (`cse: True`):", "",
                  "| links | M | C q' + g | inverse dynamics | forward dynamics (CasADi's aba) |",
                  "|---:|---:|---:|---:|---:|"]
        for r in rows:
            if "casadi_ops" not in r:
                continue
            o, c, n = r["ops"], r["casadi_ops"], r["n"]
            lines.append(f"| {n} | {o['M'] / n:.0f} / {c['M'] / n:.0f} | {o['bias'] / n:.0f} / {c['bias'] / n:.0f} "
                         f"| {o['inverse_dynamics'] / n:.0f} / {c['inverse_dynamics'] / n:.0f} "
                         f"| {c['forward_dynamics'] / n:.0f} |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
