#!/usr/bin/env bash
# Build the Pinocchio C++ Panda benchmark against the headers and shared
# libraries shipped by the pip packages (cmeel layout):
#   pip install pin example-robot-data cmeel-eigen cmeel-urdfdom-headers
#
# Usage (from anywhere):
#   benches/baselines/pinocchio/build.sh            # build only
#   benches/baselines/pinocchio/build.sh --run      # build, then run once
# Builds two programs: panda_bench (the Panda's dynamics, panda_bench.cpp) and
# derivatives_bench (the derivatives of the dynamics on the Panda, the UR5 and Solo12,
# derivatives_bench.cpp).
# Environment:
#   TARGETS      which programs to build (default: "panda_bench derivatives_bench floating_bench";
#                floating_bench is the floating-base program of benches/floating_robot.py)
#   PYTHON       python interpreter whose site-packages hold the packages (python3)
#   CMEEL_PREFIX override the .../site-packages/cmeel.prefix directory
#   BUILD_DIR    output directory (default: ${TMPDIR:-/tmp}/mechanism-pinocchio-bench)
#   CXX          compiler (g++)
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../../.." && pwd)"
PYTHON="${PYTHON:-python3}"
CXX="${CXX:-g++}"
BUILD_DIR="${BUILD_DIR:-${TMPDIR:-/tmp}/mechanism-pinocchio-bench}"

if [[ -z "${CMEEL_PREFIX:-}" ]]; then
  CMEEL_PREFIX="$("$PYTHON" -c 'import sysconfig, os; print(os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix"))')"
fi
P="$CMEEL_PREFIX"
for f in "$P/include/pinocchio/parsers/urdf.hpp" \
         "$P/include/eigen3/Eigen/Core" \
         "$P/include/urdfdom_headers/urdf_model/model.h" \
         "$P/lib/libpinocchio_parsers.so"; do
  if [[ ! -e "$f" ]]; then
    echo "missing $f -- pip install pin cmeel-eigen cmeel-urdfdom-headers" >&2
    exit 1
  fi
done

mkdir -p "$BUILD_DIR"
TARGETS="${TARGETS:-panda_bench derivatives_bench floating_bench}"

# Compile definitions:
#  * BOOST_MPL_* / BOOST_FUSION_*: the INTERFACE_COMPILE_DEFINITIONS of the
#    pinocchio::pinocchio_headers CMake target (they change the joint variant
#    type, so they must match the prebuilt libraries).
#  * PINOCCHIO_URDFDOM_HEADERS_*: those of pinocchio::pinocchio_parsers.
#  * PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION is deliberately NOT defined: the
#    algorithms (crba, rnea, aba, ...) are instantiated in this translation
#    unit from the headers and compiled with -O3 -march=native; only the URDF
#    parsing (details::parseRootTree) comes from libpinocchio_parsers.so.
#  * EIGEN_MAX_ALIGN_BYTES=16 and EIGEN_MALLOC_ALREADY_ALIGNED=1: the pip
#    libraries are built for baseline x86-64 (SSE2: 16-byte alignment, heap
#    memory from plain malloc). Under -march=native (AVX/AVX-512) Eigen would
#    otherwise assume 32/64-byte alignment and switch to its "handmade"
#    aligned allocator, so an Eigen vector allocated inside
#    libpinocchio_parsers.so (plain malloc) and freed here crashes in free()
#    (observed: SIGSEGV in ~ModelTpl right after urdf::buildModel). With both
#    defines the objects crossing the boundary are ABI compatible; Eigen still
#    emits AVX/AVX-512 instructions, it only does not assume >16-byte alignment.
CXXFLAGS=(-O3 -march=native -DNDEBUG -std=c++17
  -DEIGEN_MAX_ALIGN_BYTES=16 -DEIGEN_MALLOC_ALREADY_ALIGNED=1
  -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30
  -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12
  -DPINOCCHIO_WITH_URDFDOM
  -DPINOCCHIO_URDFDOM_HEADERS_MAJOR_VERSION=3
  -DPINOCCHIO_URDFDOM_HEADERS_MINOR_VERSION=0
  -DPINOCCHIO_URDFDOM_HEADERS_PATCH_VERSION=0
  -DPANDA_URDF_DEFAULT="\"$ROOT/mechanisms/urdf/panda.urdf\""
  -I"$P/include" -I"$P/include/eigen3" -I"$P/include/urdfdom_headers" -I"$P/include/urdfdom"
  # GCC 12 emits false-positive -Wstringop-overread warnings from Eigen's AVX-512 code
  -Wno-stringop-overread)
LDFLAGS=(-L"$P/lib" -Wl,-rpath,"$P/lib"
  -lpinocchio_parsers -lpinocchio_default -lurdfdom_model -lconsole_bridge
  -lboost_filesystem -lboost_serialization)

# compile (slow, ~3-4 min on one core each) and link as separate steps
for T in $TARGETS; do
  set -x
  "$CXX" "${CXXFLAGS[@]}" -c "$HERE/$T.cpp" -o "$BUILD_DIR/$T.o"
  "$CXX" "$BUILD_DIR/$T.o" -o "$BUILD_DIR/$T" "${LDFLAGS[@]}"
  set +x
  echo "built $BUILD_DIR/$T" >&2
done

if [[ "${1:-}" == "--run" ]]; then
  for T in $TARGETS; do
    case "$T" in
      panda_bench) "$BUILD_DIR/panda_bench" "$ROOT/mechanisms/urdf/panda.urdf" ;;
      derivatives_bench)
        "$BUILD_DIR/derivatives_bench" panda "$ROOT/mechanisms/urdf/panda.urdf"
        "$BUILD_DIR/derivatives_bench" ur5 "$ROOT/mechanisms/urdf/ur5_robot.urdf"
        "$BUILD_DIR/derivatives_bench" solo12 "$ROOT/mechanisms/urdf/solo12.urdf" ;;
    esac
  done
fi
