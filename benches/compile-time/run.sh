#!/usr/bin/env bash
# The macro's added compile time (issue 6, item 2), on demand:
#
#   benches/compile-time/run.sh
#
# Builds this tiny crate (own target dir: <target>/compile-time, where <target> is
# CARGO_TARGET_DIR when set, else the checkout's target/) with no declaration, with the
# 16-bar chain and with the 32-bar chain, under the default dev profile (proc-macros built
# at opt-level 0) and with `[profile.dev.build-override] opt-level = 3` (set here through
# CARGO_PROFILE_DEV_BUILD_OVERRIDE_OPT_LEVEL), and also `--release`. Dependencies are built
# once per variant, untimed; each timed build recompiles only this crate (touch + build),
# median of 3. Writes <target>/bench-results/compile_time.md.
#
# The sources are first copied to target/compile-time/snapshot (without target/ and .git/),
# so that edits in the checkout during the run cannot trigger rebuilds of the path
# dependencies inside a timed build.
set -euo pipefail
src_here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$src_here/../.." && pwd)"
target="$(cd "$root" && mkdir -p "${CARGO_TARGET_DIR:-target}" && cd "${CARGO_TARGET_DIR:-target}" && pwd)"
export CARGO_TARGET_DIR="$target/compile-time"
out="$target/bench-results"
mkdir -p "$out" "$CARGO_TARGET_DIR"
snap="$CARGO_TARGET_DIR/snapshot"
rm -rf "$snap"
mkdir -p "$snap"
tar -C "$root" --exclude=./target --exclude=./.git -cf - . | tar -C "$snap" -xf -
here="$snap/benches/compile-time"
cd "$here"

timed() { # median wall time (s) of 3 builds of this crate only
    local ts=()
    for _ in 1 2 3; do
        touch src/main.rs
        local t0 t1
        t0=$(date +%s.%N)
        cargo build "$@" 2>"$CARGO_TARGET_DIR/last.log" >/dev/null
        if [ "$(grep -c Compiling "$CARGO_TARGET_DIR/last.log")" -ne 1 ]; then
            echo "timed build compiled more than this crate: see $CARGO_TARGET_DIR/last.log" >&2
            exit 1
        fi
        t1=$(date +%s.%N)
        ts+=("$(echo "$t1 - $t0" | bc)")
    done
    printf '%s\n' "${ts[@]}" | sort -n | sed -n 2p
}

# Debug info of the emitted straight-line code nests one lexical scope per `let`; at N = 32
# LLVM's DWARF writer recurses past rustc's default 8 MiB stack (rustc SIGSEGV, "overflowed
# its stack"). Record whether that still happens, then time with a larger stack.
# Clean builds of this crate: no incremental reuse of the previous (identical) build.
export CARGO_INCREMENTAL=0
export CARGO_PROFILE_DEV_BUILD_OVERRIDE_OPT_LEVEL=3
cargo build -q --features chain16 >/dev/null 2>&1 || true
touch src/main.rs
if cargo build -q --features chain32 >/dev/null 2>"$CARGO_TARGET_DIR/crash.log"; then
    crash="builds with the default stack"
else
    crash="rustc crashes (stack overflow in LLVM debug info; see $CARGO_TARGET_DIR/crash.log)"
fi
export RUST_MIN_STACK=67108864

{
    echo "Default dev build (debuginfo = 2) of the N = 32 declaration: $crash."
    echo "Timed builds below run with RUST_MIN_STACK=67108864 and CARGO_INCREMENTAL=0."
    echo
    echo "| profile | no declaration (s) | + chain N = 16 (s) | + chain N = 32 (s) | added by N = 16 | added by N = 32 |"
    echo "|---|---|---|---|---|---|"
    for variant in "dev, build-override opt-level 0:0:" "dev, build-override opt-level 3:3:" "release (build-override opt-level 3):3:--release"; do
        IFS=: read -r label level flag <<<"$variant"
        export CARGO_PROFILE_DEV_BUILD_OVERRIDE_OPT_LEVEL="$level"
        export CARGO_PROFILE_RELEASE_BUILD_OVERRIDE_OPT_LEVEL="$level"
        # Warm-up: dependencies for this variant (untimed).
        cargo build -q $flag --features chain16,chain32 >/dev/null 2>&1 || cargo build $flag --features chain16,chain32
        base=$(timed $flag)
        c16=$(timed $flag --features chain16)
        c32=$(timed $flag --features chain32)
        printf '| %s | %.2f | %.2f | %.2f | %.2f | %.2f |\n' "$label" "$base" "$c16" "$c32" \
            "$(echo "$c16 - $base" | bc)" "$(echo "$c32 - $base" | bc)"
    done
    echo
    echo "Load average after the run: $(cut -d' ' -f1-3 /proc/loadavg) ($(nproc) cores)."
} | tee "$out/compile_time.md"
