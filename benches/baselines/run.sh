#!/usr/bin/env bash
# The peers, side by side (issue 6, item 4). On demand, not in CI.
#
#   benches/baselines/run.sh [--chains 4 8 16 32] [--lagranges 4 8 16 32] [--c-chains 8 16 32]
#                            [--c-variants strict per_routine] [--skip-c] [--skip-scipy]
#                            [--skip-mujoco | --mujoco-only]
#
# Creates a venv under target/baselines-venv, pip-installs sympy, scipy and numpy (and tries
# mujoco), then runs baselines.py: SymPy derivation of the chain (LagrangesMethod and the
# direct route), SymPy-cse C code timed with gcc -O3 -march=native for the seed, the
# four-bar, the RSSR and the chains, and scipy's DOP853 on the seed (10 s at 1e-10).
# Results: target/bench-results/baselines.json. Run `cargo bench -p mechanism-bench` first
# so that the scipy error is measured against our DOP853 1e-13 reference, then
# `python3 benches/report.py` for the side-by-side tables.
# SymPy-C comes in two variants (one function after one joint cse; codegen's one CSE'd routine
# per matrix) and scipy in two (lambdify cse=True; lambdify defaults): see BENCHMARKS.md.
# SymPy at N = 32 takes minutes (LagrangesMethod at N = 32: ~5-6 min of one core), hence the
# defaults.
# Then, if mujoco is importable, mujoco_four_bar.py: the soft-closed four-bar in MJCF
# (target/bench-results/mujoco.json, ~1 min). --skip-mujoco / --mujoco-only are handled
# here, not passed on (baselines.py's argparse would reject them).
set -euo pipefail
run_mujoco=1 run_baselines=1 args=()
for a in "$@"; do
    case "$a" in
        --skip-mujoco) run_mujoco=0 ;;
        --mujoco-only) run_baselines=0 ;;
        *) args+=("$a") ;;
    esac
done
root="$(cd "$(dirname "$0")/../.." && pwd)"
venv="$root/target/baselines-venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install -q sympy scipy numpy
"$venv/bin/pip" install -q mujoco || echo "mujoco not installable here: skipping it"
if [ "$run_baselines" = 1 ]; then
    "$venv/bin/python" "$root/benches/baselines/baselines.py" ${args[@]+"${args[@]}"}
fi
if [ "$run_mujoco" = 1 ]; then
    if "$venv/bin/python" -c "import mujoco" 2>/dev/null; then
        "$venv/bin/python" "$root/benches/baselines/mujoco_four_bar.py"
    else
        echo "mujoco not importable: skipping the MuJoCo four-bar"
    fi
fi
