#!/usr/bin/env bash
# A scripted adversarial campaign (issue 29): hostile inputs through the release binary,
# counting panics, silent NaNs and misdiagnoses. Rerun with
#   cargo build --release && tests/adversarial/campaign.sh [path/to/mechanism]
# Prints one line per category and the totals; exit status 1 if any count is non-zero.
set -u
BIN=${1:-${CARGO_TARGET_DIR:-target}/release/mechanism}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
runs=0 panics=0 nans=0 misdiagnoses=0 exit0=0 exit1=0 exit2=0 other=0
# Messages that named the wrong cause before issue 29 (items 10 to 15, and the NaN of a
# divergence at a loose tolerance, item 17).
WRONG='check the link lengths|conflicting drives|dead point|gamma row 1 .* is NaN|step size collapsed to h = 6|C q. of .* is (NaN|inf)'

one() { # one run: args...; records the outcome
  local dir="$WORK/run$runs" err code
  runs=$((runs + 1))
  timeout 60 "$BIN" "$@" --out "$dir" >"$WORK/stdout" 2>"$WORK/stderr"
  code=$?
  err=$(cat "$WORK/stderr")
  case $code in 0) exit0=$((exit0 + 1));; 1) exit1=$((exit1 + 1));; 2) exit2=$((exit2 + 1));; *) other=$((other + 1));; esac
  if [ "$code" = 101 ] || grep -q 'panicked' "$WORK/stderr"; then
    panics=$((panics + 1)); echo "PANIC: $*"; fi
  if [ "$code" = 0 ] && grep -qi 'nan\|inf' "$dir"/*.csv 2>/dev/null; then
    nans=$((nans + 1)); echo "SILENT NaN: $*"; fi
  if [ -n "${EXPECT_RIGHT:-}" ] && echo "$err" | grep -Eq "$WRONG"; then
    misdiagnoses=$((misdiagnoses + 1)); echo "MISDIAGNOSIS: $* -> $err"; fi
  rm -rf "$dir"
}

MECHS=$("$BIN" list | awk 'NR > 1 && NF == 7 { print $1 }' | grep -v '^panda$')
# 1. Bad numbers in every numeric option.
for m in planar_four_bar cartesian_pendulum bricard five_bar; do
  for v in nan inf -inf -1 0 1e-320 1e300 abc '' 1e9 1e-9; do
    one simulate "$m" --t-end "$v" --no-animation
    one simulate "$m" --t-end 0.2 --samples-per-second "$v" --no-animation
    one simulate "$m" --t-end 0.2 --rtol "$v" --no-animation
    one simulate "$m" --t-end 0.2 --integrator rk4 --step "$v" --no-animation
  done
done
# 2. Typos and unknown names.
for m in $MECHS; do
  one simulate "$m" --t-end 0.1 --set NOPE=1 --no-animation
  one simulate "$m" --t-end 0.1 --init nope=1 --no-animation
  one inverse "$m" --drive 'nope = t' --t-end 0.1
done
one simulate planar_four_bar_ --t-end 0.1
one simualte planar_four_bar
# 3. Huge and tiny values of parameters and initial states.
for m in planar_four_bar spatial_crank_slider cartesian_pendulum; do
  for g in 1e10 1e23 -1e10 1e-300 1e300; do
    one simulate "$m" --t-end 0.05 --set "g=$g" --no-animation
  done
  for v in 1e300 1e9 -1e9 nan; do
    one simulate "$m" --t-end 0.05 --init "$( "$BIN" equations "$m" 2>/dev/null | grep -o 'independent: [a-z_0-9]*' | head -1 | cut -d' ' -f2 )=$v" --no-animation
  done
done
# 4. Loose and tight tolerances on every mechanism (no divergence).
for m in $MECHS; do
  for tol in 1e-1 1e-3 1e-6 1e-9 1e-12; do
    EXPECT_RIGHT=1 one simulate "$m" --t-end 1 --rtol "$tol" --atol "$tol" --no-animation
  done
done
# 5. The misdiagnosed inputs of the issue (items 10 to 15).
export EXPECT_RIGHT=1
for s in 0.5 0.1 0.05; do
  one simulate planar_four_bar --integrator rk4 --step "$s" --no-animation
  one simulate planar_four_bar --integrator hht --step "$s" --no-animation
done
one simulate planar_four_bar --t-end 1e9 --samples-per-second 1e-6 --no-animation
for d in 'x = t' 'x = 2*t' 'x = 0.3 + 0.2*abs(t - 0.5)' 'x = 0.3 + 0.2*abs(t - 0.505)' 'x = 0.3 + 0.2*abs(t - 0.2)'; do
  one inverse cartesian_pendulum --drive "$d"
done
one inverse planar_four_bar --drive 'th3 = 2*pi*t'
one simulate spatial_crank_slider --set g=1e10 --t-end 0.01 --no-animation
unset EXPECT_RIGHT
# 6. Closed and full standard output.
for c in list 'equations planar_four_bar' --version; do
  runs=$((runs + 1))
  "$BIN" $c 2>"$WORK/stderr" | true
  if grep -q panicked "$WORK/stderr"; then panics=$((panics + 1)); echo "PANIC: $c | true"; fi
  runs=$((runs + 1))
  "$BIN" $c >/dev/full 2>"$WORK/stderr"
  if [ $? = 101 ] || grep -q panicked "$WORK/stderr"; then panics=$((panics + 1)); echo "PANIC: $c >/dev/full"; fi
done
# 7. Concurrent runs into one folder: one completes, the other is refused; never mixed rows.
mixed=0
for trial in 1 2 3 4 5; do
  D="$WORK/shared"; rm -rf "$D"
  A=(simulate planar_four_bar --t-end 5 --samples-per-second 2000 --no-animation --out "$D")
  "$BIN" "${A[@]}" --set g=9.81 >/dev/null 2>&1 & "$BIN" "${A[@]}" --set g=3 >/dev/null 2>&1; wait
  runs=$((runs + 2))
  if awk -F, 'NR == 1 { n = NF } NF != n { bad = 1 } END { exit !bad }' "$D/trajectory.csv"; then
    mixed=$((mixed + 1)); echo "MIXED ROWS: trial $trial"; fi
done

echo "runs: $runs (exit 0: $exit0, 1: $exit1, 2: $exit2, other: $other)"
echo "panics: $panics"
echo "silent NaNs: $nans"
echo "misdiagnoses: $misdiagnoses"
echo "concurrent trials with mixed rows: $mixed of 5"
[ $((panics + nans + misdiagnoses + mixed)) = 0 ]
