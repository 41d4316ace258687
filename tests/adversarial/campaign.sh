#!/usr/bin/env bash
# A scripted adversarial campaign (issues 29 and 53): hostile inputs through the release
# binary, counting panics, hangs, silent NaNs, silent wrong answers, misdiagnoses and lost
# data. Rerun with
#   cargo build --release && tests/adversarial/campaign.sh [path/to/mechanism]
# (as root, the full-disk section mounts a 1 MiB tmpfs; without the privilege it says so
# and goes on). Prints one line per finding and the totals; exit status 1 if any count of
# a failure is non-zero.
set -u
BIN=$(realpath "${1:-${CARGO_TARGET_DIR:-target}/release/mechanism}")
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
WORK=$(mktemp -d)
cleanup() { umount "$WORK/tmpfs" 2>/dev/null; rm -rf "$WORK"; }
trap cleanup EXIT
cd "$WORK" || exit 1
runs=0 panics=0 hangs=0 nans=0 wrong=0 misdiagnoses=0 loss=0 unlocated=0 unlocked=0 stopped=0
exit0=0 exit1=0 exit2=0 other=0
# Messages that named the wrong cause before issues 29 and 53: issue 29's items 10 to 15
# and 17, and issue 53's items 10 (a long run's singular passage blamed on stiffness), 11
# (a wheel that falls over: the orientation angles degenerate) and 12 (a value out of
# reach blamed on the guess).
WRONG='check the link lengths|conflicting drives|dead point|gamma row 1 .* is NaN|step size collapsed to h = 6|C q. of .* is (NaN|inf)|no inertia to an allowed motion|start from a closer guess|too fast or stiff'

finding() { echo "$1: ${*:2}"; }
# One run: args...; records the outcome in $code and $err ($dir holds its output).
one() {
  dir="$WORK/run"
  rm -rf "$dir"
  runs=$((runs + 1))
  timeout "${LIMIT:-60}" "$BIN" "$@" --out "$dir" >"$WORK/stdout" 2>"$WORK/stderr"
  code=$?
  err=$(cat "$WORK/stderr")
  case $code in 0) exit0=$((exit0 + 1));; 1) exit1=$((exit1 + 1));; 2) exit2=$((exit2 + 1));; *) other=$((other + 1));; esac
  if [ "$code" = 124 ]; then hangs=$((hangs + 1)); finding HANG "$*"; fi
  if [ "$code" = 101 ] || grep -q 'panicked' "$WORK/stderr"; then
    panics=$((panics + 1)); finding PANIC "$*"; fi
  if [ "$code" = 0 ] && grep -qi 'nan\|inf' "$dir"/*.csv 2>/dev/null; then
    nans=$((nans + 1)); finding "SILENT NaN" "$*"; fi
  if [ -n "${EXPECT_RIGHT:-}" ] && echo "$err" | grep -Eq "$WRONG"; then
    misdiagnoses=$((misdiagnoses + 1)); finding MISDIAGNOSIS "$* -> $err"; fi
}
# Every entry under a folder with its checksum (hidden ones too; `-x` leaves out what a
# killed run may leave, its lock and staging folder).
snap() {
  (cd "$1" 2>/dev/null && find . ${2:+-not -path './.mechanism*'} \( -type f -printf '%p ' -exec sha1sum {} \; -o -type d -printf '%p/\n' \) | sort)
}
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@" 2>/dev/null; }

MECHS=$("$BIN" list | awk 'NR > 1 && NF == 7 { print $1 }' | grep -v '^panda$')
echo "== 1. Bad numbers in every numeric option"
for m in planar_four_bar cartesian_pendulum bricard five_bar; do
  for v in nan inf -inf -1 0 1e-320 1e300 abc '' 1e9 1e-9; do
    one simulate "$m" --t-end "$v" --no-animation
    one simulate "$m" --t-end 0.2 --samples-per-second "$v" --no-animation
    one simulate "$m" --t-end 0.2 --rtol "$v" --no-animation
    one simulate "$m" --t-end 0.2 --integrator rk4 --step "$v" --no-animation
  done
done
echo "== 2. Typos and unknown names"
for m in $MECHS; do
  one simulate "$m" --t-end 0.1 --set NOPE=1 --no-animation
  one simulate "$m" --t-end 0.1 --init nope=1 --no-animation
  one inverse "$m" --drive 'nope = t' --t-end 0.1
done
one simulate planar_four_bar_ --t-end 0.1
one simualte planar_four_bar
echo "== 3. Huge and tiny values of parameters and initial states"
for m in planar_four_bar spatial_crank_slider cartesian_pendulum; do
  for g in 1e10 1e23 -1e10 1e-300 1e300; do
    one simulate "$m" --t-end 0.05 --set "g=$g" --no-animation
  done
  q=$("$BIN" equations "$m" 2>/dev/null | grep -o 'independent: [a-z_0-9]*' | head -1 | cut -d' ' -f2)
  for v in 1e300 1e9 -1e9 nan; do
    one simulate "$m" --t-end 0.05 --init "$q=$v" --no-animation
  done
done
echo "== 4. Loose and tight tolerances on every mechanism (no divergence)"
for m in $MECHS; do
  for tol in 1e-1 1e-3 1e-6 1e-9 1e-12; do
    EXPECT_RIGHT=1 one simulate "$m" --t-end 1 --rtol "$tol" --atol "$tol" --no-animation
  done
done
echo "== 5. Inputs misdiagnosed before (issue 29, items 10 to 15; issue 53, items 11, 12)"
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
for x in 1.5 2 -1.5 10; do one simulate cartesian_pendulum --init "x=$x" --no-animation; done
for w in 0 0.5 1; do
  one simulate rolling_disc --init "der(th)=$w" --t-end 10 --figures none --no-animation
done
for v in 0 0.5; do
  one simulate whipple_bicycle --set "v=$v" --t-end 10 --figures none --no-animation
done
unset EXPECT_RIGHT
echo "== 6. Closed and full standard output"
for c in list 'equations planar_four_bar' --version; do
  runs=$((runs + 1))
  "$BIN" $c 2>"$WORK/stderr" | true
  if grep -q panicked "$WORK/stderr"; then panics=$((panics + 1)); finding PANIC "$c | true"; fi
  runs=$((runs + 1))
  "$BIN" $c >/dev/full 2>"$WORK/stderr"
  if [ $? = 101 ] || grep -q panicked "$WORK/stderr"; then panics=$((panics + 1)); finding PANIC "$c >/dev/full"; fi
done
echo "== 7. Concurrent runs into one folder: one completes, the other is refused"
for trial in 1 2 3 4 5; do
  D="$WORK/shared"; rm -rf "$D"
  A=(simulate planar_four_bar --t-end 5 --samples-per-second 2000 --no-animation --out "$D")
  "$BIN" "${A[@]}" --set g=9.81 >/dev/null 2>&1 & "$BIN" "${A[@]}" --set g=3 >/dev/null 2>&1; wait
  runs=$((runs + 2))
  if awk -F, 'NR == 1 { n = NF } NF != n { bad = 1 } END { exit !bad }' "$D/trajectory.csv"; then
    loss=$((loss + 1)); finding "MIXED ROWS" "trial $trial"; fi
done
echo "== 8. URDF import: numbers out of range, encodings, an --out that is the input"
ARM="$ROOT/codegen/tests/urdf/arm.urdf"
# Each: a substitution in the test arm and the import's options. The number is absurd
# (beyond any machine, or not a number): the import must refuse it at its element,
# `x.urdf:LINE:COL:`. Imported and simulated, it is a silent wrong answer; imported and
# refused later, a misdiagnosis (the error blames the dynamics, far from the typo).
while IFS='|' read -r from to opts; do
  sed "s#$from#$to#" "$ARM" > "$WORK/x.urdf"
  cmp -s "$ARM" "$WORK/x.urdf" && { echo "campaign: no \`$from\` in the arm"; exit 2; }
  rm -f "$WORK/x.mech"
  runs=$((runs + 1))
  timeout 60 "$BIN" import "$WORK/x.urdf" --out "$WORK/x.mech" $opts >/dev/null 2>"$WORK/stderr"
  code=$?
  if [ "$code" = 101 ] || grep -q panicked "$WORK/stderr"; then panics=$((panics + 1)); finding PANIC "import $to"; fi
  if [ "$code" = 1 ] && grep -q 'x.urdf:[0-9]*:[0-9]*:' "$WORK/stderr"; then continue; fi
  if [ "$code" != 0 ]; then unlocated=$((unlocated + 1)); finding UNLOCATED "import $to -> $(cat "$WORK/stderr")"; continue; fi
  one simulate "$WORK/x.mech" --t-end 0.2 --figures none --no-animation
  if [ "$code" = 0 ]; then wrong=$((wrong + 1)); finding "SILENT WRONG" "import $to: imported and simulated"
  else misdiagnoses=$((misdiagnoses + 1)); finding MISDIAGNOSIS "import $to -> $err"; fi
done <<'CASES'
<mass value="2.5"/>|<mass value="1e300"/>|
<mass value="2.5"/>|<mass value="1e13"/>|
<mass value="2.5"/>|<mass value="-1e300"/>|
<mass value="2.5"/>|<mass value="nan"/>|
<mass value="2.5"/>|<mass value="inf"/>|
<mass value="2.5"/>|<mass value="1e400"/>|
ixx="0.053"|ixx="1e300"|
ixx="0.053" ixy="0"|ixx="0.053" ixy="1e200"|
iyy="0.053"|iyy="1e30"|
<axis xyz="0 0 1"/>|<axis xyz="1e308 0 0"/>|
<axis xyz="0 0 1"/>|<axis xyz="0 0 1e200"/>|
<axis xyz="0 0 1"/>|<axis xyz="nan 0 1"/>|
<origin xyz="0 0 0.25"|<origin xyz="0 0 1e200"|
<origin xyz="0 0 0.25"|<origin xyz="1e155 1e155 0"|
<origin xyz="0 0 0.1"/>|<origin xyz="0 0 1e200"/>|
<origin xyz="0 0 0.1"/>|<origin xyz="0 0 0.1" rpy="1e300 0 0"/>|
damping="0.1"|damping="1e300"|--damping
damping="0.1"|damping="-inf"|--damping
CASES
# In-range values the import must keep taking (a refusal here is a misdiagnosis).
for u in "$ARM" "$ROOT/mechanisms/urdf/panda.urdf" "$ROOT/mechanisms/urdf/g1_29dof_rev_1_0.urdf"; do
  runs=$((runs + 1))
  if ! "$BIN" import "$u" >/dev/null 2>"$WORK/stderr"; then
    misdiagnoses=$((misdiagnoses + 1)); finding MISDIAGNOSIS "import $u -> $(cat "$WORK/stderr")"; fi
done
# Encodings and size: refused naming the file and the place (FILE:LINE:COL), or what the
# text is (UTF-16) or its size.
iconv -f UTF-8 -t UTF-16 "$ARM" > "$WORK/e1.urdf"
iconv -f UTF-8 -t UTF-16LE "$ARM" > "$WORK/e2.urdf"
iconv -f UTF-8 -t UTF-16BE "$ARM" > "$WORK/e3.urdf"
(printf '\xfe\xff'; iconv -f UTF-8 -t UTF-16BE "$ARM") > "$WORK/e4.urdf"
sed 's/upper-arm/upper-\xe4rm/' "$ARM" > "$WORK/e5.urdf"
(cat "$ARM"; printf '\xe2\x82') > "$WORK/e6.urdf"
(printf '\xff'; cat "$ARM") > "$WORK/e7.urdf"
head -c 17000000 /dev/zero | tr '\0' ' ' > "$WORK/e8.urdf"
(printf '// a Latin-1 caf\xe9\n'; cat "$ROOT/mechanisms/planar_four_bar.mech") > "$WORK/e9.mech"
for f in e1.urdf e2.urdf e3.urdf e4.urdf e5.urdf e6.urdf e7.urdf e8.urdf e9.mech; do
  runs=$((runs + 1))
  case $f in *.urdf) "$BIN" import "$WORK/$f" >/dev/null 2>"$WORK/stderr";; *) "$BIN" simulate "$WORK/$f" --out "$WORK/run" >/dev/null 2>"$WORK/stderr";; esac
  code=$?
  if [ "$code" = 101 ] || grep -q panicked "$WORK/stderr"; then panics=$((panics + 1)); finding PANIC "$f"; fi
  if [ "$code" != 1 ] || ! grep -Eq "$f:[0-9]+:[0-9]+:|$f: it is UTF-16|$f: [0-9]+ bytes, more than" "$WORK/stderr"; then
    unlocated=$((unlocated + 1)); finding UNLOCATED "$f -> $(cat "$WORK/stderr")"; fi
done
# --out that is the URDF itself, by any path: the URDF must stay as it was.
cp "$ARM" "$WORK/R.urdf"; ln -sf R.urdf "$WORK/L.urdf"; ln -f "$WORK/R.urdf" "$WORK/H.urdf"
for pair in "R.urdf R.urdf" "R.urdf ./R.urdf" "L.urdf R.urdf" "R.urdf L.urdf" "H.urdf R.urdf"; do
  set -- $pair
  runs=$((runs + 1))
  (cd "$WORK" && "$BIN" import "$1" --out "$2" >/dev/null 2>&1)
  if ! cmp -s "$ARM" "$WORK/R.urdf"; then
    loss=$((loss + 1)); finding "DATA LOSS" "import $1 --out $2 replaced the URDF"; cp "$ARM" "$WORK/R.urdf"; fi
  ln -sf R.urdf "$WORK/L.urdf"
done
echo "== 9. Velocity constraints: chaplygin_sleigh, rolling_disc, whipple_bicycle"
for m in chaplygin_sleigh rolling_disc whipple_bicycle; do
  for i in dop853 dopri5 "rk4 --step 1e-3" "hht --step 1e-3"; do
    for s in projection baumgarte none; do
      EXPECT_RIGHT=1 one simulate "$m" --t-end 2 --integrator $i --stabilization "$s" --figures none --no-animation
    done
  done
  for v in 1e3 1e9 -1e9; do
    EXPECT_RIGHT=1 one simulate "$m" --t-end 0.5 --init "$(echo "$m" | sed 's/chaplygin_sleigh/der(theta)/; s/rolling_disc/der(th)/; s/whipple_bicycle/der(thR)/')=$v" --figures none --no-animation
  done
done
# A wheel of zero or negative radius, a negative mass or inertia: exit 0 is a silent
# wrong answer (issue 53, item 3).
for a in "rolling_disc r=-0.1" "rolling_disc r=0" "whipple_bicycle rR=-0.3" "whipple_bicycle rR=0" "whipple_bicycle rF=-0.35" "chaplygin_sleigh I=-0.1" "rolling_disc m=-1"; do
  set -- $a
  one simulate "$1" --set "$2" --t-end 0.5 --figures none --no-animation
  if [ "$code" = 0 ]; then wrong=$((wrong + 1)); finding "SILENT WRONG" "simulate $a: exit 0"; fi
done
# Initial values written with parameters follow --set (item 1): the rear wheel's rate
# der(thR) = v/rR at the start.
for a in "v=3" "v=7" "rR=0.5" "v=3 --set rR=0.25"; do
  one simulate whipple_bicycle --set $a --t-end 0.1 --figures none --no-animation
  [ "$code" = 0 ] || continue
  ok=$(json "$dir/summary.json" "abs(d['consistent_initial_state']['q_dot']['thR'] - d['parameters']['v']/d['parameters']['rR']) < 1e-9")
  if [ "$ok" != True ]; then wrong=$((wrong + 1)); finding "SILENT WRONG" "whipple --set $a: der(thR)(0) is not v/rR"; fi
done
# linearize: the eigenvalues printed are those of the state matrix written (item 2).
for a in "--set v=5" "--set v=1e3" "--set v=1e4" "--set v=1e5" "--set v=1e6" "--set v=1e7" "--set v=1e8" "--set v=1e9" "--init der(thR)=1e9"; do
  one linearize whipple_bicycle $a
  [ "$code" = 0 ] || continue
  ok=$(python3 - "$dir/linearization.json" <<'PY'
import json, sys
import numpy as np
d = json.load(open(sys.argv[1]))
ev = list(np.linalg.eigvals(np.array(d["state_matrix"])))
claimed = [complex(a, b) for a, b in d["eigenvalues_without_structural_zeros"]]
claimed += [0j] * len(d["structural_zeros"])
scale = max([1.0] + [abs(e) for e in ev])
worst = 0.0
for c in claimed:
    i = min(range(len(ev)), key=lambda i: abs(ev[i] - c))
    worst = max(worst, abs(ev.pop(i) - c) / scale)
print(worst < 1e-6 and not ev)
PY
)
  if [ "$ok" != True ]; then wrong=$((wrong + 1)); finding "SILENT WRONG" "linearize whipple_bicycle $a: eigenvalues not those of the state matrix"; fi
done
echo "== 10. The output folder: refusals, full disks, folders in the place of files, links"
G="$WORK/good"
good() { # a completed run into $1 (g = 9.81) with the user's notes beside it
  rm -rf "$1"; "$BIN" simulate planar_four_bar --t-end 0.3 --out "$1" >/dev/null 2>&1
  echo "the user's" > "$1/notes.txt"
}
# Refused before they start: the folder byte for byte as it was (issue 53, item 5).
good "$G"; snap "$G" > "$WORK/before"
while read -r line; do
  eval "set -- $line"
  runs=$((runs + 1))
  timeout 60 "$BIN" "$@" --out "$G" >/dev/null 2>"$WORK/stderr"
  if [ "$?" = 101 ]; then panics=$((panics + 1)); finding PANIC "$line"; fi
  if ! snap "$G" | cmp -s - "$WORK/before"; then
    loss=$((loss + 1)); finding "DATA LOSS" "$line replaced the results: $(cat "$WORK/stderr")"; good "$G"; snap "$G" > "$WORK/before"; fi
done <<'CASES'
simulate planar_four_bar --set G=9.81
simulate planar_four_bar --set g=abc
simulate planar_four_bar --set m2=-1
simulate planar_fourbar
simulate missing.mech
simulate planar_four_bar --t-end 1e5
simulate planar_four_bar --integrator rk4 --step 1e-9
simulate planar_four_bar --samples-per-second 1e9
simulate planar_four_bar --rtol 2
simulate planar_four_bar --t-end 0
simulate planar_four_bar --init nope=1
simulate planar_four_bar --init th1=1e300
simulate planar_four_bar --bogus
inverse planar_four_bar --drive 'nope = t'
inverse planar_four_bar --drive 'th1 = t' --drive 'th1 = 2*t'
inverse planar_four_bar --drive 'th1 = t' --init th1=1
inverse planar_four_bar --drive 'th1 = t' --t-end 1e5
inverse cartesian_pendulum --drive 'x = 0.1*sin(t)' --t-end 10 --samples-per-second 5e5
linearize planar_fourbar
linearize planar_four_bar --set G=1
CASES
# A run whose files cannot be written: on a full disk (a 1 MiB tmpfs, when this may mount
# one) and beyond `ulimit -f`. The previous results must stay (item 4).
full() { # folder, then the command's prefix; three tries each
  good "$1"; snap "$1" > "$WORK/before"
  for try in 1 2 3; do
    runs=$((runs + 1))
    "${@:2}" "$BIN" simulate planar_four_bar --t-end 10 --samples-per-second 1000 --set g=3 --out "$1" >/dev/null 2>&1
    if ! snap "$1" | cmp -s - "$WORK/before"; then
      loss=$((loss + 1)); finding "DATA LOSS" "${*:2} full: the previous results are gone"; good "$1"; snap "$1" > "$WORK/before"; fi
  done
}
mkdir -p "$WORK/tmpfs"
if mount -t tmpfs -o size=1m tmpfs "$WORK/tmpfs" 2>/dev/null; then
  full "$WORK/tmpfs/run" env
  umount "$WORK/tmpfs"
else
  echo "(no tmpfs: mounting needs root; the ulimit -f case stands in)"
fi
full "$WORK/fsize" sh -c 'ulimit -f 64; trap "" XFSZ; exec "$0" "$@"'
# A folder where a result file goes: the swap completes or changes nothing (item 8).
for name in trajectory.csv summary.json th1.png th3.svg animation.html mechanism.png; do
  good "$G"; rm -f "$G/$name"; mkdir "$G/$name"; snap "$G" > "$WORK/before"
  runs=$((runs + 1))
  "$BIN" simulate planar_four_bar --t-end 0.3 --set g=3 --out "$G" >/dev/null 2>&1
  if ! snap "$G" | cmp -s - "$WORK/before"; then
    loss=$((loss + 1)); finding "DATA LOSS" "a folder named $name: the swap stopped midway"; fi
done
# A lock file that links elsewhere: the linked file must stay as it was (item 7).
for cmd in "simulate planar_four_bar --t-end 0.3" "inverse planar_four_bar --drive 'th1 = t' --t-end 0.3" "linearize whipple_bicycle"; do
  good "$G"; echo "the user's thesis" > "$WORK/thesis.tex"; ln -s "$WORK/thesis.tex" "$G/.mechanism.lock"
  runs=$((runs + 1))
  eval "\"$BIN\" $cmd --out \"$G\"" >/dev/null 2>&1
  if [ "$(cat "$WORK/thesis.tex")" != "the user's thesis" ]; then
    loss=$((loss + 1)); finding "DATA LOSS" "$cmd wrote through a linked lock file"; fi
  rm -f "$G/.mechanism.lock"
done
# A folder held by another run (flock on its lock file): every writing command refuses
# it (item 9).
for cmd in "simulate planar_four_bar --t-end 0.3" "inverse planar_four_bar --drive 'th1 = t' --t-end 0.3" "linearize whipple_bicycle"; do
  good "$G"; snap "$G" > "$WORK/before"
  runs=$((runs + 1))
  flock "$G/.mechanism.lock" sh -c "\"$BIN\" $cmd --out \"$G\"" >/dev/null 2>&1
  if ! snap "$G" -x | cmp -s - <(grep -v '^\./\.mechanism' "$WORK/before"); then
    unlocked=$((unlocked + 1)); finding "LOCK IGNORED" "$cmd wrote into a folder another run holds"; fi
done
echo "== 11. Signals mid-run: the previous results, or the new ones complete"
good "$G"
for trial in $(seq 1 20); do
  signal=$([ $((trial % 2)) = 0 ] && echo INT || echo TERM)
  delay=$(python3 -c "import random; print(round(random.uniform(0.0, 0.8), 3))")
  snap "$G" -x > "$WORK/before"
  runs=$((runs + 1))
  timeout -s "$signal" "$delay" "$BIN" simulate planar_four_bar --t-end 20 --samples-per-second 200 --set g=3 --out "$G" >/dev/null 2>&1
  now=$(snap "$G" -x)
  if [ "$now" = "$(cat "$WORK/before")" ]; then continue; fi
  complete=$(python3 - "$G" <<'PY'
import json, os, sys
folder = sys.argv[1]
d = json.load(open(os.path.join(folder, "summary.json")))
present = sorted(f for f in os.listdir(folder) if not f.startswith(".mechanism"))
print(d["status"] == "completed" and d["parameters"]["g"] == 3
      and sorted(d["files"] + ["notes.txt"]) == present)
PY
)
  if [ "$complete" != True ]; then
    loss=$((loss + 1)); finding "DATA LOSS" "SIG$signal after $delay s: neither the previous results nor the new ones complete"; fi
  good "$G"
done
echo "== 12. Long runs with default settings"
export EXPECT_RIGHT=1
# n_four_bar for 200 s at the default output rate (issue 53, item 10), the rest at one
# sample per second (the output rate changes where the steps end, not whether they can).
for a in "n_four_bar 200 100" "n_four_bar 1000 1" "planar_four_bar 10000 1" "chaplygin_sleigh 10000 1" "rolling_disc 200 1" "spatial_crank_slider 2000 1" "bricard 1000 1"; do
  set -- $a
  LIMIT=900 one simulate "$1" --t-end "$2" --samples-per-second "$3" --figures none --no-animation
  if [ "$code" != 0 ]; then stopped=$((stopped + 1)); finding "STOPPED EARLY" "$a s -> $err"; fi
done
unset EXPECT_RIGHT

echo "runs: $runs (exit 0: $exit0, 1: $exit1, 2: $exit2, other: $other)"
echo "panics: $panics"
echo "hangs: $hangs"
echo "silent NaNs: $nans"
echo "silent wrong answers: $wrong"
echo "misdiagnoses: $misdiagnoses"
echo "data lost: $loss"
echo "refusals without the file's place: $unlocated"
echo "writes into a folder another run holds: $unlocked"
echo "long runs stopped early: $stopped"
[ $((panics + hangs + nans + wrong + misdiagnoses + loss + unlocated + unlocked)) = 0 ]
