#!/usr/bin/env bash
# What a crate that depends on `mechanism` compiles, and how long its clean release build
# takes, for each way of depending on it:
#
#   benches/user-build/run.sh [BASELINE_COMMIT]
#
# A fresh library crate (user.rs: declares the seed with `mechanism!` and calls it) is built
# against a snapshot of this checkout with
#   - the default features,
#   - default-features = false, features = ["std", "interpreter"] (the run-time library),
#   - default-features = false (the no_std core),
# and against BASELINE_COMMIT (default 4ef3966, before the cargo features existed) with its
# defaults. Each build: its own empty target dir, sources fetched beforehand (untimed),
# `cargo build --release`, wall and CPU time (user + sys) from /usr/bin/time, and the
# number of crates `cargo tree -e normal` lists besides the user crate. Rounds are
# interleaved (variant order rotates) and the median is reported. Writes
# target/bench-results/user_build.md.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
base_commit="${1:-4ef3966}"
rounds="${ROUNDS:-3}"
work="$root/target/user-build"
out="$root/target/bench-results"
rm -rf "$work"
mkdir -p "$work/src-now" "$work/src-base" "$out"
tar -C "$root" --exclude=./target --exclude=./.git -cf - . | tar -C "$work/src-now" -xf -
git -C "$root" archive "$base_commit" | tar -C "$work/src-base" -xf -

variants=(defaults runtime no_std baseline)
dep_line() {
    case "$1" in
        defaults) echo "mechanism = { path = \"$work/src-now\" }" ;;
        runtime) echo "mechanism = { path = \"$work/src-now\", default-features = false, features = [\"std\", \"interpreter\"] }" ;;
        no_std) echo "mechanism = { path = \"$work/src-now\", default-features = false }" ;;
        baseline) echo "mechanism = { path = \"$work/src-base\" }" ;;
    esac
}
for v in "${variants[@]}"; do
    mkdir -p "$work/$v/src"
    cp "$here/user.rs" "$work/$v/src/lib.rs"
    # Each side's own declaration of the seed (the baseline's grammar has no `draw`).
    src="$work/src-now"
    [ "$v" = baseline ] && src="$work/src-base"
    cp "$src/mechanisms/spatial_crank_slider.mech" "$work/$v/"
    cat >"$work/$v/Cargo.toml" <<TOML
[package]
name = "user"
version = "0.0.0"
edition = "2024"
publish = false

[workspace]

[dependencies]
$(dep_line "$v")
TOML
    (cd "$work/$v" && cargo fetch -q)
done

declare -A wall cpu crates
for r in $(seq 1 "$rounds"); do
    for i in "${!variants[@]}"; do
        v="${variants[$(((i + r) % ${#variants[@]}))]}"
        rm -rf "$work/$v/target"
        (cd "$work/$v" && /usr/bin/time -f "%e %U %S" -o "$work/$v/time" \
            cargo build -q --release --offline >/dev/null 2>"$work/$v/build.log")
        read -r e u s <"$work/$v/time"
        wall[$v]+="$e "
        cpu[$v]+="$(echo "$u + $s" | bc) "
    done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
{
    echo "| dependency | crates besides the user's | clean release build, wall (s) | CPU, user + sys (s) |"
    echo "|---|---|---|---|"
    for v in baseline defaults runtime no_std; do
        n=$(cd "$work/$v" && cargo tree -q -e normal --prefix none --offline | sed 's/ (\*)//; s/ (proc-macro)//' \
            | awk '{print $1}' | sort -u | grep -vx user | wc -l)
        printf '| %s | %s | %s | %s |\n' "$v: \`$(dep_line "$v" | sed "s|$work/||")\`" "$n" \
            "$(echo "${wall[$v]}" | median)" "$(echo "${cpu[$v]}" | median)"
    done
    echo
    echo "Median of $rounds interleaved rounds; load average after the run: $(cut -d' ' -f1-3 /proc/loadavg) ($(nproc) cores)."
} | tee "$out/user_build.md"
