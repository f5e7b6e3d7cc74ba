#!/bin/bash
# The coarse V0060 cut (24 µs), artificial stress off, contact variants, one after another on one thread: each
# run's energy_audit (docs/validation.md, "The audit in every run"). Run from the repository root after a release build.
S="--set discretisation.dx=2.0e-5 --set body.0.max=[1.0e-3,2.8e-4] --set boundary.1.max=[1.0e-9,1.4e-4] --set boundary.2.min=[0.9999e-3,-1.0] --set tool.position=[-3.6e-5] --set tool.depth_of_cut=0.9e-4 --set time.end=2.4e-5 --set output.every=2.4e-6 --set stabilisation.artificial_stress.enabled=false"
run() { tag=$1; shift; RAYON_NUM_THREADS=1 target/release/swarf run cases/cutting/v0060.toml --backend cpu $S "$@" --out /tmp/sw/$tag > /tmp/sw/$tag.log 2>&1; echo "$tag $*: $(python3 -c "import json;a=json.load(open('/tmp/sw/$tag/summary.json'))['energy_audit'];print(' '.join(f'{k}={a[k]:.4g}' for k in ['tool_work_j','friction_work_j','normal_work_j','booked_j','booked_over_workpiece_work','booked_over_tool_work']))")"; }
mkdir -p /tmp/sw
run base
run cfl025 --set time.cfl=0.25
run xi0 --set tool.contact_damping=0.0
run step --set 'tool.contact_law="step"' --set tool.contact_damping=0.0
run kappa005 --set tool.contact_stiffness=0.05
run mu0 --set tool.friction=0.0
run cfl025xi0 --set time.cfl=0.25 --set tool.contact_damping=0.0
run with-as --set stabilisation.artificial_stress.enabled=true   # the last row (run separately in the session: 1.047)
run noxsph --set stabilisation.xsph.enabled=false
run noxsph-mu0 --set stabilisation.xsph.enabled=false --set tool.friction=0.0
