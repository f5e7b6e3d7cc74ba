#!/bin/bash
cd /work/main
S="--set discretisation.dx=2.0e-5 --set body.0.max=[1.0e-3,2.8e-4] --set boundary.1.max=[1.0e-9,1.4e-4] --set boundary.2.min=[0.9999e-3,-1.0] --set tool.position=[-3.6e-5] --set tool.depth_of_cut=0.9e-4 --set time.end=2.4e-5 --set output.every=2.4e-6 --set stabilisation.artificial_stress.enabled=false"
run() { tag=$1; shift; RAYON_NUM_THREADS=2 /tmp/tgt-x/release/swarf run cases/cutting/v0060.toml --backend cpu $S "$@" --out /tmp/sw/$tag > /tmp/sw/$tag.log 2>&1; echo "$tag $*: $(python3 -c "import json;a=json.load(open('/tmp/sw/$tag/summary.json'));e=a['energy_audit'];print(' '.join(f'{k}={e[k]:.4g}' for k in ['tool_work_j','friction_work_j','normal_work_j','booked_j','booked_over_workpiece_work','booked_over_tool_work']), a['fc_n_per_mm'], a['ff_n_per_mm'])")"; }
run xc-base
run xc-mu0 --set tool.friction=0.0
