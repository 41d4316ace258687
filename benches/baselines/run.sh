#!/usr/bin/env bash
# The peers, side by side (issue 6, item 4). On demand, not in CI.
#
#   benches/baselines/run.sh [--chains 4 8 16 32] [--lagranges 4 8 16] [--c-chains 8 16] [--skip-scipy]
#
# Creates a venv under target/baselines-venv, pip-installs sympy, scipy and numpy (and tries
# mujoco), then runs baselines.py: SymPy derivation of the chain (LagrangesMethod and the
# direct route), SymPy-cse C code timed with gcc -O3 -march=native for the seed, the
# four-bar, the RSSR and the chains, and scipy's DOP853 on the seed (10 s at 1e-10).
# Results: target/bench-results/baselines.json. Run `cargo bench -p mechanism-bench` first
# so that the scipy error is measured against our DOP853 1e-13 reference, then
# `python3 benches/report.py` for the side-by-side tables.
# SymPy at N = 32 takes minutes (LagrangesMethod: several more), hence the defaults.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
venv="$root/target/baselines-venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install -q sympy scipy numpy
"$venv/bin/pip" install -q mujoco || echo "mujoco not installable here: skipping it"
exec "$venv/bin/python" "$root/benches/baselines/baselines.py" "$@"
