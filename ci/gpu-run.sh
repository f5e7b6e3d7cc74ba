#!/usr/bin/env bash
# Runs on the GPU machine from the repository root (or anywhere with gpu-pack/ beside it): device info, the
# GPU-against-CPU tests, the PTX test, `swarf bench`, the criterion benches. Logs go to $OUT (or ./gpu-logs).
# Arguments select parts: info tests bench rings ptx plasticity runs criterion (default: all but ptx). Run from the repository root
# (the rings benchmark reads cases/rings.toml).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${OUT:-$PWD/gpu-logs}
mkdir -p "$out"
parts=${*:-info tests bench rings plasticity runs criterion}
export SWARF_REQUIRE_GPU=1
status=0
summary=()
run() { # name, command...
    local name=$1; shift
    local t0=$(date +%s)
    "$@" > "$out/$name.log" 2>&1
    local rc=$?
    local dt=$(( $(date +%s) - t0 ))
    summary+=("$(printf '%-12s %s (%ss)' "$name" "$([ $rc = 0 ] && echo ok || echo "FAILED rc=$rc")" "$dt")")
    [ $rc = 0 ] || status=1
    tail -n 40 "$out/$name.log"
}
echo "commit $(cat "$here/COMMIT")"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv,noheader 2>/dev/null | tee "$out/nvidia-smi.log"
for p in $parts; do
    case $p in
        info) run info "$here/swarf" --backend gpu info ;;
        tests) run test-gpu "$here/test-gpu" --test-threads=1 --nocapture
               run test-ptx "$here/test-ptx" ;;
        bench) run bench "$here/swarf" --backend gpu bench neighbours --sizes 1e6,4e6,16e6 --dims 2,3 --precision both ;;
        rings) run rings-gpu "$here/swarf" --backend gpu bench rings --precision both
               run rings-cpu "$here/swarf" --backend cpu bench rings --precision both --steps 20 ;;
        ptx) # sm_80 PTX (JIT-compiled for the device) against the sm_90 build, same workloads
             for t in sm_80 sm_90; do
                 SWARF_PTX_TARGET=$t run "neighbours-$t" "$here/swarf" --backend gpu bench neighbours --sizes 16e6 --dims 2,3
                 SWARF_PTX_TARGET=$t run "rings-$t" "$here/swarf" --backend gpu bench rings --nbox 400,800 --steps 2000
             done ;;
        plasticity) run plasticity "$here/swarf" --backend gpu bench plasticity --repeats 5 ;;
        runs) # the issue-4 scenes on the GPU: wall time and summary (final shape) of each
              runs_log() {
                  for sc in impact taylor-bar; do
                      for p in f64 f32; do
                          "$here/swarf" --backend gpu run "cases/$sc.toml" --precision $p --out "/tmp/swarf-runs/$sc-$p" || return 1
                          cat "/tmp/swarf-runs/$sc-$p/summary.json"
                          tail -n 2 "/tmp/swarf-runs/$sc-$p/energy.csv"
                      done
                  done
              }
              run runs runs_log ;;
        criterion) run criterion "$here/bench-neighbours" --bench --noplot ;;
    esac
done
echo "== summary =="
printf '%s\n' "${summary[@]}" | tee "$out/summary.log"
exit $status
