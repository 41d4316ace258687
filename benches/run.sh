#!/usr/bin/env bash
# Every generated table of BENCHMARKS.md in one run of the current tree against the peers,
# then the tables (see benches/run.py for the steps):
#
#   benches/run.sh [--rounds 5] [--skip c rounds controllers profile criterion derivation mujoco robot a02 compile-time casadi]
#
# Creates a Python environment under <target>/baselines-venv (<target>: CARGO_TARGET_DIR
# when set, else target/) with sympy, scipy, numpy, and mujoco and Pinocchio's packages when
# they install, then runs benches/run.py with it. BENCHMARKS.md's first generated block
# gives the last run's duration and each step's share of it.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
target="$(cd "$root" && mkdir -p "${CARGO_TARGET_DIR:-target}" && cd "${CARGO_TARGET_DIR:-target}" && pwd)"
export CARGO_TARGET_DIR="$target"
venv="$target/baselines-venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install -q sympy scipy numpy
"$venv/bin/pip" install -q mujoco || echo "mujoco not installable here: its step is skipped"
"$venv/bin/pip" install -q pin cmeel-eigen cmeel-urdfdom-headers \
    || echo "Pinocchio not installable here: the Panda step is skipped"
exec "$venv/bin/python" "$root/benches/run.py" --venv-python "$venv/bin/python" "$@"
