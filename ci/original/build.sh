#!/usr/bin/env bash
# Builds the ported original code (original/, made by ci/original/port.py) with nvcc into original/build/mfree_gpu
# (or $BUILD_DIR/mfree_gpu).
# No downloads: GLM is in original/include. Flags follow the original's Release makefile (-O3, no relocatable
# device code, static cudart), with C++17 (CUDA 13's thrust needs it; the original said C++11), one GPU target
# (ARCH, default sm_90 for H100/H200), -x cu for the .cpp files too, and without -lnvidia-ml (the port
# removed NVML).
#   NVCC=nvcc ARCH=sm_90 JOBS=16 bash ci/original/build.sh          # build and link
#   COMPILE_ONLY=1 bash ci/original/build.sh                         # objects only (a machine without libcudart)
#   LINK_FLAGS=-L/path/to/cuda/lib bash ci/original/build.sh          # pip's nvcc keeps its libraries in lib/
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
orig=${ORIG_DIR:-$root/original}
src=$orig/src
bld=${BUILD_DIR:-$orig/build}
NVCC=${NVCC:-nvcc}
ARCH=${ARCH:-sm_90}
JOBS=${JOBS:-$(nproc)}
[ -f "$src/swarf_port.cu" ] || { echo "build.sh: $src is not ported: run python3 ci/original/port.py" >&2; exit 1; }
mkdir -p "$bld"
"$NVCC" --version | tail -n 2
flags=(-O3 -std=c++17 -arch="$ARCH" --relocatable-device-code=false -D__NV_NO_VECTOR_DEPRECATION_DIAG
       -I"$orig/include" -I"$src" -w)
export NVCC bld src
export FLAGS="${flags[*]}"
compile() { # one source file -> build/<name>.o. The .cpp files too go through nvcc's CUDA front end (-x cu):
    # they include thrust's CUDA headers, which CUDA 13's CCCL no longer lets a plain host compiler parse (the
    # original's makefile had -x c++ for them). Their code is host code either way, compiled by the same g++.
    local f=$1 base lang=cu
    base=$(basename "$f")
    # shellcheck disable=SC2086
    if "$NVCC" $FLAGS --compile -x "$lang" -o "$bld/${base%.*}.o" "$f" > "$bld/${base%.*}.log" 2>&1; then
        echo "  ok    $base"
    else
        echo "  FAIL  $base"; cat "$bld/${base%.*}.log"; return 1
    fi
}
export -f compile
t0=$(date +%s)
ls "$src"/*.cu "$src"/*.cpp | xargs -P "$JOBS" -I{} bash -c 'compile "$@"' _ {}
echo "compiled in $(( $(date +%s) - t0 )) s"
if [ -z "${COMPILE_ONLY:-}" ]; then
    # shellcheck disable=SC2086
    "$NVCC" -arch="$ARCH" --cudart static --relocatable-device-code=false -o "$bld/mfree_gpu" "$bld"/*.o ${LINK_FLAGS:-}
    echo "linked $bld/mfree_gpu"
fi
