#!/usr/bin/env bash
# What a user's `mechanism!(urdf = ...)` of a large robot costs rustc (issue 50, item 4):
#
#   benches/compile-time/robots.sh [ROUNDS]
#
# Talos of example-robot-data (`talos_full_v2.urdf`, found in the Python interpreter
# $PYTHON, python3 by default, that has the package installed) in two variants:
#   talos44  every joint free: 44 coordinates, the 12 <mimic> rows of its grippers;
#   talos30  the 14 gripper joints locked: 30 coordinates, no constraint row;
# and the Panda of mechanisms/urdf for scale. For each, a library crate holding the one
# declaration (and a function calling its methods, so that `cargo build` generates their
# code) is built against a snapshot of this checkout; its dependencies are built once,
# untimed; then each round touches the crate and runs `cargo check --release` and
# `cargo build --release` under /usr/bin/time -v: peak resident memory (rustc, the largest
# process) and CPU time (user + sys), median over ROUNDS (default 1). The crates set the
# README's `[profile.release.package.mechanism-codegen] opt-level = 3`, so the derivation
# inside the macro runs optimised. Writes <target>/bench-results/robots_build.md.
set -euo pipefail
rounds="${1:-1}"
root="$(cd "$(dirname "$0")/../.." && pwd)"
target="$(cd "$root" && mkdir -p "${CARGO_TARGET_DIR:-target}" && cd "${CARGO_TARGET_DIR:-target}" && pwd)"
work="$target/compile-time/robots"
out="$target/bench-results"
mkdir -p "$work" "$out"
python="${PYTHON:-python3}"
robots="$("$python" -c 'import cmeel, os; print(os.path.join(cmeel.__path__[0], "..", "cmeel.prefix", "share", "example-robot-data", "robots"))' 2>/dev/null || true)"
talos="$robots/talos_data/robots/talos_full_v2.urdf"
if [ ! -f "$talos" ]; then
    echo "talos_full_v2.urdf not found (pip install example-robot-data into $python)" >&2
    exit 1
fi
talos="$(cd "$(dirname "$talos")" && pwd)/$(basename "$talos")"

# A snapshot of the checkout, so that edits during the run cannot trigger rebuilds.
snap="$work/snapshot"
rm -rf "$snap"
mkdir -p "$snap"
tar -C "$root" --exclude=./target --exclude=./.git -cf - . | tar -C "$snap" -xf -

grippers=""
for side in left right; do
    for j in joint inner_double_joint fingertip_1_joint fingertip_2_joint motor_single_joint inner_single_joint fingertip_3_joint; do
        grippers="$grippers\"gripper_${side}_$j\", "
    done
done
declare -A decl=(
    [panda]="urdf = \"$snap/mechanisms/urdf/panda.urdf\", lock = [\"panda_finger_joint1\", \"panda_finger_joint2\"], name = Robot"
    [talos30]="urdf = \"$talos\", lock = [$grippers], name = Robot"
    [talos44]="urdf = \"$talos\", name = Robot"
)
variants=(panda talos30 talos44)
# One shared target dir: the dependencies are built once; each variant is its own package.
export CARGO_TARGET_DIR="$work/target"
export CARGO_INCREMENTAL=0
for v in "${variants[@]}"; do
    mkdir -p "$work/$v/src"
    cat >"$work/$v/Cargo.toml" <<TOML
[package]
name = "robot-$v"
version = "0.0.0"
edition = "2024"
publish = false

[workspace]

[dependencies]
mechanism = { package = "mechanism-dynamics", path = "$snap", default-features = false, features = ["std"] }

# The README's advice for large mechanisms built with --release: the derivation optimised.
[profile.release.package.mechanism-codegen]
opt-level = 3
TOML
    cat >"$work/$v/src/lib.rs" <<RUST
//! One robot imported from its URDF, and every method called, so that a build generates
//! their code.
use mechanism::Mechanism;
use mechanism::nalgebra::SVector;

mechanism::mechanism!(${decl[$v]});

/// Calls the generated methods once each.
pub fn touch<const N: usize, const M: usize>(r: &impl Mechanism<N, M>, x: f64) -> f64 {
    let q = SVector::<f64, N>::from_element(x);
    let e = r.evaluate(0.0, &q, &q);
    let (m, b) = r.mass_and_bias(0.0, &q, &q);
    r.mass_matrix(&q).sum()
        + r.coriolis_forces(&q, &q).sum()
        + r.gravity(&q).sum()
        + r.inverse_dynamics(0.0, &q, &q, &q).sum()
        + r.frame_jacobian(0, &q).map_or(0.0, |j| j.sum())
        + r.frame_placement(0, &q).map_or(0.0, |(r, p)| r.sum() + p.sum())
        + r.residual_tangent(0.0, &q, &q, &q, &SVector::<f64, M>::zeros()).map_or(0.0, |(k, d)| k.sum() + d.sum())
        + e.mass.sum()
        + m.sum()
        + b.sum()
}

/// The robot's methods, monomorphised.
pub fn run(x: f64) -> f64 {
    touch(&Robot::default(), x)
}
RUST
done

# Dependencies (untimed): a build of the smallest variant brings every dependency.
(cd "$work/panda" && cargo build -q --release >/dev/null)
(cd "$work/panda" && cargo check -q --release >/dev/null)

measure() { # variant, cargo command: prints "peak_MB cpu_s"
    local v="$1" cmd="$2" peaks=() cpus=()
    for _ in $(seq 1 "$rounds"); do
        touch "$work/$v/src/lib.rs"
        (cd "$work/$v" && /usr/bin/time -v -o "$work/$v/time.txt" cargo "$cmd" -q --release >/dev/null 2>"$work/$v/log.txt") || {
            echo "cargo $cmd of $v failed: see $work/$v/log.txt" >&2
            exit 1
        }
        peaks+=("$(awk -F': ' '/Maximum resident/ {printf "%.0f", $2 / 1024}' "$work/$v/time.txt")")
        cpus+=("$(awk -F': ' '/User time/ {u = $2} /System time/ {s = $2} END {printf "%.1f", u + s}' "$work/$v/time.txt")")
    done
    local mid=$(((rounds - 1) / 2 + 1))
    echo "$(printf '%s\n' "${peaks[@]}" | sort -n | sed -n "${mid}p") $(printf '%s\n' "${cpus[@]}" | sort -n | sed -n "${mid}p")"
}

{
    echo "| robot | coordinates | cargo check --release: peak (MB) | CPU (s) | cargo build --release: peak (MB) | CPU (s) |"
    echo "|---|---:|---:|---:|---:|---:|"
    for v in "${variants[@]}"; do
        read -r cp cc <<<"$(measure "$v" check)"
        read -r bp bc <<<"$(measure "$v" build)"
        case "$v" in panda) n=7 ;; talos30) n=30 ;; talos44) n=44 ;; esac
        printf '| %s | %s | %s | %s | %s | %s |\n' "$v" "$n" "$cp" "$cc" "$bp" "$bc"
    done
    echo
    echo "Median of $rounds round(s); load average after the run: $(cut -d' ' -f1-3 /proc/loadavg) ($(nproc) cores)."
} | tee "$out/robots_build.md"
