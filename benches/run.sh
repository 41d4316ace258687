#!/usr/bin/env bash
# Every benchmark of BENCHMARKS.md in one run, then its tables (see benches/run.py):
#
#   benches/run.sh [--rounds 7] [--skip criterion derivation mujoco a02 compile-time]
#
# Creates a Python environment under target/baselines-venv (sympy, scipy, numpy, and mujoco
# when it installs), then runs benches/run.py with it. The run takes about 20 minutes on
# the 2-core machine of BENCHMARKS.md, plus a few the first time (the harness built at each
# commit of benches/changes.toml); SymPy's LagrangesMethod at N = 32 and the compile-time
# builds are its slowest steps, and `--skip` leaves out the steps that do not feed the
# headline tables.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
venv="$root/target/baselines-venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install -q sympy scipy numpy
"$venv/bin/pip" install -q mujoco || echo "mujoco not installable here: skipping it"
exec "$venv/bin/python" "$root/benches/run.py" --venv-python "$venv/bin/python" "$@"
