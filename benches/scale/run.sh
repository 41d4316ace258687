#!/bin/sh
# Derivation at scale (issue 28): user and system CPU time, wall time and peak memory of
# `mechanism equations` (parse, derive, the constraint rows' routines for the mobility,
# the text) on the closed N-bar chain and on N free coordinates. Usage:
# benches/scale/run.sh [chain sizes] [free sizes] from the repository root, after
# `cargo build --release` (N = 800 needs MECHANISM_MAX_SIZE=100000000 in the environment).
set -eu
here=$(dirname "$0")
bin=${MECHANISM:-target/release/mechanism}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
chains=${1:-"50 100 200"}
frees=${2:-"1000 2000 5000"}
echo "| mechanism | N | user CPU (s) | system CPU (s) | wall (s) | peak memory (MB) |"
echo "|---|---|---|---|---|---|"
for n in $chains; do
    python3 "$here/closed_chain.py" "$n" > "$tmp/chain$n.mech"
    MECHANISM_MAX_INPUT_BYTES=100000000 /usr/bin/time -f "%U %S %e %M" -o "$tmp/t" "$bin" equations "$tmp/chain$n.mech" > /dev/null 2>&1
    read -r user sys wall kb < "$tmp/t"
    echo "| closed chain | $n | $user | $sys | $wall | $((kb / 1024)) |"
done
for n in $frees; do
    python3 "$here/free_coordinates.py" "$n" > "$tmp/free$n.mech"
    /usr/bin/time -f "%U %S %e %M" -o "$tmp/t" "$bin" equations "$tmp/free$n.mech" > /dev/null 2>&1
    read -r user sys wall kb < "$tmp/t"
    echo "| free coordinates | $n | $user | $sys | $wall | $((kb / 1024)) |"
done
