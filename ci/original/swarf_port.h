// swarf's hooks into the original 2D GPU code (iwf-inspire/mfree_iwf-ul_cut_gpu). This file is ours, not the
// original's: ci/original/port.py copies it into original/src and patches the original's main()
// (mfree_gpu.cpp) to call these functions. They only read the particle state and write files; the physics is the
// original's. Settings come from the environment (docs/original-code.md):
//   ORIG_OUT          output folder (created; the process chdir()s into it, so the original's results/ lands there)
//   ORIG_SETUP        ref_cut (default, what the original main() runs) | rings | impact
//   ORIG_STEPS        run exactly this many steps (overrides the cut length)
//   ORIG_CUT_MM       cut length in mm (the original: 1 mm); ignored when ORIG_STEPS is set
//   ORIG_FORCE_EVERY  steps between rows of forces.csv (default 100)
//   ORIG_DUMPS        comma-separated steps after which the whole particle state is written (default 0,1,10,100)
//   ORIG_VTK          1: the original's ASCII VTK frames (135 per run); 0: none (default 1)
//   ORIG_FRAME_EVERY  steps between the original's frames/force/wear lines (default: its own last_step/135)
#ifndef SWARF_PORT_H_
#define SWARF_PORT_H_

#include "grid.h"
#include "particle_gpu.h"
#include "types.h"

void port_begin();
particle_gpu *port_setup(int ny, grid_base **grid, float_t rake, float_t clear, float_t fillet, float_t speed,
                         float_t feed);
bool port_has_tool();
int port_last_step(int last_step);
int port_frame_every(int freq);
bool port_vtk();
void port_on_step(particle_gpu *particles, int step);
void port_after_step(particle_gpu *particles);
void port_end(double gpu_seconds, int last_step);

#endif
