#!/usr/bin/env bash
# Runs on the GPU machine, from the repository root, with the ported original code carried in original/ (made on
# a machine with the mirror by `python3 ci/original/port.py`): builds it with nvcc, then
#   dumps  the state dumps: ORIG_STEPS=$DUMP_STEPS steps of the reference cut, the whole particle state after the
#          steps in $DUMPS, the tool force every step (seconds). The tool first touches the workpiece at
#          step 7737 (its rake face starts 12.4 µm clear and moves 1.689 nm a step), so steps 1, 10, 100 only
#          check the set-up at rest; the later dumps catch the first contact and 1, 10, 100 steps after it;
#   cut    the reference cut over $CUT_MM mm (default 1 mm, about 592 000 steps, about 200 s on an H200) or
#          $CUT_STEPS steps, the tool force every $FORCE_EVERY steps, timed.
# Everything goes to $OUT (default ./original-out): run-original.log, build.log, original-dumps.tar.gz,
# original-cut.tar.gz (each at most a few MiB). The binary is built in $BUILD_DIR (default
# /tmp/swarf-original/build), so that on a warm machine a later call can run `cut` alone without rebuilding.
#   bash ci/original/run-original.sh                       # build dumps cut
#   CUT_MM=0.2 bash ci/original/run-original.sh dumps cut  # a short cut
# Settings (environment): ARCH (sm_90), NVCC (nvcc), JOBS (nproc), CUT_MM (1), CUT_STEPS, FORCE_EVERY (100),
# DUMP_STEPS (20000), DUMPS (0,1,10,100,7736,7737,7738,7747,7837,8737,10000,12000,15000,20000), VTK (0: no frames; 1: the original's 135 ASCII VTK frames, not packed),
# ORIG_ARGS (extra arguments to the original's getopt: -r rake -c clearance -f fillet[cm] -v speed[cm/us]
# -n rows -q feed[cm]).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
out=${OUT:-$root/original-out}
mkdir -p "$out"
exec > >(tee -a "$out/run-original.log") 2>&1
parts=${*:-build dumps cut}
work=${WORK:-/tmp/swarf-original}
# The build goes outside original/, so that a later call that carries original/ again keeps it (warm machine).
export BUILD_DIR=${BUILD_DIR:-$work/build}
bin=$BUILD_DIR/mfree_gpu
export JOBS=${JOBS:-$(nproc)}
status=0

echo "== run-original.sh $(date -u +%FT%TZ): parts: $parts"
command -v nvidia-smi > /dev/null && nvidia-smi -L || true
[ -f original/src/swarf_port.cu ] || { echo "original/ is not ported or not carried: python3 ci/original/port.py, carry original" >&2; exit 1; }
cat original/PORT_INFO.json | head -n 4 || true

pack() { # archive name, folder: tar.gz of the folder's small outputs into $out, split into 15 MiB parts
    # (NAME.partaa, ...; join with cat) when larger, since a returned file may be at most 16 MiB
    local name=$1 dir=$2
    [ -d "$dir" ] || return 0
    tar czf "$out/$name" -C "$dir" --exclude='results/vtk_*' --exclude='*.vtk' .
    if [ "$(stat -c %s "$out/$name")" -gt $((15 * 1024 * 1024)) ]; then
        split -b 15m "$out/$name" "$out/$name.part" && rm "$out/$name"
    fi
    ls -la "$out/$name"*
}

build() {
    echo "== build into $BUILD_DIR"
    if ! ARCH=${ARCH:-sm_90} bash ci/original/build.sh > "$out/build.log" 2>&1; then
        tail -n 60 "$out/build.log"; echo "build FAILED"; exit 1
    fi
    tail -n 4 "$out/build.log"
}

run_part() { # folder, then VAR=value settings for the original; times the run
    local dir=$1; shift
    [ -x "$bin" ] || build
    rm -rf "$dir"; mkdir -p "$dir"
    local t0 t1
    t0=$(date +%s.%N)
    # shellcheck disable=SC2086
    if env ORIG_OUT="$dir" "$@" "$bin" ${ORIG_ARGS:-} > "$dir/stdout.log" 2>&1; then
        t1=$(date +%s.%N)
        awk -v a="$t0" -v b="$t1" 'BEGIN { printf "wall seconds: %.2f\n", b - a }' | tee "$dir/wall.txt"
    else
        echo "FAILED (rc $?): tail of $dir/stdout.log"; status=1
    fi
    grep -E "timestep chosen|calculating with|last step|gpu time|estimated time|invalidated" "$dir/stdout.log" | head -n 20 || true
    tail -n 5 "$dir/stdout.log"
}

for part in $parts; do
    case $part in
    build) build ;;
    dumps)
        dumps=${DUMPS:-0,1,10,100,7736,7737,7738,7747,7837,8737,10000,12000,15000,20000}
        echo "== dumps: ${DUMP_STEPS:-20000} steps, state after steps $dumps"
        run_part "$work/dumps" ORIG_STEPS="${DUMP_STEPS:-20000}" ORIG_DUMPS="$dumps" ORIG_FORCE_EVERY=1 ORIG_VTK=0 \
            ORIG_FRAME_EVERY=100
        head -n 3 "$work/dumps/forces.csv" || true; tail -n 2 "$work/dumps/forces.csv" || true
        pack original-dumps.tar.gz "$work/dumps"
        ;;
    cut)
        if [ -n "${CUT_STEPS:-}" ]; then len=(ORIG_STEPS="$CUT_STEPS"); else len=(ORIG_CUT_MM="${CUT_MM:-1}"); fi
        echo "== cut: ${len[*]}, forces every ${FORCE_EVERY:-100} steps, vtk ${VTK:-0}"
        run_part "$work/cut" "${len[@]}" ORIG_DUMPS=none ORIG_FORCE_EVERY="${FORCE_EVERY:-100}" ORIG_VTK="${VTK:-0}"
        cat "$work/cut/timing.json" 2>/dev/null || true
        pack original-cut.tar.gz "$work/cut"
        ;;
    *) echo "unknown part $part (build dumps cut)"; status=1 ;;
    esac
done
echo "== done, status $status"
exit $status
