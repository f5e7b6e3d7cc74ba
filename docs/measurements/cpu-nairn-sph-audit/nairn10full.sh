#!/bin/bash
# V12 in SPH without the artificial stress: Nairn's SPH cut at 10 particles through h (h = 1 mm), sigma_c = 10 MPa,
# the scene's whole time (7.06 ms), pic 0 and 0.2, side by side, one thread each. From the repository root.
B=${SWARF:-target/release/swarf}
O="--set discretisation.dx=1e-4 --set boundary.0.max=[1.0,-2.8e-3] --set tool.position=[-1e-4] --set cohesive.peak=10e6 --set stabilisation.artificial_stress.enabled=false"
run() { tag=$1; shift; RAYON_NUM_THREADS=1 $B run cases/mpm/nairn-cut-sph.toml --backend cpu $O "$@" --out /tmp/na/$tag > /tmp/na/$tag.log 2>&1; echo "$tag $*: done"; }
mkdir -p /tmp/na
run full-noas-pic0 --set stabilisation.xsph.pic=0 & run full-noas-pic02 --set stabilisation.xsph.pic=0.2 & wait
