#!/usr/bin/env bash
# Issue 22 item 1, on the GPU machine from the repository root, carrying gpu-pack/ (ci/gpu-pack.sh) and original/
# (python3 ci/original/port.py): the original 2D code and swarf on the same GPU in the same call.
#   forces  the whole 1 mm reference cut, concurrently: the original (run-original.sh build dumps cut), swarf with
#           model = "mfree_iwf" with the original's tool placement, swarf's defaults; and swarf's state after the
#           original's dump steps (same placement and Δt) for `compare.py states`. Force means: compare.py forces.
#   replicas  whole 1 mm cuts of each code with the tool's speed × (1 + k·1e-7) (the cut is chaotic: this measures
#           the spread of a window's mean): the originals one after another (ORIG_REPS), swarf's mfree_iwf and
#           defaults (MFREE_REPS, DEFAULT_REPS) as separate processes beside them; orig-rep-k.tgz, swarf-rep-*.tgz
#   speed   the per-step time, one code at a time on an otherwise idle GPU: the original and swarf (mfree_iwf, same
#           Δt and steps) at 6k (30 rows, SPEED_STEPS_6K steps) and 150k (150 rows, SPEED_STEPS_150K steps).
# Everything goes to $OUT: side-by-side.log, the original's archives, swarf-*.tgz (forces.csv, summary.json,
# run.log, states/), speed.tsv.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
out=${OUT:-$root/side-by-side-out}
mkdir -p "$out"
exec > >(tee -a "$out/side-by-side.log") 2>&1
parts=${*:-forces replicas speed}
swarf=$root/gpu-pack/swarf
[ -x "$swarf" ] || { gunzip -f "$swarf.gz" && chmod +x "$swarf"; }
export SWARF_REQUIRE_GPU=1
work=${SBS_WORK:-/tmp/side-by-side} # SBS_WORK: another folder, for two invocations at once
mkdir -p "$work"
status=0
# The original's reference cut in swarf's frame (docs/original-code.md, "tool placement"): the edge's lowest point
# at (-32.873050250150927 um, 200 um) with the first column at x = 0 and the top row at y = 0.3 mm (its fillet's
# centre (17.126949749849073, 520) um against its first column at 50 um and top row at 600 um, read from its
# tool_000000.csv dump); its dt is 1.4473417988558209 ns (meta.json).
place=(--set 'tool.position=[-3.2873050250150927e-5, 2.0e-4]')
# ORIG_TOOL=1: the original's tool too (docs/original-code.md, "The thermal tool"): its extent from the edge's lowest
# point (0.4771 mm back, 0.4979 mm up; the scene's is 0.4132 x 0.431) and its thermal particles, the nodes of its
# bounding box inside it with one held layer (1 970 against the scene's 1 429 cell centres). ORIG_TOOL=shape: the
# extent alone; ORIG_TOOL=lattice: the sampling alone, on the scene's tool.
c2d_shape=(--set tool.length=4.771269497498491e-4 --set tool.height=4.978592683264774e-4)
c2d_lattice=(--set 'tool.thermal.lattice="nodes"' --set tool.thermal.fixed_width=1.03448275862069e-5)
case ${ORIG_TOOL:-0} in
    1) place+=("${c2d_shape[@]}" "${c2d_lattice[@]}") ;;
    shape) place+=("${c2d_shape[@]}") ;;
    lattice) place+=("${c2d_lattice[@]}") ;;
esac
dt=1.4473417988558209e-9
ref=cases/cutting/reference-cut.toml
ref150=cases/cutting/reference-cut-150k.toml

swarf_run() { # name, scene, args...: a swarf GPU run into $work/name, archived into $out/swarf-name.tgz
    local name=$1 scene=$2; shift 2
    local t0=$(date +%s.%N)
    "$swarf" --backend gpu run "$scene" --quiet --out "$work/$name" "$@" > "$work/$name.stdout" 2>&1
    local rc=$?
    local t1=$(date +%s.%N)
    echo "== swarf $name: rc $rc, wall $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }') s"
    tail -n 3 "$work/$name/run.log" 2>/dev/null; cat "$work/$name.stdout"
    [ -f "$work/$name/summary.json" ] && python3 -c 'import json,sys
s = json.load(open(sys.argv[1]))
print({k: s[k] for k in ("particles", "steps", "dt_s", "wall_time_s") if k in s})' "$work/$name/summary.json" 2>/dev/null
    tar czf "$out/swarf-$name.tgz" --exclude='*.vtu' --exclude='*.h5' --exclude='checkpoint*' -C "$work" "$name" 2>/dev/null
    return $rc
}

forces() {
    (states_original; OUT=$out bash ci/original/run-original.sh cut > "$work/original.stdout" 2>&1) &
    local orig=$!
    swarf_run mfree-cut "$ref" --set 'model="mfree_iwf"' "${place[@]}" &
    local a=$!
    swarf_run default-cut "$ref" &
    local b=$!
    states_runs &
    local c=$!
    wait $a $b $c || status=1
    wait $orig || status=1
    tail -n 40 "$work/original.stdout"
    if [ -d /tmp/swarf-original/cut ]; then
        for m in mfree-cut default-cut; do
            echo "== compare.py forces: original against swarf $m"
            python3 ci/original/compare.py forces --orig /tmp/swarf-original/cut --swarf "$work/$m" \
                --json "$out/forces-$m.json" || status=1
        done
    fi
    states_compare
}

# The steps whose state both codes write: the set-up at rest, then around the first contact (the original's at step
# 7737: its rake face starts 12.4 um clear and moves 1.689 nm a step), 1, 10 and 100 steps after it, and later.
steps=${STATE_STEPS:-0,1,10,100,7736,7737,7738,7747,7837,8737,10000,12000,15000,20000}
last_step=${steps##*,}

states_runs() { # swarf's state after the original's dump steps, the original's placement and Δt, both models
    local end
    end=$(python3 -c "print(($last_step + 0.5) * $dt)")
    swarf_run mfree-states "$ref" --set 'model="mfree_iwf"' "${place[@]}" --set time.dt=$dt --set time.end=$end \
        --state-at "$steps" &
    local c=$!
    swarf_run default-states "$ref" "${place[@]}" --set time.dt=$dt --set time.end=$end --state-at "$steps"
    wait $c
}

states_original() { # the original's dumps at the same steps
    OUT=$out DUMP_STEPS=$last_step DUMPS=$steps bash ci/original/run-original.sh build dumps > "$work/dumps.stdout" 2>&1
    tail -n 8 "$work/dumps.stdout"
}

states_compare() {
    [ -d /tmp/swarf-original/dumps ] || return 0
    for m in mfree-states default-states; do
        echo "== compare.py states: original against swarf $m"
        python3 ci/original/compare.py states --orig /tmp/swarf-original/dumps --swarf "$work/$m/states" \
            --json "$out/states-$m.json" || status=1
    done
}

replicas() { # replicas k: the tool's speed × (1 + k·1e-7); ORIG_REPS, MFREE_REPS, DEFAULT_REPS list the k of each code
    # (default 0 1 2 3 each). The originals run one after another: side by side on one GPU they slow each other
    # about 18-fold (4 at once, H100); swarf's runs are separate processes, concurrent with them.
    local k
    vel() { python3 -c "print(repr(1.166666592e-4 * (1 + $1 * 1e-7)))"; } # cm/µs
    # Built only when originals run: invocations of swarf's runs alone (ORIG_REPS="") beside one that runs them would
    # otherwise all build into the same folder at once.
    if [ -n "${ORIG_REPS-0 1 2 3}" ] && [ ! -x /tmp/swarf-original/build/mfree_gpu ]; then
        OUT=$out bash ci/original/run-original.sh build > /dev/null 2>&1
    fi
    (
        for k in ${ORIG_REPS-0 1 2 3}; do
            OUT=$work/rep-$k ORIG_ARGS="-v $(vel $k)" FORCE_EVERY=100 WORK=$work/orig-rep-$k \
                BUILD_DIR=/tmp/swarf-original/build bash ci/original/run-original.sh cut > "$work/orig-rep-$k.stdout" 2>&1
            tar czf "$out/orig-rep-$k.tgz" -C "$work/orig-rep-$k/cut" forces.csv meta.json timing.json wall.txt stdout.log
        done
    ) &
    local orig=$! pids=()
    for k in ${MFREE_REPS-0 1 2 3}; do
        swarf_run "rep-mfree-$k" "$ref" --set 'model="mfree_iwf"' "${place[@]}" \
            --set "tool.velocity=[$(python3 -c "print(repr($(vel $k) * 1e4))"), 0.0]" > /dev/null &
        pids+=($!)
    done
    for k in ${DEFAULT_REPS-0 1 2 3}; do
        swarf_run "rep-default-$k" "$ref" --set "tool.velocity=[$(python3 -c "print(repr($(vel $k) * 1e4))"), 0.0]" \
            > /dev/null &
        pids+=($!)
    done
    [ ${#pids[@]} -gt 0 ] && { wait "${pids[@]}" || status=1; }
    wait $orig || status=1
}

speed() { # one code at a time: per-step wall time and the original's own step-loop time (timing.json)
    local n6=${SPEED_STEPS_6K:-60000} n150=${SPEED_STEPS_150K:-3000}
    echo -e "size\tcode\tparticles\tsteps\twall_s\tloop_s\tus_per_step" > "$out/speed.tsv"
    local rows steps scene tag speed_tool=()
    # ORIG_TOOL=1: the original's tool and its node sampling, so that both codes carry the same tool particles
    # (the held band does not change the work).
    [ "${ORIG_TOOL:-0}" = 1 ] && speed_tool=("${c2d_shape[@]}" --set 'tool.thermal.lattice="nodes"')
    for cfg in "30 $n6 $ref 6k" "150 $n150 $ref150 150k"; do
        read -r rows steps scene tag <<< "$cfg"
        local od=$work/orig-$tag/cut
        OUT=$work/orig-speed-$tag ORIG_ARGS="-n $rows" CUT_STEPS=$steps FORCE_EVERY=1000 WORK=$work/orig-$tag \
            BUILD_DIR=/tmp/swarf-original/build bash ci/original/run-original.sh cut > "$work/orig-speed-$tag.stdout" 2>&1
        tail -n 12 "$work/orig-speed-$tag.stdout"
        cp "$od/timing.json" "$out/orig-timing-$tag.json" 2>/dev/null
        cp "$od/meta.json" "$out/orig-meta-$tag.json" 2>/dev/null
        python3 - "$od" "$tag" "$steps" >> "$out/speed.tsv" <<'PY' || status=1
import json, sys
d, tag, steps = sys.argv[1], sys.argv[2], int(sys.argv[3])
t = json.load(open(d + "/timing.json"))
wall = open(d + "/wall.txt").read().split()[-1]
print(f"{tag}\toriginal\t{t['particles']}\t{t['steps']}\t{wall}\t{t['gpu_seconds']}\t{t['us_per_step']}")
PY
        # swarf with the original's formulas, Δt and step count (its dt in meta.json is in µs)
        local dts
        dts=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["dt"] * 1e-6)' "$od/meta.json") || { status=1; continue; }
        local t0=$(date +%s.%N)
        "$swarf" --backend gpu run "$scene" --quiet --out "$work/speed-$tag" --set 'model="mfree_iwf"' "${speed_tool[@]}" \
            --set time.dt="$dts" --set time.end="$(python3 -c "print(($steps + 0.5) * $dts)")" --set output.every=1.0 \
            > "$work/speed-$tag.stdout" 2>&1 || status=1
        local t1=$(date +%s.%N)
        python3 - "$work/speed-$tag/summary.json" "$tag" "$t0" "$t1" >> "$out/speed.tsv" <<'PY' || status=1
import json, sys
s = json.load(open(sys.argv[1]))
wall = float(sys.argv[4]) - float(sys.argv[3])
n, loop = s["steps"], s["wall_time_s"]
print(f"{sys.argv[2]}\tswarf-mfree_iwf\t{s.get('particles', '')}\t{n}\t{wall:.2f}\t{loop}\t{1e6 * loop / n:.4f}")
PY
        tail -n 3 "$work/speed-$tag/run.log" 2>/dev/null; cat "$work/speed-$tag.stdout"
    done
    cat "$out/speed.tsv"
}

for p in $parts; do
    case $p in
    forces) forces ;;
    # (never a bare `wait`: it would also wait for this script's own tee, the process substitution above)
    states) states_original & o=$!; states_runs; wait $o; states_compare ;;
    replicas) replicas ;;
    speed) speed ;;
    *) echo "unknown part $p (forces states replicas speed)"; status=1 ;;
    esac
done
echo "== side-by-side done, status $status"
exit $status
