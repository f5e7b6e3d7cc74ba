#!/usr/bin/env bash
# Runs on the GPU machine from the repository root (or anywhere with gpu-pack/ beside it): device info, the
# GPU-against-CPU tests, the PTX test, `swarf bench`, the criterion benches. Logs go to $OUT (or ./gpu-logs).
# Arguments select parts: info firstrun tests hard regs fast bench step rings ptx plasticity runs criterion cutting ladder sweep fine
# mpm26 mpm26b mpmgrid mpm025ck mpmv1frag mpmv8fine mpmv8path mpmv8long mpmv14 mpmv10 mpmv78 mpmv5fine mpmsweep mpmdamp mpmv mpmedge mpmv5 ensemble bgensemble waitensemble earlystop holdout mufit identify v0300noise ck45 contactlaws contactlong table22 switches22 mu22 damage25 damage25fine shtb25 gf25 ducobugf taylor24 tool3d tools24 cspm24 nonfinite24 mill24 wheel24 wide24 grainres ortho5 orthosw whole150k bg150k wait150k make150k bgmake150k ncu ncufrom cutsteps fromcut refcut f32fail abfrom abstep abdamage abregs abblock abenv ncusrc refvar
# (default: info tests bench rings plasticity runs criterion). Run from the repository root
# (the rings benchmark reads cases/rings.toml).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# The tests and scenes read cases/ relative to the repository root: run from there whatever the caller's folder.
[ -d "$here/../cases" ] && cd "$here/.."
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
# `swarf chip` on the last frame of every run with frames below $1, and pictures (damage, plastic strain) of it in
# $2/<run path with - for />-<field>/.
chip_report() {
    local r
    mkdir -p "$2"
    for r in $(find "$1" -name particles.pvd | sort); do
        r=$(dirname "$r"); echo "== chip ${r#$1/}"; "$here/swarf" chip "$r" 2>&1 | tail -n 24
        for fld in damage eps; do
            "$here/swarf" render "$r" --field $fld --frame last \
                --out "$2/$(echo ${r#$1/} | tr '/' '-')-$fld" 2>&1 | tail -n 1
        done
    done
}

# The table of damage runs below $1 (docs/damage.md): forces (the steady window of summary.json, else the second half
# of forces.csv), chip thickness, segmentation, its degree and pitch, damaged and initiated volume, `swarf neck`'s
# fracture.
damage_table() {
    python3 - "$1" <<'PY'
import csv, glob, json, os, sys
root = sys.argv[1]
def last(path, col):
    try:
        rows = list(csv.DictReader(open(path)))
        return float(rows[-1][col]) if rows else None
    except (OSError, KeyError, ValueError):
        return None
def half_mean(path, col):
    try:
        v = [float(r[col]) for r in csv.DictReader(open(path))]
        v = v[len(v) // 2:]
        return sum(v) / len(v) if v else None
    except (OSError, KeyError, ValueError):
        return None
def f(x, fmt="{:.4g}"):
    return "–" if x is None else fmt.format(x)
print("| run | t_end [s] | steps | wall [s] | F_c [N/mm] | F_f [N/mm] | h [µm] | segmentation | degree | pitch [µm] | damaged volume | initiated volume | fracture |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for run in sorted(os.path.dirname(p) for p in glob.glob(root + "/**/energy.csv", recursive=True)):
    s = {}
    try:
        s = json.load(open(run + "/summary.json"))
    except (OSError, ValueError):
        pass
    seg = ((s.get("cutting") or {}).get("segments") or {})
    fc, ff = s.get("fc_n_per_mm"), s.get("ff_n_per_mm")
    if fc is None:
        fc, ff = half_mean(run + "/forces.csv", "fc_n_per_mm"), half_mean(run + "/forces.csv", "ff_n_per_mm")
    neck = "–"
    if os.path.exists(run + "/neck.json"):
        n = json.load(open(run + "/neck.json"))
        neck = "none" if not n.get("fractured") else "ε_f {:.1f} %, d_f {:.3f} mm at {:.3g} s".format(
            100 * n["fracture_strain"], n["fracture_diameter_mm"], n["fracture_time_s"])
    cells = [os.path.relpath(run, root), f(last(run + "/energy.csv", "time")), f(s.get("steps"), "{}"),
             f(s.get("wall_time_s"), "{:.1f}"), f(fc, "{:.1f}"), f(ff, "{:.1f}"), f(s.get("chip_thickness_um"), "{:.1f}"),
             f(s.get("segmentation"), "{:.3f}"), f(seg.get("degree"), "{:.3f}"), f(seg.get("pitch_um"), "{:.1f}"),
             f(last(run + "/energy.csv", "damaged_volume")), f(last(run + "/energy.csv", "initiated_volume")), neck]
    print("| " + " | ".join(cells) + " |")
PY
}

keep_sweeps() { # names...: each /tmp/mpmsweep/<name>'s sweep.md and sweep.csv into $out/mpmsweep-<name>.*
    local v
    for v in "$@"; do
        cp "/tmp/mpmsweep/$v/sweep.md" "$out/mpmsweep-$v.md" 2>/dev/null
        cp "/tmp/mpmsweep/$v/sweep.csv" "$out/mpmsweep-$v.csv" 2>/dev/null
    done
}
mpm_sweep() { # name, batch, bound [s] (0: none; SIGINT at it), --grid/--set arguments...: one batched sweep of
               # cases/mpm/nairn-cut.toml into /tmp/mpmsweep/<name>, its wall time, its tables into $out
    local name=$1 batch=$2 bound=$3; shift 3
    local t0=$(date +%s.%N)
    timeout -s INT "$bound" "$here/swarf" --backend gpu sweep cases/mpm/nairn-cut.toml --quiet --batch "$batch" \
        --out "/tmp/mpmsweep/$name" "$@"
    echo "$name: batch $batch: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
    keep_sweeps "$name"
}
cut() { # a cutting run on the GPU: out-name, scene, extra args; prints its summary and a thinned force trace
    local name=$1 scene=$2; shift 2
    "$here/swarf" --backend gpu run "$scene" --quiet --out "/tmp/swarf-cut/$name" "$@" || return 1
    echo "== $name"; cat "/tmp/swarf-cut/$name/summary.json"; tail -n 3 "/tmp/swarf-cut/$name/run.log"
    awk 'NR == 1 || NR % 10 == 0' "/tmp/swarf-cut/$name/forces.csv"
}
force_means() { # forces.csv [t0 t1]: each force and contact column's mean over t0..t1 s (default: the last quarter)
    python3 - "$@" <<'PY'
import csv, sys
try:
    rows = list(csv.reader(open(sys.argv[1])))
except OSError:
    sys.exit(0)
head, rows = rows[0], [list(map(float, r)) for r in rows[1:]]
if len(sys.argv) > 3:
    t0, t1 = float(sys.argv[2]), float(sys.argv[3])
    w, label = [r for r in rows if t0 <= r[0] <= t1], "mean %g-%g s" % (t0, t1)
else:
    w, label = rows[3 * len(rows) // 4:], "mean last quarter"
if w:
    for k, c in enumerate(head):
        if c.startswith(("fc_", "ff_", "fx_", "fy_", "fz_", "contacts", "friction")):
            print("%s %-14s %.6g" % (label, c, sum(r[k] for r in w) / len(w)))
print("samples", len(rows), "last t", rows[-1][0] if rows else None)
PY
}
# The 2D V0060 and its 8-layer periodic extrusion (cases/3d/orthogonal-v0060.toml) at Δx = $1 m, whole, f64,
# once per variant named after it, each on the side(s) it changes (base: both; docs/3d.md, "The artificial stress
# under extrusion"): as0, xsph0, mu0 switch a term off in both; hproj, the 2D run at h/dx 1.46 (the width of the
# 3D kernel summed over its layers at 1.5); as059 / as03, the 3D run's artificial stress at ε 0.59 / 0.3; as015,
# the 2D run's at 0.15 (the 3D strength at 0.3); matched, the 3D run's viscosity and XSPH at their 2D strengths;
# base2d / base3d, the 2D / 3D run alone. SWARF_ORTHO_LONG=1: 2 mm of cut on a workpiece 1 mm longer. Each run's summary line
# and force means over 0.5 mm to the end of the cut go to $out/orthosw-<dx>.log, its forces.csv beside it (folders
# and names carry the spacing, so that two spacings can run side by side in one call).
ortho_variants() {
    local dxo=$1 v k s2 s3 sides per zmax asx l2 l3 tend xmax
    shift
    per=$(python3 -c "print(8*$dxo)"); zmax=$(python3 -c "print(7*$dxo)")
    asx=stabilisation.artificial_stress.epsilon
    # SWARF_ORTHO_LONG=1: 2 mm of cut on a workpiece 1 mm longer, means over 0.5-2 mm.
    l2=(); l3=(); tend=1.5736e-4; xmax=1.87e-3
    if [ "${SWARF_ORTHO_LONG:-0}" = 1 ]; then
        tend=3.1472e-4; xmax=2.87e-3
        l2=(--set 'body.0.max=[2.87e-3,2.9e-4]' --set 'boundary.2.min=[2.8699e-3,-1.0]' --set time.end=$tend)
        l3=(--set 'boundary.3.min=[2.8699e-3,-1.0,-1.0]' --set time.end=$tend)
    fi
    for v in "$@"; do
        s2=(); s3=(); sides="2d 3d"
        case $v in
            base) ;;
            base2d) sides=2d ;;
            base3d) sides=3d ;;
            as0) s2=(--set $asx=0); s3=("${s2[@]}") ;;
            xsph0) s2=(--set stabilisation.xsph.epsilon=0); s3=("${s2[@]}") ;;
            mu0) s2=(--set tool.friction=0); s3=("${s2[@]}") ;;
            hproj) s2=(--set discretisation.h_over_dx=1.46); sides=2d ;;
            as059) s3=(--set $asx=0.59); sides=3d ;;
            as015) s2=(--set $asx=0.15); sides=2d ;;
            as03) s3=(--set $asx=0.3); sides=3d ;;
            matched) sides=3d  # every stabilisation at its 2D strength (docs/3d.md): α/0.815, β/0.676, XSPH/0.946
                s3=(--set stabilisation.artificial_viscosity.alpha=1.227 --set stabilisation.artificial_viscosity.beta=1.479
                    --set stabilisation.xsph.epsilon=0.528) ;;
            *) echo "orthosw: unknown variant $v" >&2; continue ;;
        esac
        case " $sides " in *" 2d "*)
            run orthosw-$dxo-$v-2d "$here/swarf" --backend gpu run cases/cutting/v0060.toml --quiet --force \
                --out /tmp/orthosw/$dxo/$v/2d --set "discretisation.dx=$dxo" "${l2[@]}" "${s2[@]}" ;; esac
        case " $sides " in *" 3d "*)
            run orthosw-$dxo-$v-3d "$here/swarf" --backend gpu run cases/3d/orthogonal-v0060.toml --quiet \
                --force --out /tmp/orthosw/$dxo/$v/3d --set "discretisation.dx=$dxo" \
                --set "discretisation.period_z=$per" --set "body.0.max=[$xmax,2.9e-4,$zmax]" "${l3[@]}" "${s3[@]}" ;;
        esac
        for k in 2d 3d; do
            [ -f "/tmp/orthosw/$dxo/$v/$k/forces.csv" ] || continue
            { echo "## $v $k, dx = $dxo"; tail -n 2 "/tmp/orthosw/$dxo/$v/$k/run.log"
              force_means "/tmp/orthosw/$dxo/$v/$k/forces.csv" 7.868e-5 $tend; } >> "$out/orthosw-$dxo.log"
            cp "/tmp/orthosw/$dxo/$v/$k/forces.csv" "$out/orthosw-$dxo-$v-$k-forces.csv"
        done
    done
}
from_dirs() { # the checkpoints of fromcut/abfrom (made once per machine): prints their folders, comma separated
    local d=/tmp/swarf-from; mkdir -p $d
    # A carried 6k state (carry150k/ref6k.tgz, made by an earlier build), so that builds compare on one state.
    [ -e carry150k/ref6k.tgz ] && [ ! -f $d/ref6k/checkpoint.bin ] && tar xzf carry150k/ref6k.tgz -C $d
    if [ ! -f $d/ref6k/checkpoint.bin ]; then
        "$here/swarf" --backend gpu run cases/cutting/reference-cut.toml --quiet --out $d/ref6k \
            --set time.end=4.4e-4 --checkpoint-every 1e-4 >&2 || return 1
        tail -n 2 $d/ref6k/run.log >&2
    fi
    local dirs=$d/ref6k
    # A 150k state being made in the background (part bgmake150k): wait for it, and return its parts.
    [ -n "${SWARF_MAKING:-}" ] || while pgrep -f "gpu-run.sh make150k" > /dev/null; do sleep 5; done
    if [ -e $d/make-out/whole-150k-f64.tgz.partaa ] && [ ! -e "$out/whole-150k-f64.tgz.partaa" ]; then
        cp $d/make-out/whole-150k-f64.tgz.part* "$out/"; cat $d/make150k.out >&2
    fi
    if [ -e carry150k/whole-150k-f64.tgz.partaa ] && [ ! -f $d/whole-150k-f64/checkpoint.bin ]; then
        cat carry150k/whole-150k-f64.tgz.part* | tar xzf - -C $d
    elif [ -n "${SWARF_MAKE_150K:-}" ] && [ ! -f $d/whole-150k-f64/checkpoint.bin ]; then
        # No carried 150k state: run the 150k f64 cut to SWARF_MAKE_150K seconds of cut time (6.05e-4 s: about
        # 2.1 M steps, 8 minutes on an H200) with checkpoints every 1e-4 s, and return the last one split into
        # $out/whole-150k-f64.tgz.part* (what carry150k/ holds).
        "$here/swarf" --backend gpu run cases/cutting/reference-cut-150k.toml --quiet --out $d/whole-150k-f64 \
            --set time.end="$SWARF_MAKE_150K" --set output.every=1e-4 --checkpoint-every 1e-4 >&2 || return 1
        tail -n 3 $d/whole-150k-f64/run.log >&2
        tar czf - -C $d whole-150k-f64/checkpoint.bin whole-150k-f64/scene.toml \
            | split -b 15m - "$out/whole-150k-f64.tgz.part"
    fi
    [ -f $d/whole-150k-f64/checkpoint.bin ] && dirs=$dirs,$d/whole-150k-f64
    echo "$dirs"
}
abenv() { # the checkpoints' step with each variant of $1 (space-separated; "default" or NAME=VALUE[,NAME=VALUE...]),
            # alternating, two rounds
    local dirs; dirs=$(from_dirs) || return 1
    local v round
    for round in 1 2; do
        for v in $1; do
            echo "== $v, round $round"
            env $([ "$v" = default ] || echo "${v//,/ }") \
                "$here/swarf" --backend gpu bench step --from "$dirs" --step-count 2048 || return 1
        done
    done
}
for z in "$here"/*.gz; do [ -e "$z" ] && gunzip -f "$z" && chmod +x "${z%.gz}"; done
echo "commit $(cat "$here/COMMIT")"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv,noheader 2>/dev/null | tee "$out/nvidia-smi.log"
for p in $parts; do
    case $p in
        info) run info "$here/swarf" --backend gpu info --kernels ;;
        firstrun) # issue 21: the main job (`swarf run`, the default scene) on an empty JIT cache and again on the filled
                  # one, with this build and each packed earlier one (swarf-<name>); whole-process wall times
                  firstrun() {
                      local b k t0 t1
                      for b in swarf $(cd "$here" && ls swarf-* 2>/dev/null | grep -v '\.gz$'); do
                          rm -rf "${CUDA_CACHE_PATH:-$HOME/.nv/ComputeCache}"
                          for k in first second; do
                              t0=$(date +%s%N)
                              "$here/$b" --backend gpu run --quiet --out /tmp/swarf-first/$b-$k || return 1
                              t1=$(date +%s%N)
                              echo "== $b, $k run (JIT cache $([ $k = first ] && echo empty || echo filled)):" \
                                  "$(( (t1 - t0) / 1000000 )) ms wall"
                              tail -n 2 /tmp/swarf-first/$b-$k/run.log
                          done
                          du -sh "${CUDA_CACHE_PATH:-$HOME/.nv/ComputeCache}" 2>/dev/null
                      done
                  }
                  run firstrun firstrun ;;
        make150k) # issue 7: the 150k state of fromcut/abfrom/abenv where none is carried (from_dirs, SWARF_MAKE_150K,
                  # default 6.05e-4 s); its parts come back in $OUT for carry150k/
                  SWARF_MAKING=1 SWARF_MAKE_150K=${SWARF_MAKE_150K:-6.05e-4} run make150k from_dirs ;;
        bgmake150k) # make150k in the background (its own session, so that it runs on after this call while the
                    # machine is held); the next from_dirs waits for it and returns its parts
                    mkdir -p /tmp/swarf-from
                    OUT=/tmp/swarf-from/make-out setsid nohup bash "$here/gpu-run.sh" make150k \
                        > /tmp/swarf-from/make150k.out 2>&1 < /dev/null &
                    echo "making the 150k state in the background (pid $!) at $(date +%T)" ;;
        ensemble) # issue 23: whole V0060 runs per hour and day as a batched ensemble at each width
                  # (SWARF_ENSEMBLE_WIDTHS, default 1,4,8,16,32; SWARF_ENSEMBLE_S s each, default 45;
                  # SWARF_ENSEMBLE_SET: --set arguments, e.g. the early stop)
                  run ensemble "$here/swarf" --backend gpu bench ensemble --widths "${SWARF_ENSEMBLE_WIDTHS:-1,4,8,16,32}" \
                      --duration "${SWARF_ENSEMBLE_S:-45}" ${SWARF_ENSEMBLE_SET:-} ;;
        bgensemble) # issue 23: `ensemble` in the background (its own session: runs on past this call's 10 minutes,
                    # e.g. SWARF_ENSEMBLE_S=600); waitensemble collects it
                    mkdir -p /tmp/swarf-ens
                    OUT=/tmp/swarf-ens/out setsid nohup bash "$here/gpu-run.sh" ensemble > /tmp/swarf-ens/bg.out 2>&1 < /dev/null &
                    echo "ensemble in the background (pid $!) at $(date +%T)" ;;
        waitensemble) # waits (at most SWARF_WAIT_LIMIT s, default 540) for bgensemble and copies its log here
                      waitens() {
                          local t=0
                          while pgrep -f "gpu-run.sh ensemble" > /dev/null && [ $t -lt "${SWARF_WAIT_LIMIT:-540}" ]; do
                              sleep 5; t=$((t + 5))
                          done
                          cat /tmp/swarf-ens/bg.out  # the table (its ensemble.log goes into /tmp/swarf-ens/out/logs.tgz)
                          ! pgrep -f "gpu-run.sh ensemble" > /dev/null
                      }
                      run waitensemble waitens ;;
        earlystop) # issue 23: the default cut (V0060) whole and with the early stop at two tolerances: wall time, steps,
                   # forces (SWARF_EARLY_TOLS, default "0.02 0.05")
                   earlystop() {
                       local tol t0 t1
                       for tol in none ${SWARF_EARLY_TOLS:-0.02 0.05}; do
                           rm -rf /tmp/swarf-es/$tol
                           t0=$(date +%s%N)
                           if [ $tol = none ]; then
                               "$here/swarf" --backend gpu run --quiet --out /tmp/swarf-es/$tol || return 1
                           else
                               "$here/swarf" --backend gpu run --quiet --out /tmp/swarf-es/$tol \
                                   --set "analysis.early_stop={tolerance=$tol}" || return 1
                           fi
                           t1=$(date +%s%N)
                           echo "== early stop $tol: $(( (t1 - t0) / 1000000 )) ms wall"
                           python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); print({k: s.get(k) for k in ["steps","wall_time_s","fc_n_per_mm","ff_n_per_mm","chip_thickness_um","early_stop"]})' /tmp/swarf-es/$tol/summary.json
                       done
                   }
                   run earlystop earlystop ;;
        holdout) # issue 23: Klippel's three V0060 sets (μ = 0.35) on the 24 held-out Ti6Al4V tests of
                 # cases/identify/ti6al4v-multi.toml, full-length runs as one ensemble; holdout.md and .csv
                 holdout() {
                     rm -rf /tmp/swarf-holdout
                     "$here/swarf" --backend gpu identify cases/identify/ti6al4v-multi.toml --holdout-only \
                         --out /tmp/swarf-holdout ${SWARF_HOLDOUT_ARGS:-} || return 1
                     cat /tmp/swarf-holdout/holdout.md; cp /tmp/swarf-holdout/holdout.csv "$out/holdout.csv"
                 }
                 run holdout holdout ;;
        mufit) # issue 23 (docs/identification.md, "μ fitted on eight experiments"): cases/identify/ti6al4v-multi.toml
               # (SWARF_FIT_FILE) with --only tool.friction (SWARF_FIT_ONLY; A..n at Klippel's V0060 DE set), DE's
               # generations (--batch 15, SWARF_FIT_BATCH; both empty: the file's) bounded by SWARF_FIT_S s (default 250); SWARF_FIT_FROM (a mufit-folder.tgz of an earlier call,
               # carried) resumes it, its finished runs taken from their folders. Then the best μ so far and Klippel's
               # three sets on the 24 held-out tests (--resume --holdout-only, bounded by SWARF_HOLDOUT_S, default
               # 320; 0: skipped). mufit-history.csv, mufit-holdout.csv, mufit-folder.tgz (the identification folder,
               # to carry to the next call); the reports in the log.
            mufit() {
                local d=/tmp/swarf-mufit f=${SWARF_FIT_FILE:-cases/identify/ti6al4v-multi.toml} resume= extra=()
                rm -rf $d
                if [ -n "${SWARF_FIT_FROM:-}" ]; then tar xzf "$SWARF_FIT_FROM" -C /tmp && resume=--resume; fi
                # SWARF_FIT_ONLY / SWARF_FIT_BATCH empty: the file's parameters and batch.
                [ -n "${SWARF_FIT_ONLY-tool.friction}" ] && extra+=(--only "${SWARF_FIT_ONLY-tool.friction}")
                [ -n "${SWARF_FIT_BATCH-15}" ] && extra+=(--batch "${SWARF_FIT_BATCH-15}")
                # SWARF_FIT_S=0: no fit, only the holdout of the carried folder (e.g. held-out tests added since)
                [ "${SWARF_FIT_S:-250}" = 0 ] || timeout -s INT "${SWARF_FIT_S:-250}" "$here/swarf" --backend gpu \
                    identify $f "${extra[@]}" --width "${SWARF_FIT_W:-40}" --out $d $resume
                cat $d/report.md; cp $d/history.csv "$out/mufit-history.csv"
                echo "finished runs kept: $(find $d/runs -name identify-finished.txt | wc -l)"
                if [ "${SWARF_HOLDOUT_S:-320}" != 0 ]; then
                    timeout -s INT "${SWARF_HOLDOUT_S:-320}" "$here/swarf" --backend gpu identify $f --resume \
                        --holdout-only --width "${SWARF_FIT_W:-40}" --out $d
                    cat $d/holdout/holdout.md $d/holdout.md 2>/dev/null
                    cp $d/holdout.csv $d/holdout/holdout.csv "$out/" 2>/dev/null
                fi
                # What a resume needs (the whole folder, 44 MB compressed after 165 s, is over what a call returns):
                # the folder's own files and each finished run's summary.json and mark.
                (cd /tmp && { find swarf-mufit -maxdepth 1 -type f
                    find swarf-mufit/runs -name summary.json -o -name identify-finished.txt; } |
                    tar czf "$out/mufit-folder.tgz" -T -)
            }
            run mufit mufit ;;
        identify) # issue 23: Klippel's DE on V0060 (cases/identify/v0060-de.toml) for SWARF_IDENTIFY_S seconds (default
                  # 150), then Ctrl-C (SIGINT): the completed batches are kept; history.csv and report.md come back
                  identify() {
                      rm -rf /tmp/swarf-de
                      timeout -s INT "${SWARF_IDENTIFY_S:-150}" "$here/swarf" --backend gpu identify \
                          cases/identify/v0060-de.toml --out /tmp/swarf-de ${SWARF_IDENTIFY_ARGS:-}
                      cat /tmp/swarf-de/report.md; cp /tmp/swarf-de/history.csv "$out/de-history.csv"
                  }
                  run identify identify ;;
        v0300noise) # issue 23 (docs/identification.md "Ck45 V0300 by DE"): the run-to-run scatter of V0300's forces, the
                    # floor under any ΔF²: Klippel's DE set (the scene's) and swarf's DE best set
                    # (cases/materials/Ck45-V0300-swarf-DE.toml) each at five CFL numbers within 0.2 % of 0.5, one
                    # batched sweep each; v0300noise-klippel.md, v0300noise-swarf.md
            v0300noise() {
                local s set
                for s in klippel swarf; do
                    set=(); [ $s = swarf ] && set=(--set 'material.name="Ck45-V0300-swarf-DE"')
                    "$here/swarf" --backend gpu sweep cases/cutting/v0300.toml --grid time.cfl=0.499,0.4995,0.5,0.5005,0.501 \
                        "${set[@]}" --batch 5 --out /tmp/v0300-$s --quiet
                    cp /tmp/v0300-$s/sweep.md "$out/v0300noise-$s.md"; cat /tmp/v0300-$s/sweep.md
                done
            }
            run v0300noise v0300noise ;;
        ck45) # issue 22 item 5: the failing Ck45 cut (cases/hard/ck45-slow-fine-cut.toml) whole on the GPU, with
              # checkpoints every 2e-5 s; its logs, force trace and last checkpoint come back as ck45.tgz (resume on
              # the CPU to step through a failure: CPU = GPU bit for bit)
              # SWARF_CK45_S (default 400) bounds it, so that what it has written comes back within the call;
              # SWARF_CK45_ARGS adds arguments (e.g. --resume, overrides)
            run ck45 timeout "${SWARF_CK45_S:-400}" "$here/swarf" --backend gpu run cases/hard/ck45-slow-fine-cut.toml \
                --quiet --out /tmp/ck45 --checkpoint-every 2e-5 ${SWARF_CK45_ARGS:-}
            tail -n 5 /tmp/ck45/run.log; tar czf "$out/ck45.tgz" --exclude='*.vtu' -C /tmp ck45
            last=$(ls /tmp/ck45/frames/*.vtu 2>/dev/null | tail -n 1); [ -n "$last" ] && gzip -c "$last" > "$out/ck45-last.vtu.gz" ;;
        contactlaws) # issue 22 item 3: V0060 (1 mm) over the contact laws × damping × CFL × κ as one batched sweep;
              # the table and every run's force trace (friction_ratio) come back as contactlaws.tgz
            run contactlaws "$here/swarf" --backend gpu sweep cases/cutting/v0060.toml \
                --grid 'tool.contact_law="step","bulk"' --grid tool.contact_damping=${SWARF_DAMPINGS:-0,1} \
                --grid time.cfl=0.5,0.25 --grid tool.contact_stiffness=0.1,0.2 --batch 8 --out /tmp/contactlaws --quiet
            cat /tmp/contactlaws/sweep.md
            tar czf "$out/contactlaws.tgz" --exclude='*.vtu' --exclude='*.png' -C /tmp contactlaws ;;
        table22) # issue 22's validation table: V0060, V0300, the reference cut (1 mm) with swarf's defaults and "mfree_iwf",
                 # one batched sweep per case; tables and force traces come back as table22.tgz
            # (twice each: CFL 0.5 and 0.4995, a replica of the chaotic cut)
            for c in v0060 v0300 reference-cut; do
                run "table22-$c" "$here/swarf" --backend gpu sweep cases/cutting/$c.toml \
                    --grid 'model="swarf","mfree_iwf"' --grid time.cfl=0.5,0.4995 --batch 4 --out /tmp/table22/$c --quiet
                cat /tmp/table22/$c/sweep.md
            done
            tar czf "$out/table22.tgz" --exclude='*.vtu' --exclude='*.png' -C /tmp table22 ;;
        tool3d) # issue 24 (docs/3d.md): (1) the 3D step against each packed earlier build (swarf-<name>) on the
                # 3D tubes at Δx = 0.5 mm (the non-periodic 3D path), bench step both precisions; (2) the extruded
                # V0060 (cases/3d/orthogonal-v0060.toml, 45k particles) at t = 0 with and without its z period;
                # (3) whole runs, each bounded by SWARF_TOOL3D_S s (default 240; SIGINT keeps what was written): the
                # 2D V0060, its periodic plane-strain extrusion, and the single diamond grain
                # (cases/3d/single-grain.toml); F_c and F_f per mm, the 3D columns, wall time; tool3d.tgz
                # (summaries, forces.csv, energy.csv, the grain's last frame and tool surface)
            tool3d() {
                local d=/tmp/tool3d lim=${SWARF_TOOL3D_S:-240} b others
                others=$(cd "$here" && ls swarf-* 2>/dev/null | grep -v '\.gz$')
                rm -rf $d; mkdir -p $d/ab
                sed 's/^dx = 0.0025/dx = 0.0005/' cases/cylinders-3d.toml > $d/ab/tubes-3d.toml
                for b in swarf $others; do
                    echo "== $b: 3D tubes"
                    (cd $d/ab && "$here/$b" --backend gpu bench step --precision both --step-count 512 \
                        --scenes tubes-3d.toml) || return 1
                done
                # 10 layers (P = 10 dx), so that the bench's skin 0.2 h still has 5 cells in the period.
                sed 's/^period_z = 8.0e-5/period_z = 1.0e-4/; s/2.9e-4, 7.0e-5\]/2.9e-4, 9.0e-5]/' \
                    cases/3d/orthogonal-v0060.toml > $d/orthogonal-period.toml
                sed '/^period_z/d' $d/orthogonal-period.toml > $d/orthogonal-noperiod.toml
                cp -r cases/3d/tools $d/
                "$here/swarf" --backend gpu bench step --precision both --step-count 512 \
                    --scenes $d/orthogonal-period.toml,$d/orthogonal-noperiod.toml || return 1
                for c in cases/cutting/v0060.toml cases/3d/orthogonal-v0060.toml cases/3d/single-grain.toml; do
                    local name; name=$(basename "$c" .toml)
                    local t0; t0=$(date +%s.%N)
                    timeout -s INT "$lim" "$here/swarf" --backend gpu run "$c" --quiet --out "$d/$name"
                    local rc=$?
                    echo "== $name rc=$rc wall $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }') s"
                    grep -E '"(fc|ff)_n_per_mm"' "$d/$name/summary.json" 2>/dev/null | head -2
                    tail -n 2 "$d/$name/run.log" 2>/dev/null
                    head -n 1 "$d/$name/forces.csv"; awk 'NR > 1 && NR % 20 == 0' "$d/$name/forces.csv" | tail -n 12
                done
                local last; last=$(ls $d/single-grain/frame_*.vtu 2>/dev/null | tail -n 1)
                mkdir -p $d/grain-last
                if [ -n "$last" ]; then
                    cp "$last" $d/grain-last/
                    cp "$(dirname "$last")/tool_$(basename "$last" .vtu | sed 's/^frame_//').vtp" $d/grain-last/ 2>/dev/null
                fi
                tar czf "$out/tool3d.tgz" -C $d --exclude='*/frame_*.vtu' --exclude='*/tool_*.vtp' --exclude=./ab \
                    --exclude=./tools .
                tar czf "$out/grain-last.tgz" -C $d grain-last
            }
            run tool3d tool3d ;;
        tools24) # issue 24, several tools (docs/3d.md): (1) bench step of the single grain and the 2D V0060 with this
                 # build and each packed earlier one that reads them (the contact pass's tool array against the mesh
                 # passed by value); (2) whole runs, each bounded by SWARF_TOOLS24_S s (default 150; SIGINT keeps
                 # what was written): the 2D tandem tools, the Taylor bar on the rigid wall (μ = 0, 0.3) beside the
                 # particle wall, the micro-milling cut with JC and SCGL, the multi-grain patterns A, B, C (SWARF_TOOLS24_CASES picks fewer: names of
                 # whole runs); every tool's mean force over the last quarter; tools24.tgz
            tools24() {
                local d=/tmp/tools24 lim=${SWARF_TOOLS24_S:-150} b name round
                rm -rf $d; mkdir -p $d
                local sc
                for round in ${SWARF_TOOLS24_AB_ROUNDS-1 2}; do
                    for b in swarf $(cd "$here" && ls swarf-* 2>/dev/null | grep -v '\.gz$'); do
                        for sc in cases/cutting/v0060.toml cases/3d/single-grain.toml; do
                            echo "== $b: $sc, bench step, round $round"
                            "$here/$b" --backend gpu bench step --precision f64 --step-count 256 --scenes "$sc" \
                                || echo "($b cannot run $sc)"
                        done
                    done
                done
                local names=${SWARF_TOOLS24_CASES:-"tandem taylor-particles taylor-wall taylor-wall-mu03 mill-jc mill-scgl grain-a grain-b grain-c"}
                for name in $names; do
                    local c set=()
                    case $name in
                        tandem) c=cases/cutting/tandem-tools.toml ;;
                        taylor-particles) c=cases/taylor-bar.toml ;;
                        taylor-wall) c=cases/3d/taylor-bar-wall.toml; set=(--state-at 1500) ;;
                        taylor-wall-mu03) c=cases/3d/taylor-bar-wall.toml; set=(--set tool.friction=0.3) ;;
                        mill-jc) c=cases/3d/micro-milling.toml ;;
                        mill-scgl) c=cases/3d/micro-milling.toml; set=(--set 'material.name="OFHC-Cu-SCGL"') ;;
                        # 504k particles: 4 frames (forces.csv keeps 10 samples per frame interval).
                        grain-a|grain-c) c=cases/3d/multi-grain-${name#grain-}.toml; set=(--set output.every=2.9e-6) ;;
                        grain-b) c=cases/3d/multi-grain-b.toml; set=(--set output.every=2.9e-6 --state-at 23000) ;;
                    esac
                    local t0; t0=$(date +%s.%N)
                    timeout -s INT -k 20 "$lim" "$here/swarf" --backend gpu run "$c" "${set[@]}" --quiet --out "$d/$name" < /dev/null
                    local rc=$?
                    echo "== $name rc=$rc wall $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }') s"
                    tail -n 2 "$d/$name/run.log" 2>/dev/null
                    # Kept in $out as each run ends, so that a call cut short returns the runs it finished.
                    mkdir -p "$out/runs/$name"
                    cp "$d/$name"/{summary.json,forces.csv,run.log,energy.csv} "$out/runs/$name/" 2>/dev/null
                    python3 - "$d/$name" <<'PY'
import json, sys
try:
    s = json.load(open(sys.argv[1] + "/summary.json"))
    for b in s.get("bodies", []):
        print("body", b["name"], "extent_m", b["extent_m"], "min_m", b["min_m"], "radius_xy_max_m", b.get("radius_xy_max_m"))
except (OSError, ValueError) as e:
    print("no summary:", e)
PY
                    force_means "$d/$name/forces.csv"
                done
                tar czf "$out/tools24.tgz" -C $d --exclude='*/frame_*.vtu' --exclude='*/tool*_*.vtp' --exclude='*/states' .
                # Pictures' data: the state tables of grain-b and taylor-wall (--state-at), thinned to x, y, z, the
                # plastic strain and the owning tool (grain-b: the particles above mid-height only).
                local f
                for f in $d/grain-b/states/state_*.csv $d/taylor-wall/states/state_*.csv; do
                    [ -e "$f" ] || continue
                    python3 - "$f" "$out/pic-$(basename "$(dirname "$(dirname "$f")")")-$(basename "$f" .csv).csv" <<'PY'
import csv, sys
src, dst = sys.argv[1], sys.argv[2]
r = csv.reader(open(src))
head = next(r)
cols = [c for c in ("x", "y", "z", "eps_pl", "contact_tool") if c in head]
ix = [head.index(c) for c in cols]
grain = "grain-b" in dst
with open(dst, "w") as o:
    o.write(",".join(cols) + "\n")
    for row in r:
        if grain and float(row[head.index("y")]) < 3.0e-5:
            continue
        o.write(",".join("%.4g" % float(row[k]) for k in ix) + "\n")
PY
                    gzip -9 "$out"/pic-*.csv
                done
            }
            run tools24 tools24 ;;
        cspm24) # issue 24, the CSPM correction (docs/3d.md, "CSPM"): (1) bench step, f64, 256 steps, two rounds
                # (SWARF_CSPM24_AB_ROUNDS): the 2D V0060 and the single grain with this build and each packed earlier
                # one (the cost of the new entries' neighbour on the default path), and the single grain with CSPM;
                # (2) whole runs at CFL 0.3, each bounded by SWARF_CSPM24_S s (default 150; SIGINT keeps what was
                # written), SWARF_CSPM24_CASES picks: a-plain, c-cspm, d-cspm-as (the single grain in Röthlin's
                # configurations A, C = CSPM, D = CSPM + AS, thesis §7.6.2.1), pic-a/pic-d (A and D with a state
                # table near their end, thinned to a slab |z| < 6 µm for a side view of the chip), grain-a-d,
                # grain-b-d, grain-c-d (the multi-grain patterns in configuration D; grain-a-a ... in A), all at CFL
                # SWARF_CSPM24_CFL (default 0.3); mean forces over 2-10 µs;
                # every run's summary, forces and log in cspm24-runs.tgz, rewritten as each run ends
            cspm24() {
                local d=/tmp/cspm24 lim=${SWARF_CSPM24_S:-150} b sc round name
                rm -rf $d; mkdir -p $d
                cp -r cases/3d/tools $d/
                sed 's/^xsph = { epsilon = 0.5 }/xsph = { epsilon = 0.5 }\ncspm = {}/' cases/3d/single-grain.toml \
                    > $d/single-grain-cspm.toml
                for round in ${SWARF_CSPM24_AB_ROUNDS-1 2}; do
                    for b in swarf $(cd "$here" && ls swarf-* 2>/dev/null | grep -v '\.gz$'); do
                        for sc in cases/cutting/v0060.toml cases/3d/single-grain.toml $d/single-grain-cspm.toml; do
                            echo "== $b: $sc, bench step, round $round"
                            "$here/$b" --backend gpu bench step --precision f64 --step-count 256 --scenes "$sc" \
                                || echo "($b cannot run $sc)"
                        done
                    done
                done
                local cspm=(--set 'stabilisation.cspm={}' --set 'stabilisation.artificial_stress={}')
                for name in ${SWARF_CSPM24_CASES:-a-plain c-cspm d-cspm-as}; do
                    local c=cases/3d/single-grain.toml set=(--set time.cfl=${SWARF_CSPM24_CFL:-0.3})
                    case $name in
                        c-cspm) set+=(--set 'stabilisation.cspm={}') ;;
                        d-cspm-as) set+=("${cspm[@]}") ;;
                        pic-a) set+=(--state-at 35000) ;;
                        pic-d) set+=("${cspm[@]}" --state-at 39000) ;;
                        grain-?-d) c=cases/3d/multi-grain-${name:6:1}.toml
                                   set+=("${cspm[@]}" --set output.every=2.9e-6) ;;
                        grain-?-a) c=cases/3d/multi-grain-${name:6:1}.toml; set+=(--set output.every=2.9e-6) ;;
                    esac
                    local t0; t0=$(date +%s.%N)
                    timeout -s INT -k 20 "$lim" "$here/swarf" --backend gpu run "$c" "${set[@]}" --quiet \
                        --out "$d/$name" < /dev/null
                    echo "== $name rc=$? wall $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }') s"
                    tail -n 2 "$d/$name/run.log" 2>/dev/null
                    force_means "$d/$name/forces.csv" 2e-6 1e-5
                    local f
                    for f in $d/$name/states/state_*.csv; do
                        [ -e "$f" ] || continue
                        python3 - "$f" "$d/$name/pic-$name.csv" <<'PY'
import csv, sys
src, dst = sys.argv[1], sys.argv[2]
r = csv.reader(open(src))
head = next(r)
cols = [c for c in ("x", "y", "z", "eps_pl", "temperature") if c in head]
ix = [head.index(c) for c in cols]
iz = head.index("z")
with open(dst, "w") as o:
    o.write(",".join(cols) + "\n")
    for row in r:
        if abs(float(row[iz])) < 6.0e-6:
            o.write(",".join("%.4g" % float(row[k]) for k in ix) + "\n")
PY
                    done
                    tar czf "$out/cspm24-runs.tgz" -C $d --exclude='*/frame_*.vtu' --exclude='*/tool*_*.vtp' \
                        --exclude='*/states' --exclude='*/energy.csv' --exclude=tools --exclude='*.png' .
                done
            }
            run cspm24 cspm24 ;;
        damage25|damage25fine) # issue 25 item 5 (docs/damage.md, "Scenes"). damage25: the CT specimen with the mask, without
                  # it and with load reversal; the SHTB, classic JC and JC-GG (fracture strain and diameter by
                  # `swarf neck`); V0060 with damage at 10 and 5 µm; Ducobu at 9.3 µm, 4 flow models × damage on/off
                  # as one batched sweep, last (the biggest: 8 × 11.5k particles × 890k steps). damage25fine: Ducobu
                  # at 4.65 µm (8 × 46.6k particles × 1.78 M steps: far beyond one call; SWARF_DUCOBU_END shortens
                  # it). Every run is bounded by SWARF_DAMAGE_S s (default 240; SIGINT: it stops and keeps what it
                  # wrote, and the table takes F_c from the second half of forces.csv where summary.json is missing).
                  # damage25.md (the table: forces, segmentation, pitch, damaged volume, SHTB fracture) and
                  # damage25.tgz (summaries, force and energy traces, no frames).
            damage25() {
                local d=/tmp/damage25 lim=${SWARF_DAMAGE_S:-240} m models=""
                mkdir -p $d
                for m in JC TANH2008 TANH2010 TANHSO3; do models="$models${models:+,}\"Ti6Al4V-Klippel-$m\""; done
                one() { # out-name, scene, --set arguments...
                    local name=$1 scene=$2; shift 2
                    local sets=(); for a in "$@"; do sets+=(--set "$a"); done
                    rm -rf "$d/$name"
                    timeout -s INT "$lim" "$here/swarf" --backend gpu run "$scene" --quiet --out "$d/$name" "${sets[@]}"
                    echo "== $name rc=$? $(tail -n 1 "$d/$name/run.log" 2>/dev/null)"
                }
                if [ "$1" = damage25 ]; then
                    local ct=cases/damage/ct-specimen.toml rev='[5.0e-5,1.5e-4]'
                    one ct-mask $ct
                    one ct-nomask $ct damage.mask=false
                    one ct-reversal $ct "boundary.0.reverse_at=$rev" "boundary.1.reverse_at=$rev" time.end=4.52e-4
                    one v0060-damage-10um cases/cutting/v0060-damage.toml
                    one shtb-jc cases/damage/shtb-50sib8.toml
                    one shtb-jcgg cases/damage/shtb-50sib8.toml 'material.name="50SiB8-Klippel-JCGG"'
                    for r in shtb-jc shtb-jcgg; do
                        "$here/swarf" neck "$d/$r" && find "$d/$r" -name 'frame_*.vtu' -delete
                    done
                    one v0060-damage-5um cases/cutting/v0060-damage.toml discretisation.dx=5.0e-6
                    rm -f $d/ct-*/frame_*.vtu $d/v0060-*/frame_*.vtu
                    timeout -s INT "$lim" "$here/swarf" --backend gpu sweep cases/cutting/ducobu.toml --grid "material.name=$models" \
                        --grid damage.enabled=true,false --batch 8 --out $d/ducobu-9.3um --quiet
                else
                    timeout -s INT "$lim" "$here/swarf" --backend gpu sweep cases/cutting/ducobu.toml --grid "material.name=$models" \
                        --grid damage.enabled=true,false --set discretisation.dx=4.65e-6 \
                        --set time.end="${SWARF_DUCOBU_END:-1.2e-3}" --batch 8 --out $d/ducobu-4.65um --quiet
                fi
                damage_table "$d" > "$out/$1.md"
                cat "$out/$1.md"
                tar czf "$out/$1.tgz" --exclude='*.vtu' --exclude='*.png' --exclude='*.vtp' --exclude='checkpoint.bin' -C /tmp damage25
            }
            run "$p" damage25 "$p" ;;
        shtb25) # issue 25 (docs/damage.md, "SHTB"): the SHTB, JC classic and JC-GG, with `swarf neck` (fracture
                # strain and diameter; to SWARF_SHTB_END, default 0.6 ms, past the fracture at 0.43 ms); frames every
                # SWARF_SHTB_EVERY (default the scene's 10 µs: the neck is measured at the last frame before the
                # fracture); SWARF_SHTB_RUNS picks runs among jc, jcgg and jcgg-dt1e8 (JC-GG at Klippel's Δt = 1e-8 s);
                # SWARF_SHTB_DX the spacing (default the scene's 0.2 mm), SWARF_SHTB_S bounds each run (SIGINT: it
                # stops with what it wrote); shtb25.md (damage_table)
            shtb25() {
                local d=/tmp/shtb25 r set
                rm -rf $d; mkdir -p $d
                for r in ${SWARF_SHTB_RUNS:-jc jcgg}; do
                    set=(--set time.end=${SWARF_SHTB_END:-6e-4})
                    [ -n "${SWARF_SHTB_EVERY:-}" ] && set+=(--set output.every=$SWARF_SHTB_EVERY)
                    [ -n "${SWARF_SHTB_DX:-}" ] && set+=(--set discretisation.dx=$SWARF_SHTB_DX)
                    case $r in
                        jc) ;;
                        jcgg) set+=(--set 'material.name="50SiB8-Klippel-JCGG"') ;;
                        jcgg-dt1e8) set+=(--set 'material.name="50SiB8-Klippel-JCGG"' --set time.dt=1.0e-8) ;;
                    esac
                    timeout -s INT "${SWARF_SHTB_S:-100000}" \
                        "$here/swarf" --backend gpu run cases/damage/shtb-50sib8.toml --quiet --out $d/shtb-$r "${set[@]}"
                    "$here/swarf" neck "$d/shtb-$r"; tail -n 2 "$d/shtb-$r/run.log"
                    find $d/shtb-$r -name 'frame_*.vtu' -delete  # frames every 2 µs fill the disk: keep the summaries
                done
                damage_table "$d" > "$out/shtb25.md"; cat "$out/shtb25.md"
            }
            run shtb25 shtb25 ;;
        gf25) # issue 25 (docs/damage.md, "Which fracture energy segments V0060"): V0060 with damage over G_f
              # (SWARF_GF_VALUES, default the thesis's 44 501.7 J/m² down to 300) × the mask's two forms, at
              # SWARF_GF_DX (default 10 and 5 µm), one batched sweep each, with frames when SWARF_GF_FRAMES=1; then
              # SWARF_GF_FINE (spacings, default none) with G_f = 10 kJ/m² and the invariant mask, one run each.
              # `swarf chip` on every run with frames, pictures (damage, plastic strain) in $OUT/gfpics.
              # gf25.md (damage_table), gf25-chip.md, gf25.tgz (summaries, traces, no frames).
            gf25() {
                local d=/tmp/gf25 dx r frames=
                [ "${SWARF_GF_FRAMES:-0}" = 1 ] && frames=--frames
                rm -rf $d
                for dx in ${SWARF_GF_DX-1.0e-5 5.0e-6}; do
                    "$here/swarf" --backend gpu sweep cases/cutting/v0060-damage.toml $frames \
                        --grid damage.fracture_energy=${SWARF_GF_VALUES:-44501.7,10000,3000,1000,300} \
                        --grid 'damage.mask_form="printed","invariant"' --set discretisation.dx=$dx \
                        --batch 10 --out $d/dx-$dx --quiet
                done
                for dx in ${SWARF_GF_FINE:-}; do
                    "$here/swarf" --backend gpu run cases/cutting/v0060-damage.toml --quiet --out $d/fine-$dx \
                        --set discretisation.dx=$dx --set damage.fracture_energy=10000 \
                        --set 'damage.mask_form="invariant"'
                done
                damage_table "$d" > "$out/gf25.md"; cat "$out/gf25.md"
                chip_report $d "$out/gfpics" > "$out/gf25-chip.md"
                tar czf "$out/gf25.tgz" --exclude='*.vtu' --exclude='*.png' --exclude='*.vtp' --exclude='checkpoint.bin' -C /tmp gf25
            }
            run gf25 gf25 ;;
        ducobugf) # issue 25 (docs/damage.md, "Ducobu over G_f"): Ducobu at 9.3 µm with damage, the four flow models
                  # × G_f (SWARF_DUCOBU_GF, default 20 and 10 kJ/m²), the invariant mask, one batched sweep with
                  # frames (SWARF_DUCOBU_END sets its end, SWARF_DUCOBU_LEN the workpiece's length, SWARF_DUCOBU_DX the
                  # spacing, SWARF_DUCOBU_MODELS the flow models); `swarf chip` and pictures of each (tar'd:
                  # ducobugf-pics.tgz). ducobugf.md (damage_table), ducobugf-chip.md, ducobugf.tgz. SWARF_DUCOBU_TAG
                  # suffixes every folder and file name, so that two sweeps (two spacings) can run side by side in one
                  # call: `SWARF_DUCOBU_TAG=-fine … gpu-run.sh ducobugf & SWARF_DUCOBU_TAG=-coarse … gpu-run.sh ducobugf`.
            ducobugf() {
                local t=${SWARF_DUCOBU_TAG:-} m models="" len=${SWARF_DUCOBU_LEN:-1.0e-3} geo=() dmg=()
                local d=/tmp/ducobugf$t
                rm -rf $d
                for m in ${SWARF_DUCOBU_MODELS:-JC TANH2008 TANH2010 TANHSO3}; do models="$models${models:+,}\"Ti6Al4V-Klippel-$m\""; done
                # SWARF_DUCOBU_LEN: a longer workpiece (its fixed right side moved with it), so that the chip leaves
                # the start and segments can follow each other; SWARF_DUCOBU_NODAMAGE=1 adds the runs without damage.
                geo=(--set "body.0.max=[$len,0.75e-3]" --set "boundary.2.min=[$(python3 -c "print($len-1e-5)"),-1.0]")
                [ "${SWARF_DUCOBU_NODAMAGE:-0}" = 1 ] && dmg=(--grid damage.enabled=true,false)
                timeout -s INT "${SWARF_DAMAGE_S:-420}" "$here/swarf" --backend gpu sweep cases/cutting/ducobu.toml --frames --grid "material.name=$models" \
                    --grid damage.fracture_energy=${SWARF_DUCOBU_GF:-20000,10000} "${dmg[@]}" --set 'damage.mask_form="invariant"' \
                    "${geo[@]}" --set discretisation.dx=${SWARF_DUCOBU_DX:-9.3e-6} --set output.every=${SWARF_DUCOBU_EVERY:-2.4e-5} \
                    --set time.end="${SWARF_DUCOBU_END:-1.2e-3}" --batch 8 --out $d/sweep --quiet
                damage_table "$d" > "$out/ducobugf$t.md"; cat "$out/ducobugf$t.md"
                chip_report $d /tmp/ducobugf$t-pics > "$out/ducobugf$t-chip.md"
                tar czf "$out/ducobugf$t-pics.tgz" -C /tmp ducobugf$t-pics
                tar czf "$out/ducobugf$t.tgz" --exclude='*.vtu' --exclude='*.png' --exclude='*.vtp' --exclude='checkpoint.bin' -C /tmp ducobugf$t
            }
            run ducobugf${SWARF_DUCOBU_TAG:-} ducobugf ;;
        taylor24) # issue 24 (docs/3d.md "The Taylor bar on the rigid wall"): cases/3d/taylor-bar-wall.toml with Balsara's
                  # switch at each "dx:cfl" of SWARF_TAYLOR_RUNS (default 0.4, 0.2, 0.1 mm at CFL 0.3 and 0.2 mm at 0.1), f64,
                  # one run at a time (the finest fills the GPU); ci/taylor-foot.py measures each last frame.
                  # taylor24.md, taylor24.tgz (summaries, energy.csv, run.log; no frames).
            taylor24() {
                local d=/tmp/taylor24 spec dx cfl
                rm -rf $d
                for spec in ${SWARF_TAYLOR_RUNS:-0.4e-3:0.3 0.2e-3:0.3 0.1e-3:0.3 0.2e-3:0.1}; do
                    dx=${spec%%:*} cfl=${spec##*:}
                    local t0=$SECONDS
                    "$here/swarf" --backend gpu run cases/3d/taylor-bar-wall.toml --quiet \
                        --out $d/dx$dx-cfl$cfl --set discretisation.dx=$dx --set time.cfl=$cfl --set output.every=8e-5 \
                        --set 'stabilisation.artificial_viscosity.switch="balsara"' 2>&1 | tail -n 3
                    echo "dx $dx cfl $cfl: $((SECONDS - t0)) s wall" | tee -a "$out/taylor24.md"
                    python3 ci/taylor-foot.py $d/dx$dx-cfl$cfl $dx | tee -a "$out/taylor24.md"
                done
                tar czf "$out/taylor24.tgz" --exclude='*.vtu' --exclude='checkpoint.bin' -C /tmp taylor24
            }
            run taylor24 taylor24 ;;
        mu22) # issue 22: V0060 (1 mm) with the defaults over μ, twice each (CFL 0.5, 0.4995): can friction alone bring
              # F_f to the measured 115.5 N/mm with F_c within 10 % of 157.5? mu22.tgz
            run mu22 "$here/swarf" --backend gpu sweep cases/cutting/v0060.toml --grid tool.friction=0.35,0.5,0.7,1.0 \
                --grid time.cfl=0.5,0.4995 --batch 8 --out /tmp/mu22 --quiet
            cat /tmp/mu22/sweep.md
            tar czf "$out/mu22.tgz" --exclude='*.vtu' --exclude='*.png' --exclude='*.vtp' -C /tmp mu22 ;;
        switches22) # issue 22 item 1: the reference cut (1 mm, the original's tool placement) with each of the original
                    # code's switches alone, swarf's defaults and all of them (model = "mfree_iwf"); switches22.tgz
            sw='"swarf","mfree_iwf"'
            for k in c2d_norm c2d_return uintah_rate kernel_w6 glm_slip row_datum sqrt_v_dt abs_cutoff fixed_temperature \
                c2d_conduction; do sw="$sw,[\"$k\"]"; done
            run switches22 "$here/swarf" --backend gpu sweep cases/cutting/reference-cut.toml \
                --set 'tool.position=[-2.44763e-5, 2.0e-4]' --grid "model=$sw" --batch ${SWARF_BATCH:-12} \
                --out /tmp/switches22 --quiet
            cat /tmp/switches22/sweep.md
            tar czf "$out/switches22.tgz" --exclude='*.vtu' --exclude='*.png' -C /tmp switches22 ;;
        contactlong) # issue 22 item 3: V0060 over a 2 mm cut (workpiece 2.87 mm, 8 640 particles), law × ξ × CFL × κ,
                     # twice (the tool 1 nm apart: a replica), so that F_f's window settles; contactlong.tgz
            # SWARF_SWEEP_S bounds it (Ctrl-C: running members stop with a checkpoint; their traces come back)
            run contactlong timeout -s INT "${SWARF_SWEEP_S:-100000}" "$here/swarf" --backend gpu sweep cases/cutting/v0060.toml \
                --set 'body.0.max=[2.87e-3,2.9e-4]' --set 'boundary.2.min=[2.8699e-3,-1.0]' --set time.end=3.1472e-4 \
                --set output.every=6.2944e-6 \
                --grid "tool.contact_law=${SWARF_LAWS:-\"step\",\"bulk\"}" --grid tool.contact_damping=${SWARF_DAMPINGS:-0,1} \
                --grid time.cfl=0.5,0.25 --grid tool.contact_stiffness=0.1,0.2 \
                --grid "tool.position=${SWARF_POSITIONS:-[-3.6e-5],[-3.6001e-5]}" --batch ${SWARF_BATCH:-16} \
                --out /tmp/contactlong --quiet
            cat /tmp/contactlong/sweep.md
            tar czf "$out/contactlong.tgz" --exclude='*.vtu' --exclude='*.png' -C /tmp contactlong ;;
        nonfinite24) # issue 24 (docs/3d.md): the JC micro-milling run folder carried in gpu-pack/jcrun[.tgz] (CPU checkpoint at
                     # step 253 862) resumed with this build and with each packed earlier one (swarf-<name>), each
                     # within SWARF_NONFINITE_LIMIT s (default 240): the CPU reaches non-finite at step 255 356;
                     # the wall time to its report, or the limit
              [ -e "$here/jcrun.tgz" ] && [ ! -d "$here/jcrun" ] && tar xzf "$here/jcrun.tgz" -C "$here"
              for b in "$here"/swarf "$here"/swarf-*; do
                  [ -x "$b" ] && [ -d "$here/jcrun" ] || continue
                  n=$(basename "$b"); d=/tmp/nonfinite24/$n
                  rm -rf "$d"; mkdir -p /tmp/nonfinite24; cp -r "$here/jcrun" "$d"
                  run "nonfinite24-$n" timeout -s INT -k 20 "${SWARF_NONFINITE_LIMIT:-240}" \
                      "$b" --backend gpu run --resume "$d" --accept-changes --quiet
                  tail -n 4 "$d/run.log" >> "$out/nonfinite24-$n.log"
              done ;;
        mill24) # issue 24 (docs/3d.md): the micro-milling scene (cases/3d/micro-milling.toml) with JC and with SCGL, one
                # after the other, at CFL SWARF_MILL_CFL (default: the scene's), each resumed from a carried folder
                # gpu-pack/mill-<model>.tgz where there is one; interrupted (checkpoint written) at SWARF_MILL_DEADLINE
                # s after this part began (default 540). Returns each run's forces, log tail and summary, and an
                # unfinished run's folder without frames as mill-<model>.tgz (carry it to go on)
              t0=$(date +%s)
              for m in JC SCGL; do
                  d=/tmp/mill24/$m; mkdir -p /tmp/mill24
                  [ -e "$here/mill-$m.tgz" ] && [ ! -d "$d" ] && tar xzf "$here/mill-$m.tgz" -C /tmp/mill24
                  left=$(( ${SWARF_MILL_DEADLINE:-540} - ($(date +%s) - t0) ))
                  [ $left -gt 10 ] || break
                  if [ -f "$d/checkpoint.bin" ]; then args=(run --resume "$d" --quiet)
                  else args=(run cases/3d/micro-milling.toml --quiet --out "$d" --set "material.name=\"OFHC-Cu-$m\""
                             ${SWARF_MILL_CFL:+--set time.cfl=$SWARF_MILL_CFL})
                  fi
                  run "mill24-$m" timeout -s INT -k 30 $left "$here/swarf" --backend gpu "${args[@]}"
                  cp "$d/forces.csv" "$out/mill24-$m-forces.csv"
                  { tail -n 6 "$d/run.log"; cat "$d/summary.json" 2>/dev/null; } >> "$out/mill24-$m.log"
                  if [ ! -f "$d/summary.json" ] && grep -q "interrupted" "$d/run.log"; then
                      tar czf "$out/mill-$m.tgz" -C /tmp/mill24 --exclude='*.vtu' --exclude='*.vtp' "$m"
                  fi
              done ;;
        blank24) # issue 24 (docs/3d.md "Blanking"): the single grain (cases/3d/single-grain.toml, CFL SWARF_BLANK_CFL,
                 # default 0.3) whole: without blanking; with a box at rest that holds every particle (the same run,
                 # bit for bit); and with a growing box from 200 µm behind the workpiece to SWARF_BLANK_FRONTS (µm into
                 # it, default "40 115"), its front moving with the grain. Wall times side by side, run.log tails, the
                 # force means over 2-10 µs; then (unless SWARF_BLANK_NO_AB) the default V0060 cut and the reference
                 # cuts' step (bench step) with this build and each packed earlier one (swarf-<name>), for the cost
                 # of the active count on runs without blanking
              for v in plain all ${SWARF_BLANK_FRONTS:-40 115}; do
                  set=(--set "time.cfl=${SWARF_BLANK_CFL:-0.3}")
                  case $v in
                      plain) ;;
                      all) set+=(--set 'blanking.min=[-1.0,-1.0,-1.0]' --set 'blanking.max=[1.0,1.0,1.0]'
                                 --set 'blanking.velocity=[0.0,0.0,0.0]') ;;
                      *) set+=(--set 'blanking.min=[-2.0e-4,-1.0,-1.0]' --set "blanking.max=[${v}.0e-6,1.0,1.0]"
                               --set blanking.grow=true) ;;
                  esac
                  run "blank24-$v" "$here/swarf" --backend gpu run cases/3d/single-grain.toml --quiet \
                      --out "/tmp/blank24/$v" "${set[@]}"
                  { tail -n 5 "/tmp/blank24/$v/run.log"; force_means "/tmp/blank24/$v/forces.csv" 2e-6 1e-5; } \
                      >> "$out/blank24-$v.log"
                  cp "/tmp/blank24/$v/forces.csv" "$out/blank24-$v-forces.csv"
              done
              cmp -s /tmp/blank24/plain/forces.csv /tmp/blank24/all/forces.csv \
                  && echo "forces.csv of plain and all: bitwise equal" || echo "forces.csv of plain and all: DIFFER"
              [ -n "${SWARF_BLANK_NO_AB:-}" ] && continue
              blankab() {
                  local b others; others=$(cd "$here" && ls swarf-* 2>/dev/null | grep -v '\.gz$')
                  for b in swarf $others swarf $others; do
                      echo "== $b"
                      "$here/$b" --backend gpu bench step --precision both --step-count 2048 \
                          --scenes cases/cutting/reference-cut.toml,cases/cutting/reference-cut-150k.toml || return 1
                      local t0=$(date +%s%N)
                      "$here/$b" --backend gpu run cases/cutting/v0060.toml --quiet --out "/tmp/blankab-$b" || return 1
                      echo "v0060 whole: $(( ($(date +%s%N) - t0) / 1000000 )) ms"
                      grep -o '"fc_n_per_mm":[^,]*\|"ff_n_per_mm":[^,]*' "/tmp/blankab-$b/summary.json" | head -2
                      rm -rf "/tmp/blankab-$b"
                  done
              }
              run blank24-ab blankab ;;
        grain2m) # issue 24: the single grain at Röthlin's resolution (cases/3d/single-grain.toml at dx = 1.13 µm: about
                 # 2 M particles, f64), blanked by a growing box (200 µm behind to SWARF_GRAIN_FRONT µm, default 115,
                 # into the workpiece; CFL SWARF_GRAIN_CFL, default the scene's); first the
                 # step's cost without blanking at t = 0 (bench step: ms/step, roofline); then the run, resumed from
                 # /tmp/grain2m where a checkpoint is (the same warm machine), interrupted with a checkpoint at
                 # SWARF_GRAIN_DEADLINE s (default 520); log tail, summary, force means over 2-10 µs. SWARF_GRAIN_BENCH=0
                 # leaves the bench out; SWARF_GRAIN_REAR (µm, default -200) the box's rear at t = 0, SWARF_GRAIN_GROW=false
                 # a translating box
              d=/tmp/grain2m
              sed 's/^dx = 3.0e-6/dx = 1.13e-6/' cases/3d/single-grain.toml > cases/3d/single-grain-2m.toml
              [ -f "$d/checkpoint.bin" ] || [ "${SWARF_GRAIN_BENCH:-1}" = 0 ] || run grain2m-bench "$here/swarf" --backend gpu bench step --precision f64 \
                  --step-count 64 --scenes cases/3d/single-grain-2m.toml
              # SWARF_GRAIN_STATE_AT (steps, comma separated): state tables before a blow-up, and what stands out in
              # them (ci/state-anomalies.py: grain2m-state.log, grain2m-state-*.csv)
              if [ -f "$d/checkpoint.bin" ]; then args=(run --resume "$d" --quiet)
              else args=(run cases/3d/single-grain-2m.toml --quiet --out "$d" --set output.every=1.0e-6
                         --set "blanking.min=[${SWARF_GRAIN_REAR:--200}.0e-6,-1.0,-1.0]"
                         --set "blanking.max=[${SWARF_GRAIN_FRONT:-115}.0e-6,1.0,1.0]"
                         --set "blanking.grow=${SWARF_GRAIN_GROW:-true}" ${SWARF_GRAIN_CFL:+--set time.cfl=$SWARF_GRAIN_CFL})
              fi
              run grain2m timeout -s INT -k 90 "${SWARF_GRAIN_DEADLINE:-520}" "$here/swarf" --backend gpu "${args[@]}" \
                  ${SWARF_GRAIN_STATE_AT:+--state-at $SWARF_GRAIN_STATE_AT}
              [ -d "$d/states" ] && python3 ci/state-anomalies.py "$d/states" "$out/grain2m-state" 1e-5 \
                  > "$out/grain2m-state.log" 2>&1
              { tail -n 8 "$d/run.log"; cat "$d/summary.json" 2>/dev/null; force_means "$d/forces.csv" 2e-6 1e-5; } \
                  >> "$out/grain2m.log"
              cp "$d/forces.csv" "$out/grain2m-forces.csv"
              # a finished run: its last frame's plastic strain seen along z and along x (PNG)
              [ -f "$d/summary.json" ] && [ "${SWARF_GRAIN_RENDER:-1}" = 1 ] && for ax in z x; do
                  "$here/swarf" render "$d" --field eps --frame last --along $ax --out "$out/grain2m-render-$ax" \
                      >> "$out/grain2m.log" 2>&1
              done ;;
        grainres) # issue 24: the single grain (cases/3d/single-grain.toml) whole at Δx = SWARF_GRAIN_DXS µm (default
                  # "2.0 1.5"), f64, CFL 0.3, blanked as grain2m (a growing box 200 µm behind the workpiece to 115 µm
                  # into it): does the 2 M run's blow-up near 8 µs come at coarser spacings too? Each run bounded by
                  # SWARF_GRAIN_DEADLINE s (default 200); its log tail (the non-finite report says where) and force means
              for dxu in ${SWARF_GRAIN_DXS:-2.0 1.5}; do
                  d=/tmp/grainres/$dxu; rm -rf "$d"
                  run "grainres-$dxu" timeout -s INT -k 30 "${SWARF_GRAIN_DEADLINE:-200}" "$here/swarf" --backend gpu run \
                      cases/3d/single-grain.toml --quiet --out "$d" --set "discretisation.dx=${dxu}e-6" \
                      --set output.every=1.0e-6 --set time.cfl=0.3 --set 'blanking.min=[-2.0e-4,-1.0,-1.0]' \
                      --set 'blanking.max=[115.0e-6,1.0,1.0]' --set blanking.grow=true
                  { echo "## dx = $dxu um"; tail -n 4 "$out/grainres-$dxu.log"; tail -n 12 "$d/run.log"
                    force_means "$d/forces.csv" 2e-6 1e-5; } >> "$out/grainres.log"
                  cp "$d/forces.csv" "$out/grainres-$dxu-forces.csv" 2>/dev/null
              done ;;
        ortho5) # issue 24 (docs/3d.md, the extruded V0060): orthosw's base at Δx = SWARF_ORTHO_DX (default 5.0e-6):
                # do F_c and F_f converge towards each other?
              ortho_variants "${SWARF_ORTHO_DX:-5.0e-6}" base ;;
        orthosw) # issue 24: ortho_variants at Δx = SWARF_ORTHO_DX (default 1.0e-5) for each of SWARF_ORTHO_VARIANTS
                 # (default: base as0 xsph0 mu0 hproj)
              ortho_variants "${SWARF_ORTHO_DX:-1.0e-5}" ${SWARF_ORTHO_VARIANTS:-base as0 xsph0 mu0 hproj} ;;
        grain2mplain) # issue 24: the 2 M-particle single grain of grain2m without blanking, to SWARF_GRAIN_END s (default
                      # 2.3e-6: past where the blanked runs went non-finite), CFL SWARF_GRAIN_CFL (default the scene's)
              sed 's/^dx = 3.0e-6/dx = 1.13e-6/' cases/3d/single-grain.toml > cases/3d/single-grain-2m.toml
              d=/tmp/grain2mplain; rm -rf "$d"
              run grain2mplain timeout -s INT -k 90 "${SWARF_GRAIN_DEADLINE:-520}" "$here/swarf" --backend gpu run \
                  cases/3d/single-grain-2m.toml --quiet --out "$d" --set output.every=5.0e-7 \
                  --set "time.end=${SWARF_GRAIN_END:-2.3e-6}" ${SWARF_GRAIN_CFL:+--set time.cfl=$SWARF_GRAIN_CFL}
              { tail -n 8 "$d/run.log"; force_means "$d/forces.csv" 1e-6 3e-6; } >> "$out/grain2mplain.log"
              cp "$d/forces.csv" "$out/grain2mplain-forces.csv" ;;
        wide24) # issue 24 (docs/neighbour-search.md "Wide offsets"): bench step, f64, of the 3D scenes with the Verlet
                # list's 16- and 32-bit offsets side by side (bench step's list rows): the 2 M-particle single grain
                # (64 steps), the 107k single grain and the extruded V0060 (256 steps)
              sed 's/^dx = 3.0e-6/dx = 1.13e-6/' cases/3d/single-grain.toml > cases/3d/single-grain-2m.toml
              run wide24-2m "$here/swarf" --backend gpu bench step --precision f64 --step-count 64 \
                  --scenes cases/3d/single-grain-2m.toml
              run wide24 "$here/swarf" --backend gpu bench step --precision f64 --step-count 256 \
                  --scenes cases/3d/single-grain.toml,cases/3d/orthogonal-v0060.toml ;;
        mpm26) # issue 26 (docs/mpm.md): Nairn's cut with MPM at the paper's resolution (15 particles through h):
               # V1/V2 (rake 30°) and V3 (rake 15°) at h = SWARF_MPM_DEPTHS (default 0.25 0.5 0.75 1.0 1.5 mm), each
               # run's summary line; the V15 bonds in f64 on the GPU. SWARF_MPM_SETS: further --set arguments.
              mpm() { # name, scene, --set arguments...
                  local name=$1 scene=$2; shift 2
                  "$here/swarf" --backend gpu run "$scene" --force --out "/tmp/mpm/$name" "$@" ${SWARF_MPM_SETS:-} \
                      2>&1 | grep -v "^mpm: t" | sed "s/^/$name: /"
                  cp "/tmp/mpm/$name/forces.csv" "$out/mpm-$name-forces.csv" 2>/dev/null
                  cp "/tmp/mpm/$name/summary.json" "$out/mpm-$name-summary.json" 2>/dev/null
              }
              mpm_all() {
                  for m in 1 2; do mpm bond$m cases/mpm/bond-mode$m.toml; done
                  # The step time with and without captured batches, one point each, side by side.
                  SWARF_NO_GRAPHS=1 mpm plain-a30-h1.0 cases/mpm/nairn-cut.toml
                  for a in ${SWARF_MPM_RAKES:-30 15}; do
                      for h in ${SWARF_MPM_DEPTHS:-0.25 0.5 0.75 1.0 1.5}; do
                          mpm "a$a-h$h" cases/mpm/nairn-cut.toml --set "cut.depth=${h}e-3" --set "cut.rake=$a"
                      done
                  done
                  # V5 (the transition at 30°) and V12 (PIC damping off at h = 0.9 mm), unless SWARF_MPM_SHORT.
                  [ -n "${SWARF_MPM_SHORT:-}" ] && return
                  for h in 2.0 2.5 3.0; do
                      mpm "a30-h$h" cases/mpm/nairn-cut.toml --set "cut.depth=${h}e-3"
                  done
                  for pic in 1.0 0.0; do
                      mpm "a30-h0.9-pic$pic" cases/mpm/nairn-cut.toml --set cut.depth=0.9e-3 --set "damping.pic=$pic"
                  done
              }
              run mpm26 mpm_all ;;
        sph26) # issue 26 (docs/mpm.md "SPH against MPM"): V1 with the SPH cohesive path: Nairn's cut in SPH
               # (cases/mpm/nairn-cut-sph.toml, 15 particles through h) at h = SWARF_SPH_DEPTHS mm (default 0.5 1.0 1.5),
               # the scene scaled with h; then the MPM twin (cases/mpm/nairn-cut.toml) at the same depths; each run's
               # summary and forces. SWARF_SPH_SETS, SWARF_MPM_SETS: further --set arguments of the SPH and MPM runs;
               # SWARF_SPH_NO_MPM: the SPH runs only; SWARF_SPH_FRAMES: every fourth frame of each SPH run.
              sph_at() { # h in mm, name, further --set arguments
                  local h=$1 name=$2; shift 2
                  local s; s=$(python3 -c "h=$h*1e-3; print(' '.join('--set %s' % a for a in [
                      'discretisation.dx=%r' % (h/15), 'body.0.min=[0.0,%r]' % (-3*h), 'body.0.max=[%r,%r]' % (30*h, h),
                      'boundary.0.max=[1.0,%r]' % (-3*h + 2*h/15 - h/150), 'cohesive.extent=[0.0,%r]' % (18*h),
                      'cohesive.traction_free=[0.0,%r]' % (2*h), 'tool.length=%r' % (8*h), 'tool.height=%r' % (6*h),
                      'tool.position=[%r]' % (-h/15), 'tool.depth_of_cut=%r' % h, 'tool.ramp=%r' % (0.3*12*h/(0.85*2)),
                      'time.end=%r' % (12*h/(0.85*2)), 'output.every=%r' % (12*h/(0.85*2)/20)]))")
                  # shellcheck disable=SC2086
                  "$here/swarf" --backend gpu run cases/mpm/nairn-cut-sph.toml --force --quiet --out "/tmp/sph/$name" \
                      $s "$@" ${SWARF_SPH_SETS:-} 2>&1 | tail -n 4 | sed "s/^/$name: /"
                  cp "/tmp/sph/$name/forces.csv" "$out/sph-$name-forces.csv" 2>/dev/null
                  cp "/tmp/sph/$name/energy.csv" "$out/sph-$name-energy.csv" 2>/dev/null
                  cp "/tmp/sph/$name/summary.json" "$out/sph-$name-summary.json" 2>/dev/null
                  if [ -n "${SWARF_SPH_FRAMES:-}" ]; then
                      tar czf "$out/sph-$name-frames.tgz" -C "/tmp/sph/$name" $(cd "/tmp/sph/$name" && ls frame_*.vtu \
                          | awk 'NR % 4 == 1') 2>/dev/null
                  fi
              }
              sph_all() {
                  for h in ${SWARF_SPH_DEPTHS:-0.5 1.0 1.5}; do sph_at "$h" "h$h"; done
                  [ -n "${SWARF_SPH_NO_MPM:-}" ] && return
                  for h in ${SWARF_SPH_DEPTHS:-0.5 1.0 1.5}; do
                      "$here/swarf" --backend gpu run cases/mpm/nairn-cut.toml --force --out "/tmp/sph/mpm-h$h" \
                          --set "cut.depth=${h}e-3" ${SWARF_MPM_SETS:-} 2>&1 | grep -v "^mpm: t" | tail -n 3 \
                          | sed "s/^/mpm-h$h: /"
                      cp "/tmp/sph/mpm-h$h/summary.json" "$out/mpm-h$h-summary.json" 2>/dev/null
                  done
              }
              run sph26 sph_all ;;
        mpmsweep) # issue 26 (docs/mpm.md "Sweeps"): MPM points as one batched ensemble (`swarf sweep`, a stream each).
                  # (1) throughput: 8 short cuts (cut_length 3 h, paper resolution) one at a time and 8 at once, and
                  # 16 at once (unless SWARF_MPM_FIGURE_ONLY); (2) unless SWARF_MPM_PROBE_ONLY, a whole h x rake x friction figure (10 x 2 x 5 = 100
                  # points, cut_length SWARF_MPM_LENGTH, default the scene's) at --batch SWARF_MPM_BATCH (default 16),
                  # in the background so that its table survives the call's limit (sweep.md is rewritten per point).
              mpm_probe() {
                  local short=(--set cut.cut_length=3.0)
                  mpm_sweep probe8-serial 1 0 "${short[@]}" --grid cut.friction=0,0.05,0.1,0.15,0.2,0.25,0.3,0.35
                  mpm_sweep probe8-batch8 8 0 "${short[@]}" --grid cut.friction=0,0.05,0.1,0.15,0.2,0.25,0.3,0.35
                  mpm_sweep probe16-batch16 16 0 "${short[@]}" \
                      --grid cut.friction=0,0.05,0.1,0.15,0.2,0.25,0.3,0.35 --grid cut.rake=30,15
              }
              [ -z "${SWARF_MPM_FIGURE_ONLY:-}" ] && run mpmprobe mpm_probe
              [ -n "${SWARF_MPM_PROBE_ONLY:-}" ] && continue
              (
                  len=${SWARF_MPM_LENGTH:+--set cut.cut_length=$SWARF_MPM_LENGTH}
                  mpm_sweep figure "${SWARF_MPM_BATCH:-16}" 0 $len \
                      --grid cut.depth=0.25e-3,0.5e-3,0.75e-3,1.0e-3,1.25e-3,1.5e-3,2.0e-3,2.5e-3,3.0e-3,3.5e-3 \
                      --grid cut.rake=30,15 --grid cut.friction=0,0.1,0.2,0.4,0.6
              ) > "$out/mpmfigure.log" 2>&1 &
              figure=$!
              limit=${SWARF_WAIT_LIMIT:-420}
              t0=$(date +%s.%N)
              for ((i = 0; i < limit; i += 5)); do kill -0 $figure 2>/dev/null || break; sleep 5; done
              kill -0 $figure 2>/dev/null && { pkill -INT -f "swarf --backend gpu sweep" ; sleep 5; }
              keep_sweeps figure
              echo "figure: $(grep -c ',ok,' /tmp/mpmsweep/figure/sweep.csv 2>/dev/null) points done, \
$(grep -c ',failed,' /tmp/mpmsweep/figure/sweep.csv 2>/dev/null) failed, after \
$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s" \
                  >> "$out/mpmfigure.log"
              summary+=("$(printf '%-12s %s' mpmfigure "$(tail -n 1 "$out/mpmfigure.log")")") ;;
        mpmdamp) # issue 26 (docs/mpm.md "Start-up damping", V12): two batched MPM sweeps at 30°, mu = 0: the start-up
                 # feedback gain (0, 100, 1000, 10000) over h = 0.25 ... 2.0 mm, and the PIC fraction (1, 0.9, 0.5)
                 # at h = 0.5 and 1.0 mm without feedback. Tables under $out/mpmsweep-*.md/csv.
              mpm_damp() {
                  local name batch
                  for name in feedback pic; do
                      local t0=$(date +%s.%N)
                      case $name in
                          feedback) set -- --grid cut.depth=0.25e-3,0.5e-3,0.75e-3,1.0e-3,1.5e-3,2.0e-3 \
                                        --grid damping.feedback=0,100,1000,10000 ;;
                          pic) set -- --grid cut.depth=0.5e-3,1.0e-3 --grid damping.pic=1.0,0.9,0.5 ;;
                      esac
                      "$here/swarf" --backend gpu sweep cases/mpm/nairn-cut.toml --quiet --batch 24 \
                          --out "/tmp/mpmsweep/$name" "$@"
                      echo "$name: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                      keep_sweeps "$name"
                  done
              }
              run mpmdamp mpm_damp ;;
        mpmv) # issue 26 (docs/mpm.md): V6 (the transition with sigma_c = 10 MPa against 40 at 30°, mu = 0), V11 (h = 0.9
              # mm at 7, 15 and 31 particles through h), as batched sweeps; and the frames (particles.pvd, VTU) of
              # V16 (h = 0.5 mm, rake 15°, E_T = 100 MPa) and of the cut that went non-finite at h = 0.25 mm, rake 15°,
              # their last 6 frames packed into $out/logs-mpm-<run>.tgz (beside logs.tgz).
              mpm_v() {
                  local sweep=("$here/swarf" --backend gpu sweep cases/mpm/nairn-cut.toml --quiet --batch 24)
                  local t0=$(date +%s.%N)
                  "${sweep[@]}" --out /tmp/mpmsweep/v6 --grid cohesive.peak=40e6,10e6 \
                      --grid cut.depth=0.5e-3,0.75e-3,1.0e-3,1.25e-3,1.5e-3,2.0e-3 &
                  "${sweep[@]}" --out /tmp/mpmsweep/v11 --grid cut.particles_across=7,15,31 --set cut.depth=0.9e-3 &
                  for run in v16 fail025; do
                      case $run in
                          v16) set -- --set cut.depth=0.5e-3 --set cut.rake=15 --set material.tangent_modulus=100e6 ;;
                          fail025) set -- --set cut.depth=0.25e-3 --set cut.rake=15 ;;
                      esac
                      "$here/swarf" --backend gpu run cases/mpm/nairn-cut.toml --quiet --force --out "/tmp/mpm/$run" \
                          --set time.frames=60 "$@" 2>&1 | tail -3 &
                  done
                  wait
                  echo "all: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  keep_sweeps v6 v11
                  # The last 6 frames of each (VTU; the runs' summaries and forces whole).
                  for r in v16 fail025; do
                      (cd /tmp/mpm && tar czf "$out/logs-mpm-$r.tgz" "$r"/*.json "$r"/*.csv "$r"/particles.pvd \
                          $(ls "$r"/frames/*.vtu | tail -n 6))
                  done
              }
              run mpmv mpm_v ;;
        mpmedge) # issue 26 (docs/mpm.md "Stability"): after the contact normal by the field's side of the crack: the
                 # figure's depths x rake 30, 15 x mu = 0, 0.2 (40 points, --batch 16) and, beside it, V11 (h = 0.9
                 # mm at 7, 15 and 31 particles through h); tables under $out/mpmsweep-edge*.md/csv.
              mpm_edge() {
                  local sweep=("$here/swarf" --backend gpu sweep cases/mpm/nairn-cut.toml --quiet)
                  local t0=$(date +%s.%N)
                  "${sweep[@]}" --batch 16 --out /tmp/mpmsweep/edge \
                      --grid cut.depth=0.25e-3,0.5e-3,0.75e-3,1.0e-3,1.25e-3,1.5e-3,2.0e-3,2.5e-3,3.0e-3,3.5e-3 \
                      --grid cut.rake=30,15 --grid cut.friction=0,0.2 &
                  "${sweep[@]}" --batch 3 --out /tmp/mpmsweep/edge-v11 --grid cut.particles_across=7,15,31 \
                      --set cut.depth=0.9e-3 &
                  wait
                  echo "both: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  keep_sweeps edge edge-v11
              }
              run mpmedge mpm_edge ;;
        mpmv5) # issue 26 (docs/mpm.md): `swarf bench mpm` (the default cut at 15 and 31 particles through h, f64 and
               # f32), then V5's transition against the start-up: h = 1.5, 1.75, 2.0 mm x ramp 0.3, 0.6 x cut length
               # 12, 20 h (30°, mu = 0), one batched sweep.
              run mpmbench bash -c "'$here/swarf' --backend gpu bench mpm --step-count 2000 && \
                  '$here/swarf' --backend gpu bench mpm --step-count 1000 --set cut.particles_across=31"
              mpm_v5() {
                  local t0=$(date +%s.%N)
                  "$here/swarf" --backend gpu sweep cases/mpm/nairn-cut.toml --quiet --batch 12 --out /tmp/mpmsweep/v5 \
                      --grid cut.depth=1.5e-3,1.75e-3,2.0e-3 --grid cut.ramp=0.3,0.6 --grid cut.cut_length=12,20
                  echo "v5: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  keep_sweeps v5
              }
              run mpmv5 mpm_v5 ;;
        mpmv78) # issue 26 (docs/mpm.md "V5, V7, V8"): three batched sweeps at once (30°/15°/45°, mu = 0):
                # V7 E_T = 0, 10, 25, 100 MPa x h 0.5-2.5 mm (30°); V8 E_T = 100 MPa x rake 15, 30, 45 x h 0.1-7 mm;
                # V5 at the transition: h 1.25-2.0 mm x 15 and 31 particles through h. Tables under $out/mpmsweep-*.
              mpm_v78() {
                  local sweep=("$here/swarf" --backend gpu sweep cases/mpm/nairn-cut.toml --quiet)
                  local t0=$(date +%s.%N)
                  "${sweep[@]}" --batch 12 --out /tmp/mpmsweep/v7 --grid material.tangent_modulus=0,10e6,25e6,100e6 \
                      --grid cut.depth=0.5e-3,1.0e-3,1.25e-3,1.5e-3,2.0e-3,2.5e-3 &
                  "${sweep[@]}" --batch 12 --out /tmp/mpmsweep/v8 --set material.tangent_modulus=100e6 \
                      --grid cut.rake=15,30,45 --grid cut.depth=0.1e-3,0.25e-3,0.5e-3,1.0e-3,2.0e-3,3.0e-3,5.0e-3,7.0e-3 &
                  "${sweep[@]}" --batch 8 --out /tmp/mpmsweep/v5res --grid cut.particles_across=15,31 \
                      --grid cut.depth=1.25e-3,1.5e-3,1.75e-3,2.0e-3 &
                  wait
                  echo "all: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  keep_sweeps v7 v8 v5res
              }
              run mpmv78 mpm_v78 ;;
        mpmv5fine) # issue 26 (docs/mpm.md "V5, V7, V8"): V1 and V5 at 31 particles through h (30°, mu = 0: h 0.25-1.0
                   # and 2.25-3.0 mm) and, beside them, V8's points whose chip left the grid, with twice the room
                   # (E_T = 100 MPa). Each sweep stops at 560 s; its table holds the points finished by then.
              mpm_v5fine() {
                  local sweep=(timeout -s INT 560 "$here/swarf" --backend gpu sweep cases/mpm/nairn-cut.toml --quiet)
                  local t0=$(date +%s.%N)
                  "${sweep[@]}" --batch 7 --out /tmp/mpmsweep/v5fine --set cut.particles_across=31 \
                      --grid cut.depth=0.25e-3,0.5e-3,0.75e-3,1.0e-3,2.25e-3,2.5e-3,3.0e-3 &
                  "${sweep[@]}" --batch 9 --out /tmp/mpmsweep/v8room --set material.tangent_modulus=100e6 --set cut.room=20 \
                      --grid cut.rake=15,30,45 --grid cut.depth=3.0e-3,5.0e-3,7.0e-3 &
                  wait
                  echo "all: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  keep_sweeps v5fine v8room
              }
              run mpmv5fine mpm_v5fine ;;
        mpmv14) # issue 26 (docs/mpm.md "Position updates", "Traction laws"): three batched sweeps at once (30°, mu = 0):
                # V14, the position update second/first/zeroth x h 0.5, 1.0 mm at 15 particles through h, and
                # second/zeroth at h = 1 mm at 31, each with the glyph test's coverage; V1 with the triangular law
                # (h 0.25-2.0 mm, 15 through h). Each sweep stops at 540 s. Tables under $out/mpmsweep-*.
              mpm_v14() {
                  local sweep=(timeout -s INT 540 "$here/swarf" --backend gpu sweep cases/mpm/nairn-cut.toml --quiet)
                  local t0=$(date +%s.%N)
                  "${sweep[@]}" --batch 6 --out /tmp/mpmsweep/v14 --grid damping.position_update='"second"','"first"','"zeroth"' \
                      --grid cut.depth=0.5e-3,1.0e-3 &
                  "${sweep[@]}" --batch 2 --out /tmp/mpmsweep/v14fine --set cut.particles_across=31 \
                      --grid damping.position_update='"second"','"zeroth"' &
                  "${sweep[@]}" --batch 7 --out /tmp/mpmsweep/tri --set cohesive.law='"triangular"' \
                      --grid cut.depth=0.25e-3,0.5e-3,0.75e-3,1.0e-3,1.25e-3,1.5e-3,2.0e-3 &
                  wait
                  echo "all: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  keep_sweeps v14 v14fine tri
              }
              run mpmv14 mpm_v14 ;;
        mpm025ck) # issue 26 (docs/mpm.md "Stability"): V1's h = 0.25 mm at 31 particles through h, which blows up at
                  # step 213 465 of 266 331 (80.2 %), interrupted (SIGINT) once its progress passes SWARF_CK_PCT %
                  # (default 70): its checkpoint comes back as mpm025ck.tgz (split if large), to resume on the CPU
                  # (bitwise the GPU's) with frames close together up to the failure.
              mpm_025ck() {
                  local d=/tmp/mpm/ck025 log=/tmp/mpm/ck025.log pct=${SWARF_CK_PCT:-70}
                  rm -rf $d; mkdir -p /tmp/mpm
                  "$here/swarf" --backend gpu run cases/mpm/nairn-cut.toml --force --out $d \
                      --set cut.depth=0.25e-3 --set cut.particles_across=31 > $log 2>&1 &
                  local pid=$!
                  while kill -0 $pid 2>/dev/null; do
                      local now=$(grep -oE '\([0-9]+ %\)' $log | tail -1 | tr -dc '0-9')
                      if [ -n "$now" ] && [ "$now" -ge "$pct" ]; then kill -INT $pid; break; fi
                      sleep 0.5
                  done
                  wait $pid; tail -n 5 $log
                  (cd /tmp/mpm && tar czf "$out/mpm025ck.tgz" ck025/checkpoint.bin ck025/scene.toml ck025/forces.csv \
                      ck025/particles.pvd ck025.log)
                  ls -la "$out/mpm025ck.tgz"
              }
              run mpm025ck mpm_025ck ;;
        mpmv10) # issue 26 (docs/mpm.md "V10"): the base depth d = 2, 3, 4, 5 h at h = 0.9 mm (30°, mu = 0) at 15
                # particles through h and d = 3, 5 at 31, since the contact fix; beside them V1's h = 0.25 mm at 31
                # through h, which blew up, with 80 frames (its last 6 frames come back as logs-mpm-fail025fine.tgz).
              mpm_v10() {
                  local sweep=(timeout -s INT 560 "$here/swarf" --backend gpu sweep cases/mpm/nairn-cut.toml --quiet)
                  local t0=$(date +%s.%N)
                  "${sweep[@]}" --batch 4 --out /tmp/mpmsweep/v10 --set cut.depth=0.9e-3 --grid cut.base=2,3,4,5 &
                  "${sweep[@]}" --batch 2 --out /tmp/mpmsweep/v10fine --set cut.depth=0.9e-3 \
                      --set cut.particles_across=31 --grid cut.base=3,5 &
                  timeout -s INT 560 "$here/swarf" --backend gpu run cases/mpm/nairn-cut.toml --quiet --force \
                      --out /tmp/mpm/fail025fine --set cut.depth=0.25e-3 --set cut.particles_across=31 \
                      --set time.frames=80 2>&1 | tail -3 &
                  wait
                  echo "all: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  keep_sweeps v10 v10fine
                  local r=fail025fine
                  (cd /tmp/mpm && tar czf "$out/logs-mpm-$r.tgz" "$r"/*.json "$r"/*.csv "$r"/*.log "$r"/particles.pvd \
                      $(ls "$r"/frames/*.vtu | tail -n 6))
              }
              run mpmv10 mpm_v10 ;;
        mpmv1frag) # issue 26 (docs/mpm.md "Stray particles", "Fragments"): V1 with the stray and fragment rules, two
                   # batched sweeps at once (30°, mu = 0): h 0.25-1.5 mm at 31 particles through h (the 0.25 mm point
                   # blew up before the rules) and at 15; runs untouched by the rules give the earlier bits. Each
                   # sweep stops at SWARF_SWEEP_S s (default 540).
              mpm_v1frag() {
                  local sweep=(timeout -s INT "${SWARF_SWEEP_S:-540}" "$here/swarf" --backend gpu sweep
                      cases/mpm/nairn-cut.toml --quiet)
                  local t0=$(date +%s.%N)
                  "${sweep[@]}" --batch 6 --out /tmp/mpmsweep/v1fine --set cut.particles_across=31 \
                      --grid cut.depth=0.25e-3,0.5e-3,0.75e-3,1.0e-3,1.25e-3,1.5e-3 &
                  "${sweep[@]}" --batch 6 --out /tmp/mpmsweep/v1 \
                      --grid cut.depth=0.25e-3,0.5e-3,0.75e-3,1.0e-3,1.25e-3,1.5e-3 &
                  wait
                  echo "all: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  keep_sweeps v1fine v1
              }
              run mpmv1frag mpm_v1frag ;;
        mpmgrid) # issue 26: one batched sweep of cases/mpm/nairn-cut.toml with the --set/--grid arguments of
                 # SWARF_MPM_ARGS (split at spaces), named SWARF_MPM_NAME (default grid), --batch SWARF_MPM_BATCH
                 # (default 8), stopped at SWARF_SWEEP_S s (default 540); $out/mpmsweep-<name>.{md,csv}.
              # shellcheck disable=SC2086 # the arguments are words on purpose
              run mpmgrid mpm_sweep "${SWARF_MPM_NAME:-grid}" "${SWARF_MPM_BATCH:-8}" "${SWARF_SWEEP_S:-540}" \
                  ${SWARF_MPM_ARGS:-} ;;
        mpmv8fine) # issue 26 (docs/mpm.md "V8 at 31 particles"): V8's bending regime (E_T = 100 MPa, mu = 0) at 31
                   # particles through h, rakes 15/30/45 x h 3, 5, 7 mm, room 20 h, as one batched sweep (is the
                   # fall beyond 3-5 mm at 15 particles the resolution's, as V5's early transition was?). Stops at
                   # SWARF_SWEEP_S s (default 560).
              run mpmv8fine mpm_sweep v8fine 9 "${SWARF_SWEEP_S:-560}" --set cut.particles_across=31 \
                  --set material.tangent_modulus=100e6 --set cut.room=20 \
                  --grid cut.rake=15,30,45 --grid cut.depth=3.0e-3,5.0e-3,7.0e-3 ;;
        mpmv8path) # issue 26 (docs/mpm.md "V8 and the crack path's end"): V8's bending regime (E_T = 100 MPa, mu = 0,
                   # room 20 h) with the crack path lengthened from 18 to 24 h (specimen 36 h wide, so that 12 h stay
                   # uncut) at 15 particles through h (rakes 15/30/45 x h 3, 5, 7 mm) and at 31 (30 deg, 5 and 7 mm),
                   # and with the tool's travel shortened from 12 to 9 h (30 deg, 3/5/7 mm, 15 through h): three
                   # batched sweeps at once, each stopped at SWARF_SWEEP_S s (default 560).
              mpm_v8path() {
                  local sweep=(timeout -s INT "${SWARF_SWEEP_S:-560}" "$here/swarf" --backend gpu sweep
                      cases/mpm/nairn-cut.toml --quiet --set material.tangent_modulus=100e6 --set cut.room=20)
                  local t0=$(date +%s.%N)
                  "${sweep[@]}" --batch 9 --out /tmp/mpmsweep/v8path --set cut.crack=24 --set cut.width=36 \
                      --grid cut.rake=15,30,45 --grid cut.depth=3.0e-3,5.0e-3,7.0e-3 &
                  "${sweep[@]}" --batch 2 --out /tmp/mpmsweep/v8pathfine --set cut.crack=24 --set cut.width=36 \
                      --set cut.particles_across=31 --set cut.rake=30 --grid cut.depth=5.0e-3,7.0e-3 &
                  "${sweep[@]}" --batch 3 --out /tmp/mpmsweep/v8short --set cut.cut_length=9 --set cut.rake=30 \
                      --grid cut.depth=3.0e-3,5.0e-3,7.0e-3 &
                  wait
                  echo "all: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  keep_sweeps v8path v8pathfine v8short
              }
              run mpmv8path mpm_v8path ;;
        mpmv8long) # issue 26 (docs/mpm.md "V8 and the tool's travel"): V8's bending regime (E_T = 100 MPa, mu = 0, room
                   # 20 h, 15 particles through h) with the tool's travel lengthened from 12 to 18 h (crack 30 h,
                   # specimen 42 h wide, so that 12 h stay uncut): rakes 15/30/45 x h 3, 5, 7 mm, one batched sweep
                   # stopped at SWARF_SWEEP_S s (default 560).
              mpm_v8long() {
                  local t0=$(date +%s.%N)
                  timeout -s INT "${SWARF_SWEEP_S:-560}" "$here/swarf" --backend gpu sweep cases/mpm/nairn-cut.toml \
                      --quiet --batch 9 --out /tmp/mpmsweep/v8long --set material.tangent_modulus=100e6 \
                      --set cut.room=20 --set cut.cut_length=18 --set cut.crack=30 --set cut.width=42 \
                      --grid cut.rake=15,30,45 --grid cut.depth=3.0e-3,5.0e-3,7.0e-3
                  echo "all: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  keep_sweeps v8long
              }
              run mpmv8long mpm_v8long ;;
        mpm26b) # issue 26 (docs/mpm.md): V7 (hardening: E_T 25 and 100 MPa at 30°), V10 (base depth 2 and 4 at
                # h = 0.9 mm), and the GPU time of each MPM kernel over two steps (ncu, after 2000 steps)
              mpm_b() {
                  for et in 25 100; do
                      for h in 0.5 1.0 1.5 2.0; do
                          mpm "a30-et$et-h$h" cases/mpm/nairn-cut.toml --set "cut.depth=${h}e-3" \
                              --set "material.tangent_modulus=${et}e6"
                      done
                  done
                  for d in 2.0 4.0; do
                      mpm "a30-h0.9-d$d" cases/mpm/nairn-cut.toml --set cut.depth=0.9e-3 --set "cut.base=$d"
                  done
              }
              mpm() { # name, scene, --set arguments...
                  local name=$1 scene=$2; shift 2
                  "$here/swarf" --backend gpu run "$scene" --force --out "/tmp/mpm/$name" "$@" 2>&1 \
                      | grep -v "^mpm: t" | sed "s/^/$name: /"
                  cp "/tmp/mpm/$name/forces.csv" "$out/mpm-$name-forces.csv" 2>/dev/null
                  cp "/tmp/mpm/$name/summary.json" "$out/mpm-$name-summary.json" 2>/dev/null
              }
              run mpm26b mpm_b
              run ncu-mpm ncu --launch-skip 24000 --launch-count 24 --metrics gpu__time_duration.sum \
                  "$here/swarf" --backend gpu run cases/mpm/nairn-cut.toml --force --out /tmp/mpm/ncu \
                  --set time.end=2.2e-4 ;;
        wheel24) # issue 24 (docs/3d.md "Grinding wheel"): the wheel segment in Pinto's patterns
                 # (cases/3d/grinding-wheel-*.toml; SWARF_WHEEL_PATTERNS, default "a b c"), one after another (three
                 # processes at once ran 1.47x slower in all: they time-slice the GPU), each stopped with a checkpoint
                 # at SWARF_WHEEL_DEADLINE s (default 480); per-grain wear and forces (ci/wheel-wear.py), and pictures
                 # of the last frames seen from above (plastic strain, temperature) in $OUT/wheelpics/;
                 # SWARF_WHEEL_SETS: extra `--set` arguments for every pattern (e.g. CSPM)
              wheel() {
                  local patterns=${SWARF_WHEEL_PATTERNS:-a b c}
                  for p in $patterns; do
                      local t0=$(date +%s.%N)
                      timeout -s INT -k 30 "${SWARF_WHEEL_DEADLINE:-480}" "$here/swarf" --backend gpu run \
                          "cases/3d/grinding-wheel-$p.toml" --quiet --force --out "/tmp/wheel/$p" ${SWARF_WHEEL_SETS:-} \
                          > "/tmp/wheel-$p.log" 2>&1
                      echo "$p: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s wall"
                  done
                  mkdir -p "$out/wheelpics"
                  for p in $patterns; do
                      cat "/tmp/wheel-$p.log"; tail -n 4 "/tmp/wheel/$p/run.log"
                      cp "/tmp/wheel/$p/forces.csv" "$out/wheel-$p-forces.csv"
                      cp "/tmp/wheel/$p/summary.json" "$out/wheel-$p-summary.json" 2>/dev/null
                      python3 ci/wheel-wear.py "/tmp/wheel/$p/forces.csv" "pattern $p"
                      for fld in eps T; do
                          # the workpiece (z ±50 µm, x 0-400 µm) and the chips just ahead of it: stray particles
                          # thrown far out would otherwise shrink it to a sliver
                          "$here/swarf" render "/tmp/wheel/$p" --field $fld --frame last --along y \
                              --window=-7e-5,7e-5,-2e-5,5e-4 --out "$out/wheelpics/$p-top" 2>&1 | tail -n 1
                      done
                  done
              }
              run wheel24 wheel ;;
        millpics) # issue 24 (docs/3d.md): the micro-milling scene with JC (cases/3d/micro-milling.toml) whole, then
                  # pictures of its frames (swarf render): seen from above (--along y) at the first and second tooth
                  # passes' force peaks (frames 47, 85: 188, 340 µs) and at the end, the equivalent plastic strain
                  # and the temperature; and the mid-plane slab z = 45-55 µm seen along z at the end (the burr).
                  # The PNGs come back in $OUT/millpics/
              d=/tmp/millpics; rm -rf "$d"
              run millpics timeout -s INT -k 30 "${SWARF_MILL_DEADLINE:-420}" "$here/swarf" --backend gpu run \
                  cases/3d/micro-milling.toml --quiet --out "$d"
              { tail -n 6 "$d/run.log"; cat "$d/summary.json" 2>/dev/null; } >> "$out/millpics.log"
              cp "$d/forces.csv" "$out/millpics-forces.csv"
              mkdir -p "$out/millpics"
              for f in 47 85 last; do
                  for fld in eps T; do
                      "$here/swarf" render "$d" --field $fld --frame $f --along y --out "$out/millpics/top" \
                          >> "$out/millpics.log" 2>&1
                  done
              done
              "$here/swarf" render "$d" --field eps --frame last --along z --slab=4.5e-5,5.5e-5 \
                  --out "$out/millpics/side" >> "$out/millpics.log" 2>&1 ;;
        tests) # three tests at a time (SWARF_GPU_TEST_THREADS): 29 tests in about 210 s on an H100, against about
               # 420 s one at a time (docs/measurements/notebook.md, 2026-12-07); each still compares bit for bit
               run test-gpu "$here/test-gpu" --test-threads="${SWARF_GPU_TEST_THREADS:-3}" --nocapture
               run test-ptx "$here/test-ptx" ;;
        regs) # issue 7: the register cap of the neighbour kernels (SWARF_MAXNREG) against the compiler's choice
              sc=cases/cutting/reference-cut.toml,cases/cutting/reference-cut-150k.toml
              run regs-none "$here/swarf" --backend gpu bench step --scenes $sc --precision both
              for r in 64 80 96; do
                  SWARF_MAXNREG=$r run "regs-$r" "$here/swarf" --backend gpu bench step --scenes $sc --precision both
                  SWARF_MAXNREG=$r run "regs-info-$r" "$here/swarf" --backend gpu info --kernels
              done ;;
        hard) # issue 8: the stability suite's tests, the same criteria, on the GPU backend
              # (the CPU suite's binary, test-suite, filtered to the tests/stability_*.rs modules)
              for t in stability_solids stability_energy stability_thermal stability_contact; do
                  SWARF_TEST_BACKEND=gpu run "hard-$t" "$here/test-suite" "$t::" --test-threads=1 --nocapture
              done ;;
        bench) run bench "$here/swarf" --backend gpu bench neighbours --sizes 1e6,4e6,16e6 --dims 2,3 --precision both ;;
        rings) run rings-gpu "$here/swarf" --backend gpu bench rings --precision both
               run rings-cpu "$here/swarf" --backend cpu bench rings --precision both --steps 20 ;;
        ptx) # a bench, not test-ptx (that runs in `tests`): the embedded PTX targets side by side, same workloads:
             # SWARF_PTX_TARGETS (default sm_80, the one target build.rs embeds; "sm_80 sm_90" with a build that
             # adds sm_90 to its TARGETS)
             for t in ${SWARF_PTX_TARGETS:-sm_80}; do
                 SWARF_PTX_TARGET=$t run "neighbours-$t" "$here/swarf" --backend gpu bench neighbours --sizes 16e6 --dims 2,3
                 SWARF_PTX_TARGET=$t run "rings-$t" "$here/swarf" --backend gpu bench rings --nbox 400,800 --steps 2000
             done ;;
        step) # issue 7: the whole step of the standard workloads, per phase, with each physics option off
              run step "$here/swarf" --backend gpu bench step --precision both --options ;;
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
        criterion) run criterion "$here/bench-neighbours" --bench --noplot
                   [ -x "$here/bench-mpm" ] && run criterion-mpm "$here/bench-mpm" --bench --noplot
                   run criterion-step "$here/bench-step" --bench --noplot ;;
        fast) # issue 7: the f32 LLVM flags (--fast-math): V0060 cut observables and the step time, against default
              fastcmp() {
                  for p in f32 f64; do
                      for m in default fast; do
                          local flag=; [ $m = fast ] && flag=--fast-math
                          "$here/swarf" --backend gpu $flag run cases/cutting/v0060.toml --precision $p --quiet \
                              --out "/tmp/swarf-fast/$p-$m" || return 1
                          echo "== v0060 $p $m"; cat "/tmp/swarf-fast/$p-$m/summary.json"
                      done
                  done
              }
              run fast-v0060 fastcmp
              run fast-step "$here/swarf" --backend gpu --fast-math bench step --precision both \
                  --scenes cases/rings.toml,cases/impact.toml,cases/cutting/reference-cut.toml,cases/cutting/reference-cut-150k.toml ;;
        cutting) # issue 5: the validation cuts, whole (1 mm), with wall time; summary and a thinned force trace
                 cuts() {
                     cut v0060-f64 cases/cutting/v0060.toml && cut v0060-f32 cases/cutting/v0060.toml --precision f32 \
                         && cut v0300-f64 cases/cutting/v0300.toml && cut reference-cut-f64 cases/cutting/reference-cut.toml
                 }
                 run cutting cuts ;;
        longcut) # issue 8: chip self-contact in a 4 mm cut (cases/hard/long-cut.toml): min pair and contact distances
                 longcut() {
                     cut long-cut cases/hard/long-cut.toml || return 1
                     cp /tmp/swarf-cut/long-cut/energy.csv "$out/long-cut-energy.csv"
                     cp /tmp/swarf-cut/long-cut/forces.csv "$out/long-cut-forces.csv"
                     awk -F, 'NR == 1 || NR % 10 == 1' /tmp/swarf-cut/long-cut/energy.csv
                     # The frame of the closest contact (energy rows and frames are written at the same outputs)
                     # and the last frame, to see where the chip meets itself or the workpiece.
                     local f=/tmp/swarf-cut/long-cut
                     local k=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "min_contact_distance") c = i }
                         NR > 2 && $c != "NaN" && (best == "" || $c + 0 < best) { best = $c + 0; row = NR - 2 }
                         END { print row + 0 }' /tmp/swarf-cut/long-cut/energy.csv)
                     ls "$f"/*.vtu | wc -l
                     cp "$f/$(printf 'frame_%05d.vtu' "$k")" "$out/long-cut-closest.vtu" 2>/dev/null || echo "no frame $k"
                     cp "$(ls "$f"/*.vtu | tail -1)" "$out/long-cut-last.vtu"
                 }
                 run longcut longcut ;;
        study) # issue 7: wall time against error over resolutions × precisions (swarf study), the published studies
               # (SWARF_STUDY_PRECISIONS, default f64,f32,mixed)
               studies() {
                   local precs=${SWARF_STUDY_PRECISIONS:-f64,f32,mixed}
                   "$here/swarf" --backend gpu study cases/rings.toml --levels 1,1/2,1/4 --precisions "$precs" \
                       --out /tmp/swarf-study/rings --quiet && cat /tmp/swarf-study/rings/study.md \
                   && "$here/swarf" --backend gpu study cases/impact.toml --levels 2,1,1/2 --precisions "$precs" \
                       --out /tmp/swarf-study/impact --quiet && cat /tmp/swarf-study/impact/study.md \
                   && "$here/swarf" --backend gpu study cases/cutting/v0060.toml --levels 1,1/2,1/3 --precisions "$precs" \
                       --set time.end=7.868e-5 --out /tmp/swarf-study/v0060 --quiet && cat /tmp/swarf-study/v0060/study.md
                   local ok=$?
                   for s in rings impact v0060; do
                       cp "/tmp/swarf-study/$s/study.md" "$out/study-$s.md" 2>/dev/null
                       cp "/tmp/swarf-study/$s/study.png" "$out/study-$s.png" 2>/dev/null
                   done
                   return $ok
               }
               run study studies ;;
        ladder) # H9 / C9: V0060 at about 65k and 127k particles (0.5 mm of cut)
                ladder() {
                    cut v0060-6k cases/cutting/v0060.toml --set time.end=7.868e-5 \
                    && cut v0060-65k cases/cutting/v0060.toml --set discretisation.dx=2.9e-6 \
                        --set 'boundary.2.min=[1.8675e-3,-1.0]' \
                        --set time.end=7.868e-5 --set output.every=1.5736e-6 \
                    && cut v0060-127k cases/cutting/v0060.toml --set discretisation.dx=2.07e-6 \
                        --set 'boundary.2.min=[1.8691e-3,-1.0]' \
                        --set time.end=7.868e-5 --set output.every=1.5736e-6
                }
                run ladder ladder ;;
        sweep) # AT-85 friction sweep, AT-83 edge radius, AT-86 friction cap: reference cut, 0.25 mm each
               sweep() {
                   local e="--set time.end=2.1428e-4 --set output.every=4.2857e-6" ok=0
                   cut mu035 cases/cutting/reference-cut.toml $e || ok=1
                   for mu in 0.5 0.6 0.7; do cut mu$mu cases/cutting/reference-cut.toml $e --set tool.friction=$mu || ok=1; done
                   cut r10 cases/cutting/reference-cut.toml $e --set tool.edge_radius=1.0e-5 \
                       --set 'tool.position=[-1.31e-5,2.0517e-4]' || ok=1
                   cut r50 cases/cutting/reference-cut.toml $e --set tool.edge_radius=5.0e-5 \
                       --set 'tool.position=[-5.31e-5,2.0517e-4]' || ok=1
                   for c in static current; do
                       cut cap-$c cases/cutting/reference-cut.toml $e --set tool.friction=0.7 \
                           --set "tool.friction_cap=\"$c\"" || ok=1
                   done
                   cut v0060-f64 cases/cutting/v0060.toml || ok=1
                   return $ok
               }
               run sweep sweep ;;
        whole150k) # issues 7/8: the whole 150k reference cut (1 mm), resumable across device calls and sessions: each
                   # call runs until SWARF_CUT_LIMIT seconds (default 500), is interrupted (checkpoint written), and
                   # its run folder (frames left out) comes back in $OUT as whole-150k-<prec>.tgz.part?? (15 MiB
                   # pieces: the device returns at most 8 files of 16 MiB). Put the pieces in the git-ignored
                   # carry150k/ and carry it with the next call, which resumes from them.
                   # SWARF_CUT_BACKEND / SWARF_CUT_SCENE change the backend and scene (to test this part on a CPU).
              for prec in ${SWARF_CUT_PRECISIONS:-f64}; do
                  d=runs/whole-150k-$prec
                  if [ ! -f "$d/checkpoint.bin" ] && [ -e "carry150k/whole-150k-$prec.tgz.partaa" ]; then
                      mkdir -p runs && cat carry150k/whole-150k-$prec.tgz.part* | tar xzf - -C runs
                      echo "unpacked the carried run folder: $(grep -c . "$d/forces.csv") force rows"
                  fi
                  if [ -f "$d/checkpoint.bin" ]; then
                      timeout --foreground -s INT "${SWARF_CUT_LIMIT:-500}" "$here/swarf" --backend "${SWARF_CUT_BACKEND:-gpu}" \
                          run --resume "$d" --quiet
                  else
                      timeout --foreground -s INT "${SWARF_CUT_LIMIT:-500}" "$here/swarf" --backend "${SWARF_CUT_BACKEND:-gpu}" run \
                          "${SWARF_CUT_SCENE:-cases/cutting/reference-cut-150k.toml}" --precision "$prec" --out "$d" \
                          --quiet --checkpoint-every 5e-5
                  fi
                  echo "rc $? ($prec)"
                  cp "$d/run.log" "$out/whole150k-$prec-run.log" 2>/dev/null
                  cp "$d/summary.json" "$out/whole150k-$prec-summary.json" 2>/dev/null
                  tail -n 3 "$d/run.log"
                  tar czf - -C runs --exclude='*.vtu' "whole-150k-$prec" | split -b 15m - "$out/whole-150k-$prec.tgz.part"
                  ls -la "$out"/whole-150k-$prec.tgz.part*
              done ;;
        bg150k) # issue 8: the whole 150k reference cut (1 mm) in the background, one precision per GPU
                # (SWARF_CUT_GPUS, default "f64:0"; e.g. "f64:1 f32:0" on two GPUs): started in its own session
                # (setsid), so that it runs on after this call returns while the machine is held; part wait150k
                # waits for it and returns its summary, force trace and energies. Resumes from a checkpoint where
                # the run folder has one (a carried carry150k/ is unpacked first, as in whole150k, unless
                # SWARF_CUT_FRESH is set: then the cut starts at t = 0).
                # An entry may add run-time settings after a second colon ("f64:1:SWARF_PAIR_ORDER=forward", commas
                # between several; SWARF_BIN=swarf-<name> runs that packed build): its run folder is then named
                # after the GPU too (whole-150k-f64-g1).
                for pg in ${SWARF_CUT_GPUS:-f64:0}; do
                    IFS=: read -r prec gpu envs <<< "$pg"
                    label=$prec; [ -z "$envs" ] || label=$prec-g$gpu
                    bin=swarf
                    case ",$envs," in *,SWARF_BIN=*) bin=${envs#*SWARF_BIN=}; bin=${bin%%,*} ;; esac
                    d=runs/whole-150k-$label
                    mkdir -p runs
                    if [ ! -f "$d/checkpoint.bin" ] && [ -e "carry150k/whole-150k-$prec.tgz.partaa" ] \
                        && [ -z "${SWARF_CUT_FRESH:-}" ]; then
                        cat carry150k/whole-150k-$prec.tgz.part* | tar xzf - -C runs
                    fi
                    if [ -f "$d/checkpoint.bin" ]; then args=(run --resume "$d" --quiet)
                    else args=(run cases/cutting/reference-cut-150k.toml --precision "$prec" --out "$d" --quiet \
                               --checkpoint-every 5e-5); fi
                    env CUDA_VISIBLE_DEVICES=$gpu ${envs//,/ } setsid nohup "$here/$bin" --backend gpu "${args[@]}" \
                        > "runs/whole-150k-$label.out" 2>&1 < /dev/null &
                    echo "started the 150k cut in $prec on GPU $gpu ${envs:+with $envs }(pid $!) at $(date +%T)"
                done
                sleep 20; nvidia-smi --query-gpu=index,utilization.gpu,memory.used --format=csv ;;
        wait150k) # waits (at most SWARF_WAIT_LIMIT s, default 540) for the background 150k cuts of bg150k and
                  # returns what they wrote so far: summary, run log, forces and energies (no frames, no checkpoint)
                  t0=$(date +%s)
                  while pgrep -f "reference-cut-150k|whole-150k" > /dev/null \
                        && [ $(( $(date +%s) - t0 )) -lt "${SWARF_WAIT_LIMIT:-540}" ]; do sleep 5; done
                  for d in runs/whole-150k-*; do
                      [ -d "$d" ] || continue
                      b=$(basename "$d")
                      echo "== $b"; cat "$d/../$b.out" 2>/dev/null | tail -n 5; tail -n 3 "$d/run.log"
                      cat "$d/summary.json" 2>/dev/null || echo "(running: no summary yet)"
                      for f in run.log summary.json forces.csv energy.csv; do cp "$d/$f" "$out/$b-$f" 2>/dev/null; done
                  done
                  pgrep -af "whole-150k" || echo "no 150k cut running" ;;
        ncu) # issue 7: the FLOP side of the roofline: hardware counters of one launch of the 150k interaction kernel
             ncu_once() {
                 local prec=$1
                 ncu --kernel-name regex:swarf_sph_rates --launch-count 1 --metrics \
gpu__time_duration.sum,sm__sass_thread_inst_executed_op_dfma_pred_on.sum,sm__sass_thread_inst_executed_op_dmul_pred_on.sum,sm__sass_thread_inst_executed_op_dadd_pred_on.sum,sm__sass_thread_inst_executed_op_ffma_pred_on.sum,sm__sass_thread_inst_executed_op_fmul_pred_on.sum,sm__sass_thread_inst_executed_op_fadd_pred_on.sum,dram__bytes_read.sum,dram__bytes_write.sum,lts__t_bytes.sum,l1tex__t_bytes.sum,sm__warps_active.avg.pct_of_peak_sustained_active,sm__inst_executed_pipe_fp64.avg.pct_of_peak_sustained_active,sm__throughput.avg.pct_of_peak_sustained_elapsed,smsp__inst_executed.sum,smsp__thread_inst_executed_per_inst_executed.ratio \
                     "$here/swarf" --backend gpu bench step --scenes cases/cutting/reference-cut-150k.toml \
                     --precision "$prec" --step-count 32
             }
             run ncu-f64 ncu_once f64
             run ncu-f32 ncu_once f32 ;;
        cutsteps) # issue 7: the step of the three reference workloads (both precisions, every variant side by side)
                  run cutsteps "$here/swarf" --backend gpu bench step --precision both \
                      --scenes cases/cutting/reference-cut.toml,cases/cutting/reference-cut-150k.toml,cases/cutting/v0060.toml ;;
        fromcut) # issue 7: the step of states in the middle of a cut (chip, plastic flow, contact), from checkpoints:
                 # the 6k reference cut run to half its length here, and the carried 150k f64 run folder (carry150k/)
                 fromcut() {
                     local dirs; dirs=$(from_dirs) || return 1
                     "$here/swarf" --backend gpu bench step --from "$dirs"
                     # Register caps side by side on the same states: the plastic corrector uncapped (its default
                     # is 128), the neighbour kernels capped at 80 and 64 (default: 128 on the 2D ones).
                     for v in SWARF_PLASTIC_MAXNREG=0 SWARF_MAXNREG=80 SWARF_MAXNREG=64; do
                         echo "== $v"; env "$v" "$here/swarf" --backend gpu bench step --from "$dirs"
                     done
                 }
                 run fromcut fromcut ;;
        abfrom) # issue 7: this build against earlier ones (gpu-pack/swarf-old, swarf-<name>, when packed) on the same
                # checkpoints, alternating (new, old, new, old), so that the difference shows beside the run-to-run noise
                abfrom() {
                    local dirs; dirs=$(from_dirs) || return 1
                    local others; others=$(cd "$here" && ls swarf-* 2>/dev/null | grep -v '\.gz$')
                    for round in 1 2; do
                        for b in swarf $others; do
                            [ -x "$here/$b" ] || continue
                            echo "== $b, round $round"
                            "$here/$b" --backend gpu bench step --from "$dirs" --step-count 2048 || return 1
                        done
                    done
                }
                run abfrom abfrom ;;
        abstep) # issue 7: as abfrom (one round), the reference cuts at t = 0 in both precisions (the f32 pair rate;
                # SWARF_AB_PRECISION=all adds the mixed precision)
                abstep() {
                    local others; others=$(cd "$here" && ls swarf-* 2>/dev/null | grep -v '\.gz$')
                    for round in 1; do
                        for b in swarf $others; do
                            echo "== $b, round $round"
                            "$here/$b" --backend gpu bench step --precision "${SWARF_AB_PRECISION:-both}" --step-count 2048 \
                                --scenes cases/cutting/reference-cut.toml,cases/cutting/reference-cut-150k.toml || return 1
                        done
                    done
                }
                run abstep abstep ;;
        abdamage) # issue 25: the damage's own entries (`_dmg` variants): this build against each packed earlier one
                  # (swarf-<name>) on the reference cuts at t = 0 (bench step, both precisions) and the default V0060
                  # cut (whole-process wall time, two rounds alternating); the scenes and the runs sit in /tmp/ab, out
                  # of the tree, so that each binary reads its own built-in material library
                  abdamage() {
                      local b round t0 t1 others; others=$(cd "$here" && ls swarf-* 2>/dev/null | grep -v '\.gz$')
                      rm -rf /tmp/ab && mkdir -p /tmp/ab || return 1
                      cp cases/cutting/reference-cut.toml cases/cutting/reference-cut-150k.toml /tmp/ab/ || return 1
                      for b in swarf $others; do
                          echo "== $b"
                          (cd /tmp/ab && "$here/$b" --backend gpu bench step --precision both --step-count 2048 \
                              --scenes reference-cut.toml,reference-cut-150k.toml) || return 1
                      done
                      for round in 1 2; do
                          for b in swarf $others; do
                              t0=$(date +%s%N)
                              (cd /tmp/ab && "$here/$b" --backend gpu run --quiet --out "/tmp/ab/v0060-$b-$round") || return 1
                              t1=$(date +%s%N)
                              echo "== $b, round $round: $(( (t1 - t0) / 1000000 )) ms"
                              grep -E '"(fc_n_per_mm|ff_n_per_mm)"' "/tmp/ab/v0060-$b-$round/summary.json" | head -4
                              md5sum "/tmp/ab/v0060-$b-$round/forces.csv"
                          done
                      done
                  }
                  run abdamage abdamage ;;
        abregs) # issue 7: register caps of the neighbour kernels (SWARF_MAXNREG) on the checkpoints, alternating with
                # the uncapped build and gpu-pack/swarf-mid; then the 150k f32 interaction at t = 0 capped and not
                abregs() {
                    local dirs; dirs=$(from_dirs) || return 1
                    for v in 128 96 80; do
                        echo "== SWARF_MAXNREG=$v"; SWARF_MAXNREG=$v "$here/swarf" --backend gpu info --kernels | grep -E 'rates|heat_'
                    done
                    for round in 1 2; do
                        for v in none 128 96 80; do
                            echo "== swarf, SWARF_MAXNREG=$v, round $round"
                            env $([ $v = none ] || echo SWARF_MAXNREG=$v) "$here/swarf" --backend gpu bench step \
                                --from "$dirs" --step-count 2048 || return 1
                        done
                        if [ -x "$here/swarf-mid" ]; then
                            echo "== swarf-mid, round $round"
                            "$here/swarf-mid" --backend gpu bench step --from "$dirs" --step-count 2048 || return 1
                        fi
                    done
                    for v in none 80 64; do
                        echo "== swarf f32 150k t = 0, SWARF_MAXNREG=$v"
                        env $([ $v = none ] || echo SWARF_MAXNREG=$v) "$here/swarf" --backend gpu bench step \
                            --precision f32 --step-count 2048 --scenes cases/cutting/reference-cut-150k.toml || return 1
                    done
                }
                run abregs abregs ;;
        abenv) # issue 7: run-time settings side by side on the checkpoints, alternating, two rounds: SWARF_AB_ENVS holds
               # the variants, space-separated, each "default" or NAME=VALUE[,NAME=VALUE...]
               run abenv abenv "${SWARF_AB_ENVS:-default}" ;;
        abblock) # issue 7: block sizes of the neighbour passes and the plastic corrector (SWARF_PAIR_BLOCK,
                 # SWARF_PLASTIC_BLOCK) on the checkpoints, alternating with the default (256)
                 blocks="default"
                 for v in 128/256 256/128 128/128 64/64; do
                     blocks="$blocks SWARF_PAIR_BLOCK=${v%/*},SWARF_PLASTIC_BLOCK=${v#*/}"
                 done
                 run abblock abenv "$blocks" ;;
        ncufrom) # issue 7: the hardware counters of one launch of the interaction inside the 150k cut (checkpoint), and
                 # of the corrector with the plastic update inside both cuts
                 ncufrom() {
                     local dirs; dirs=$(from_dirs) || return 1
                     ncu --kernel-name regex:swarf_sph_rates --launch-count 1 --metrics \
gpu__time_duration.sum,sm__sass_thread_inst_executed_op_dfma_pred_on.sum,sm__sass_thread_inst_executed_op_dmul_pred_on.sum,sm__sass_thread_inst_executed_op_dadd_pred_on.sum,sm__sass_thread_inst_executed_op_ffma_pred_on.sum,sm__sass_thread_inst_executed_op_fmul_pred_on.sum,sm__sass_thread_inst_executed_op_fadd_pred_on.sum,dram__bytes_read.sum,dram__bytes_write.sum,lts__t_bytes.sum,l1tex__t_bytes.sum,sm__warps_active.avg.pct_of_peak_sustained_active,sm__inst_executed_pipe_fp64.avg.pct_of_peak_sustained_active,sm__throughput.avg.pct_of_peak_sustained_elapsed,smsp__inst_executed.sum,smsp__thread_inst_executed_per_inst_executed.ratio \
                         "$here/swarf" --backend gpu bench step --from "${dirs#*,}" --step-count 32
                 }
                 run ncufrom ncufrom
                 # The corrector with the plastic update at both checkpoints (6k, then 150k): how long its warps run
                 # and how many of their threads take part (the Newton iterations of the yielding particles).
                 ncuplastic() {
                     local dirs; dirs=$(from_dirs) || return 1
                     local d
                     for d in ${dirs//,/ }; do
                         ncu --kernel-name regex:swarf_step_finish_jc --launch-count 1 --metrics \
gpu__time_duration.sum,sm__sass_thread_inst_executed_op_dfma_pred_on.sum,sm__sass_thread_inst_executed_op_dmul_pred_on.sum,sm__sass_thread_inst_executed_op_dadd_pred_on.sum,sm__warps_active.avg.pct_of_peak_sustained_active,sm__inst_executed_pipe_fp64.avg.pct_of_peak_sustained_active,sm__throughput.avg.pct_of_peak_sustained_elapsed,smsp__inst_executed.sum,smsp__thread_inst_executed_per_inst_executed.ratio,sm__cycles_active.max,sm__cycles_active.avg,launch__grid_size \
                             "$here/swarf" --backend gpu bench step --from "$d" --step-count 32
                     done
                 }
                 run ncuplastic ncuplastic ;;
        ncusrc) # issue 7: where the interaction and the plastic corrector wait, inside the 150k cut (checkpoint): ncu's
                # full set on one launch of each, its details page, and the SASS with the warp-stall samples of each
                # instruction (sass-<kernel>.csv.gz)
                ncusrc() {
                    local dirs; dirs=$(from_dirs) || return 1
                    local k
                    for k in swarf_sph_rates swarf_step_finish_jc; do
                        ncu --set full --kernel-name regex:$k --launch-count 1 -f -o /tmp/ncu-$k \
                            "$here/swarf" --backend gpu bench step --from "${dirs#*,}" --step-count 32 > /dev/null || return 1
                        echo "== $k"; ncu -i /tmp/ncu-$k.ncu-rep --page details
                        ncu -i /tmp/ncu-$k.ncu-rep --page source --csv --print-source sass | gzip > "$out/sass-$k.csv.gz"
                    done
                }
                run ncusrc ncusrc ;;
        refcut) # issue 7: the whole 6k reference cut (1 mm) in f64, f32 and mixed (SWARF_REFCUT_PRECISIONS), wall time
                # against the original's 201 / 182 s
                refcut() {
                    local p
                    for p in ${SWARF_REFCUT_PRECISIONS:-f64 f32 mixed}; do
                        cut reference-cut-$p cases/cutting/reference-cut.toml --precision $p || return 1
                    done
                }
                run refcut refcut ;;
        refvar) # issue 7: how far round-off moves the 6k reference cut's forces: the whole f64 cut with each packed build
                # (swarf, swarf-<name>) and with the sums in another order (SWARF_LANES=4 and 2; 8 is the default at 6k)
                refvar() {
                    local b v
                    for b in swarf $(cd "$here" && ls swarf-* 2>/dev/null | grep -v '\.gz$'); do
                        "$here/$b" --backend gpu run cases/cutting/reference-cut.toml --quiet --out /tmp/swarf-cut/var-$b \
                            || return 1
                        echo "== $b"; tail -n 1 /tmp/swarf-cut/var-$b/run.log
                    done
                    for v in 4 2; do
                        SWARF_LANES=$v "$here/swarf" --backend gpu run cases/cutting/reference-cut.toml --quiet \
                            --out /tmp/swarf-cut/var-lanes$v || return 1
                        echo "== swarf, SWARF_LANES=$v"; tail -n 1 /tmp/swarf-cut/var-lanes$v/run.log
                    done
                }
                run refvar refvar ;;
        f32fail) # issue 8: the 150k reference cut in f32 up to just past where it went non-finite (t = 3.43e-5 s):
                 # the run must stop within 4 096 steps of the first non-finite position, with its report, and
                 # keep its last good frame
                 f32fail() {
                     "$here/swarf" --backend gpu run cases/cutting/reference-cut-150k.toml --precision f32 --quiet \
                         --out /tmp/swarf-cut/f32fail --set time.end=4.5e-5 --set output.every=4.2857e-6
                     local rc=$?
                     echo "exit status $rc"
                     tail -n 6 /tmp/swarf-cut/f32fail/run.log
                     ls /tmp/swarf-cut/f32fail
                     [ $rc != 0 ]
                 }
                 run f32fail f32fail ;;
        fine) # the 150k reference cut: the first 0.5 % of the cut (about 15 000 steps), for the step time
              run fine "$here/swarf" --backend gpu run cases/cutting/reference-cut-150k.toml --verbose \
                  --set time.end=4.2857e-6 --set output.every=1.0714e-6 --out /tmp/swarf-cut/fine ;;
    esac
done
echo "== summary =="
printf '%s\n' "${summary[@]}" | tee "$out/summary.log"
# At most 8 files come back from a device call: everything but the summary goes into one archive, a new one per
# invocation (a second invocation in the same call must not overwrite the first one's logs.tgz).
archive=logs.tgz k=2
while [ -e "$out/$archive" ]; do archive=logs-$k.tgz k=$((k + 1)); done
( cd "$out" && find . -maxdepth 1 -type f ! -name summary.log ! -name 'logs*.tgz' ! -name '*.tgz.part*' -printf '%P\n' \
    | tar czf "$archive" --remove-files -T - ) || echo "could not archive the logs"
# A device call returns files of at most 16 MiB (the device README): a bigger archive is split into parts of
# 15 MiB, to rejoin with `cat logs.tgz.part* | tar xzf -` (a 44 MB archive was lost whole once).
size=$(stat -c %s "$out/$archive" 2>/dev/null || echo 0)
if [ "$size" -gt $((16 * 1024 * 1024)) ]; then
    split -b 15m "$out/$archive" "$out/$archive.part" && rm "$out/$archive"
    echo "$archive: $size bytes, split into $(ls "$out/$archive".part* | wc -l) parts (cat $archive.part* | tar xzf -)" \
        | tee -a "$out/summary.log"
fi
exit $status
