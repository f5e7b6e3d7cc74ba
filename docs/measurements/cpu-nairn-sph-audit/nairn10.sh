#!/bin/bash
# Nairn's SPH cut at 10 particles through h (dx = 0.1 mm, h = 1 mm), sigma_c = 10 MPa, to 4 ms: defaults and
# without the artificial stress, side by side, one thread each. From the repository root.
B=${SWARF:-target/release/swarf}
O="--set discretisation.dx=1e-4 --set boundary.0.max=[1.0,-2.8e-3] --set tool.position=[-1e-4] --set time.end=4e-3 --set output.every=2e-4 --set cohesive.peak=10e6"
run() { tag=$1; shift; RAYON_NUM_THREADS=1 $B run cases/mpm/nairn-cut-sph.toml --backend cpu $O "$@" --out /tmp/na/$tag > /tmp/na/$tag.log 2>&1; echo "$tag $*: $(python3 -c "import json;a=json.load(open('/tmp/na/$tag/summary.json'));e=a['energy_audit'];print(' '.join(f'{k}={e[k]:.4g}' for k in ['tool_work_j','friction_work_j','normal_work_j','workpiece_work_j','booked_j','booked_over_workpiece_work','booked_over_tool_work']))" 2>&1 | tail -1)"; }
mkdir -p /tmp/na
run n10-default & run n10-noas --set stabilisation.artificial_stress.enabled=false & wait
