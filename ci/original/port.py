#!/usr/bin/env python3
"""Extracts the original 2D GPU code (iwf-inspire/mfree_iwf-ul_cut_gpu, GPLv3, ETH IWF) into the git-ignored
folder original/ and ports it to CUDA 12/13 by programmatic edits. Nothing of the original's is committed to
swarf: this script, the hook files beside it (ours) and the edits' anchors are.

    python3 ci/original/port.py [--mirror GIT_DIR | --src CHECKOUT] [--glm GLM_INCLUDE_DIR] [--out original]

The edits (docs/original-code.md lists them with their reasons):
  E1  interactions_gpu.cu: texture references -> __ldg loads through pointers in one __constant__ struct
      (swarf_tex.cuh); the double-from-int2 fetch helpers go.
  E2  tool_gpu.cu: cudaThreadSynchronize (removed in CUDA 12) -> cudaDeviceSynchronize.
  E3  grid_gpu_green.cu: #include <thrust/sort.h> (sort_by_key is no longer pulled in by device_vector.h).
  E4  grid.cu: the min/max_element comparators' operator() made const (CCCL calls them through a const object).
  E5  mfree_gpu.cpp: no NVML (device 0), no nvidia-smi shell-out for the temperature, no `rm results/*`, no
      cuda_profiler_api.h; hooks into swarf_port.cu: output folder, set-up choice, step count / cut length,
      forces.csv, state dumps sorted by set-up index, timing.json, optional VTK frames.
  E6  vtk_writer.cpp: copy `blanked` to the host before using it (it was read uninitialised; output only).
  E7  types.h: include <cuda/std/cmath> before float_t becomes a macro (CCCL 3 declares `using ::float_t`).
The physics (kernels, constants, step order, set-up) is not touched; every anchor must match exactly as often
as stated, or the script stops.
"""

import argparse
import io
import json
import os
import re
import shutil
import subprocess
import sys
import tarfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
DEFAULT_MIRROR = Path("/work/.mirror/iwf-inspire+mfree_iwf-ul_cut_gpu/repo")
KNOWN_COMMIT = "341be21"  # the commit this port was written against (HEAD of the public repository, 2019)

# E1: the textures the original declares (name -> element type of the array bound to it), as in swarf_tex.cuh.
TEXTURES = {
    "pos_tex": "float2_tex_t", "vel_tex": "float2_tex_t", "S_tex": "float4_tex_t", "R_tex": "float4_tex_t",
    "h_tex": "float_tex_t", "rho_tex": "float_tex_t", "p_tex": "float_tex_t", "T_tex": "float_tex_t",
    "tool_particle_tex": "float_tex_t", "hashes_tex": "int", "pos_to_tex": "float2_tex_t",
    "h_to_tex": "float_tex_t", "T_to_tex": "float_tex_t", "hashes_to_tex": "int", "cells_start_tex": "int",
    "cells_end_tex": "int",
}


class Source:
    def __init__(self, src: Path):
        self.src = src
        self.log = []

    def _read(self, name):
        return (self.src / name).read_text()

    def _write(self, name, text):
        (self.src / name).write_text(text)

    def sub(self, name, pattern, repl, count, tag, flags=0):
        """Regex substitution that must match exactly `count` times."""
        text = self._read(name)
        new, n = re.subn(pattern, repl, text, flags=flags)
        if n != count:
            sys.exit(f"port.py: {tag}: {name}: pattern {pattern!r} matched {n} times, expected {count}")
        self._write(name, new)
        self.log.append({"edit": tag, "file": name, "matches": n})

    def literal(self, name, old, new, count, tag):
        self.sub(name, re.escape(old), new.replace("\\", "\\\\"), count, tag)

    def between(self, name, start, end, new, tag):
        """Replaces the text from `start` (included) to `end` (excluded), each found exactly once."""
        text = self._read(name)
        if text.count(start) != 1 or text.count(end) != 1:
            sys.exit(f"port.py: {tag}: {name}: anchors {start!r} / {end!r} not found exactly once")
        a, b = text.index(start), text.index(end)
        if b < a:
            sys.exit(f"port.py: {tag}: {name}: anchors in the wrong order")
        self._write(name, text[:a] + new + text[b:])
        self.log.append({"edit": tag, "file": name, "matches": 1})

    def require(self, name, needle, tag):
        if needle not in self._read(name):
            sys.exit(f"port.py: {tag}: {name}: expected {needle!r}")


def extract(args, out: Path):
    """Puts the original's src/ and README.md under out/, returns the commit."""
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    if args.src:
        src = Path(args.src)
        shutil.copytree(src / "src", out / "src")
        if (src / "README.md").exists():
            shutil.copy(src / "README.md", out / "README.md")
        try:
            commit = subprocess.check_output(["git", "-C", str(src), "rev-parse", "HEAD"], text=True).strip()
        except (subprocess.CalledProcessError, FileNotFoundError):
            commit = "unknown"
        return commit
    mirror = Path(args.mirror)
    commit = subprocess.check_output(["git", "-C", str(mirror), "rev-parse", "HEAD"], text=True).strip()
    data = subprocess.check_output(["git", "-C", str(mirror), "archive", "--format=tar", "HEAD", "src", "README.md"])
    with tarfile.open(fileobj=io.BytesIO(data)) as tar:
        tar.extractall(out, filter="data") if sys.version_info >= (3, 12) else tar.extractall(out)
    return commit


def copy_glm(args, out: Path):
    """GLM (header only, MIT/Expat; the original's only dependency) goes to out/include/glm, so that the GPU
    machine, which has no network, builds from the carried folder alone."""
    candidates = [args.glm] if args.glm else [os.environ.get("GLM_INCLUDE_DIR"), "/usr/include", "/usr/local/include"]
    for c in candidates:
        if c and (Path(c) / "glm" / "glm.hpp").exists():
            shutil.copytree(Path(c) / "glm", out / "include" / "glm")
            return str(Path(c) / "glm")
    sys.exit("port.py: GLM headers not found: apt-get install libglm-dev, or --glm DIR (the folder holding glm/)")


def port(s: Source):
    # Precision: the comparisons with swarf are f64.
    s.require("types.h", "\n#define USE_DOUBLE\n", "double precision")

    # E7 CUDA 13's CCCL says `using ::float_t;` in <cuda/std/cmath>; the original makes float_t a macro (double)
    # in types.h, and a file that includes types.h before a thrust header (debug.cpp, tool_gpu.cu) then fails. The
    # header is read once, before the macro exists.
    s.literal("types.h", "#include <glm/glm.hpp>\n",
              "#include <glm/glm.hpp>\n#include <cuda/std/cmath>\t// swarf port: before float_t becomes a macro\n", 1,
              "E7")

    # E1 texture references -> __ldg.
    f = "interactions_gpu.cu"
    text = s._read(f)
    found = dict((n, t) for t, n in re.findall(r"^texture<\s*(\w+)\s*,\s*1\s*,\s*cudaReadModeElementType>\s*(\w+)\s*;",
                                               text, flags=re.M))
    if found != TEXTURES:
        sys.exit(f"port.py: E1: textures differ from swarf_tex.cuh: {found}")
    s.sub(f, r"^texture<\s*\w+\s*,\s*1\s*,\s*cudaReadModeElementType>\s*\w+\s*;[ \t]*\n", "", len(TEXTURES), "E1",
          flags=re.M)
    s.sub(f, r"#ifdef USE_DOUBLE\s*\nstatic __inline__ __device__ double fetch_double\(.*?\n#endif\n", "", 1, "E1",
          flags=re.S)
    s.literal(f, '#include "kernels.cuh"\n', '#include "kernels.cuh"\n#include "swarf_tex.cuh"\n', 1, "E1")
    s.sub(f, r"cudaBindTexture\(\s*0\s*,\s*(\w+)\s*,\s*([^,]+?)\s*,[^;]*\);", r"swarf_tex_h.f_\1 = \2;", 20, "E1")
    s.sub(f, r"[ \t]*cudaUnbindTexture\(\s*\w+\s*\);[ \t]*\n", "", 20, "E1")
    s.literal(f, "tex1Dfetch(", "texfetch1(", 6, "E1")
    s.sub(f, r"\n([ \t]*)(do_interactions_(?:monaghan|heat_pse)<<<)", r"\n\1swarf_tex_upload();\n\1\2", 3, "E1")

    # E2 the removed runtime call.
    s.literal("tool_gpu.cu", "cudaThreadSynchronize()", "cudaDeviceSynchronize()", 1, "E2")

    # E3, E4 thrust.
    s.literal("grid_gpu_green.cu", '#include "grid_gpu_green.h"\n',
              '#include "grid_gpu_green.h"\n#include <thrust/sort.h>\n', 1, "E3")
    s.literal("grid.cu", "bool operator()(float2_t lhs, float2_t rhs) {",
              "bool operator()(float2_t lhs, float2_t rhs) const {", 2, "E4")

    # E5 main(): no NVML, no shell-outs, hooks.
    m = "mfree_gpu.cpp"
    s.literal(m, "#include <cuda_profiler_api.h>\n", "", 1, "E5")
    s.literal(m, "#include <nvml.h>\n", '#include "swarf_port.h"\n', 1, "E5")
    s.between(m, "int poll_temp() {", "void poll_memory_usage() {",
              "int poll_temp() {\n\treturn -1;\t// swarf port: no nvidia-smi shell-out\n}\n\n", "E5")
    s.between(m, "void chose_cuda_device() {", "int main(int argc, char *argv[]) {",
              "void chose_cuda_device() {\n"
              "\t// swarf port: no NVML; the first visible device\n"
              "\tif (cudaSetDevice(0) != cudaSuccess) {\n\t\tprintf(\"couldn't set device!\\n\");\n\t\texit(-1);\n\t}\n"
              "\tcudaDeviceProp prop;\n\tcudaGetDeviceProperties(&prop, 0);\n"
              "\tprintf(\"context established on %s\\n\", prop.name);\n}\n\n", "E5")
    s.sub(m, r"(int main\(int argc, char \*argv\[\]\) \{\s*chose_cuda_device\(\);)", r"\1\n\tport_begin();", 1, "E5")
    s.literal(m, "particle_gpu *particles = setup_ref_cut(", "particle_gpu *particles = port_setup(", 1, "E5")
    s.literal(m, "if (global_tool == 0) {", "if (global_tool == 0 && port_has_tool()) {", 1, "E5")
    s.sub(m, r"[ \t]*ret = system\(\"rm results/\*\.(?:txt|vtk)\"\);[ \t]*\n", "", 2, "E5")
    s.literal(m, "int last_step = global_t_final/global_dt;",
              "int last_step = global_t_final/global_dt;\n\tlast_step = port_last_step(last_step);", 1, "E5")
    s.literal(m, "int freq = last_step/135;", "int freq = port_frame_every(last_step/135);", 1, "E5")
    s.literal(m, "for (int step = 0; step < last_step+1; step++) {",
              "for (int step = 0; step < last_step+1; step++) {\n\t\tport_on_step(particles, step);", 1, "E5")
    s.literal(m, "vtk_writer_write(particles, print_iter);", "if (port_vtk()) vtk_writer_write(particles, print_iter);",
              1, "E5")
    s.literal(m, "vtk_writer_write(global_tool, print_iter);",
              "if (port_vtk()) vtk_writer_write(global_tool, print_iter);", 1, "E5")
    s.literal(m, "stepper->step(particles, grid);", "stepper->step(particles, grid);\n\t\tport_after_step(particles);",
              1, "E5")
    s.literal(m, 'printf("gpu time: (seconds) %f\\n", milliseconds/1e3);',
              'printf("gpu time: (seconds) %f\\n", milliseconds/1e3);\n\tport_end(milliseconds/1e3, last_step);', 1,
              "E5")
    for needle in ("popen", "system(", "nvml"):
        if needle in s._read(m):
            sys.exit(f"port.py: E5: {m} still contains {needle!r}")

    # E6 output only.
    s.sub("vtk_writer.cpp", r"(cudaMemcpy\(h_tool_p, particles->tool_particle,[^;]*;)",
          r"\1\n\tcudaMemcpy(h_blanked, particles->blanked, sizeof(float_t)*n, cudaMemcpyDeviceToHost);", 1, "E6")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mirror", default=str(DEFAULT_MIRROR), help="bare git repository of the original")
    ap.add_argument("--src", help="a checkout of the original instead of --mirror")
    ap.add_argument("--glm", help="folder holding glm/glm.hpp (default: $GLM_INCLUDE_DIR, /usr/include)")
    ap.add_argument("--out", default=str(ROOT / "original"), help="target folder (git-ignored), default original/")
    args = ap.parse_args()
    out = Path(args.out)
    commit = extract(args, out)
    if not commit.startswith(KNOWN_COMMIT):
        print(f"port.py: warning: original at {commit}, the port was written against {KNOWN_COMMIT}", file=sys.stderr)
    glm = copy_glm(args, out)
    s = Source(out / "src")
    port(s)
    for name in ("swarf_port.h", "swarf_port.cu", "swarf_tex.cuh"):
        shutil.copy(HERE / name, out / "src" / name)
    info = {"original": "iwf-inspire/mfree_iwf-ul_cut_gpu", "commit": commit, "glm": glm, "edits": s.log}
    (out / "PORT_INFO.json").write_text(json.dumps(info, indent=1) + "\n")
    print(f"ported {commit[:12]} into {out} ({len(s.log)} edits); build: bash ci/original/build.sh")


if __name__ == "__main__":
    main()
