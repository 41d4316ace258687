#!/usr/bin/env bash
# Our generated code against CasADi's code from Pinocchio's algorithms (issue 50): a step of
# benches/run.sh (`casadi`), or alone:
#
#   benches/baselines/casadi/run.sh [--rounds 5] [--robots panda ur5 ...]
#
# Installs the peer into its own virtual environment (CASADI_VENV, default
# <target>/casadi-venv): `cmeel-casadi-kin-dyn`, whose wheels need Python 3.11-compatible
# cmeel builds and bring their own Pinocchio 2.6 and CasADi 3.6 (its libraries are found
# through LD_LIBRARY_PATH at the environment's cmeel.prefix/lib, which casadi_bench.py sets),
# then runs casadi_bench.py with the interpreter $PYTHON (python3 by default), which must
# have Pinocchio 4.1 (`pin`), example-robot-data and numpy: the reference and the robots.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
target="$(cd "$root" && mkdir -p "${CARGO_TARGET_DIR:-target}" && cd "${CARGO_TARGET_DIR:-target}" && pwd)"
export CARGO_TARGET_DIR="$target"
venv="${CASADI_VENV:-$target/casadi-venv}"
python="${PYTHON:-python3}"
if [ ! -x "$venv/bin/python" ]; then
    python3.11 -m venv "$venv" 2>/dev/null || "$python" -m venv "$venv"
fi
"$venv/bin/pip" install -q cmeel-casadi-kin-dyn numpy
exec "$python" "$here/casadi_bench.py" --casadi-python "$venv/bin/python" --pin-python "$python" "$@"
