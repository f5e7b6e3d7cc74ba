// swarf's hooks into the original 2D GPU code; see swarf_port.h for what each setting does and
// docs/original-code.md for the files written. Ours, not the original's: copied into original/src by
// ci/original/port.py. Everything here reads the particle state, or the tool, and writes files; nothing writes
// to the solver's state except the bookkeeping array of original particle indices, which is ours.
//
// Files (in $ORIG_OUT):
//   meta.json                    units, dt, particle counts, settings
//   forces.csv                   step,time,fx,fy: Σ(f_c + f_t) over all particles (the original's report_force),
//                                every ORIG_FORCE_EVERY steps, in code units (µs; g·cm/µs² per cm of depth)
//   dumps/state_NNNNNN.csv       the whole particle state after NNNNNN steps, one row per particle, sorted by
//                                the particle's index at set-up (column id), in code units
//   dumps/tool_NNNNNN.csv        the tool's segments and fillet at the same instant, full precision
//   timing.json                  the original's own GPU-event time of the step loop

#include "swarf_port.h"

#include "benchmarks.h"
#include "output.h"

#include <thrust/device_ptr.h>
#include <thrust/sequence.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>
#include <vector>

extern float_t global_dt;
extern float_t global_t_final;

namespace {

std::string g_setup = "ref_cut";
int g_force_every = 100;
std::vector<int> g_dumps = {0, 1, 10, 100};
bool g_vtk = true;
int g_frame_every = 0;
double g_cut_mm = 0.;
FILE *g_forces = nullptr;
int *g_orig = nullptr;      // device: for each slot, the index the particle had at set-up
int *g_orig_tmp = nullptr;  // device: scratch for the gather
std::vector<float2_t> g_pos0;  // host: positions at set-up, by set-up index
unsigned int g_n = 0;

const char *env(const char *name) {
    const char *v = getenv(name);
    return (v && *v) ? v : nullptr;
}

void die(const char *msg, const char *what = "") {
    fprintf(stderr, "swarf port: %s%s\n", msg, what);
    exit(2);
}

void check(cudaError_t e, const char *what) {
    if (e != cudaSuccess) {
        fprintf(stderr, "swarf port: %s: %s\n", what, cudaGetErrorString(e));
        exit(3);
    }
}

void mkdir_p(const std::string &path) {
    std::string cur;
    for (size_t i = 0; i <= path.size(); i++) {
        if (i == path.size() || path[i] == '/') {
            if (!cur.empty() && mkdir(cur.c_str(), 0777) != 0 && errno != EEXIST) die("cannot create ", cur.c_str());
        }
        if (i < path.size()) cur += path[i];
    }
}

__global__ void gather_index(const int *idx, const int *orig, int *out, unsigned int n) {
    unsigned int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < n) out[i] = orig[idx[i]];
}

template <class T> std::vector<T> to_host(const T *d, unsigned int n) {
    std::vector<T> h(n);
    check(cudaMemcpy(h.data(), d, sizeof(T) * n, cudaMemcpyDeviceToHost), "device to host copy");
    return h;
}

void write_tool(int step) {
    if (!global_tool) return;
    char buf[256];
    snprintf(buf, sizeof buf, "dumps/tool_%06d.csv", step);
    FILE *fp = fopen(buf, "w");
    if (!fp) die("cannot write ", buf);
    fprintf(fp, "kind,x0,y0,x1,y1,nx,ny,r,t1,t2\n");
    for (const segment &s : global_tool->get_segments()) {
        fprintf(fp, "segment,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,,,\n", s.left.x, s.left.y, s.right.x, s.right.y,
                s.n.x, s.n.y);
    }
    if (circle_segment *f = global_tool->get_fillet()) {
        fprintf(fp, "fillet,%.17g,%.17g,,,,,%.17g,%.17g,%.17g\n", f->p.x, f->p.y, f->r, f->t1, f->t2);
    }
    fclose(fp);
}

void dump_state(particle_gpu *p, int step) {
    check(cudaDeviceSynchronize(), "before the state dump");
    unsigned int n = p->N;
    std::vector<int> orig = to_host(g_orig, n);
    std::vector<float2_t> pos = to_host(p->pos, n), vel = to_host(p->vel, n), fc = to_host(p->fc, n),
                          ft = to_host(p->ft, n), nrm = to_host(p->n, n);
    std::vector<float4_t> S = to_host(p->S, n);
    std::vector<float_t> rho = to_host(p->rho, n), prs = to_host(p->p, n), T = to_host(p->T, n),
                         eps = to_host(p->eps_pl, n), eps_dot = to_host(p->eps_pl_dot, n),
                         fixed = to_host(p->fixed, n), blanked = to_host(p->blanked, n),
                         tool = to_host(p->tool_particle, n), h = to_host(p->h, n);

    std::vector<int> slot(n, -1);
    for (unsigned int i = 0; i < n; i++) {
        if (orig[i] < 0 || (unsigned int)orig[i] >= n || slot[orig[i]] != -1) die("particle index bookkeeping broken");
        slot[orig[i]] = i;
    }

    char buf[256];
    snprintf(buf, sizeof buf, "dumps/state_%06d.csv", step);
    FILE *fp = fopen(buf, "w");
    if (!fp) die("cannot write ", buf);
    fprintf(fp, "id,x0,y0,tool,fixed,blanked,x,y,vx,vy,rho,p,sxx,sxy,syy,szz,T,eps_pl,eps_pl_dot,"
                "fcx,fcy,ftx,fty,nx,ny,h\n");
    for (unsigned int id = 0; id < n; id++) {
        int i = slot[id];
        fprintf(fp,
                "%u,%.17g,%.17g,%d,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
                id, g_pos0[id].x, g_pos0[id].y, tool[i] == 1. ? 1 : 0, fixed[i] == 1. ? 1 : 0,
                blanked[i] == 1. ? 1 : 0, pos[i].x, pos[i].y, vel[i].x, vel[i].y, rho[i], prs[i], S[i].x, S[i].y,
                S[i].z, S[i].w, T[i], eps[i], eps_dot[i], fc[i].x, fc[i].y, ft[i].x, ft[i].y, nrm[i].x, nrm[i].y,
                h[i]);
    }
    fclose(fp);
    write_tool(step);
    printf("swarf port: wrote %s\n", buf);
}

void write_meta(particle_gpu *p) {
    unsigned int n = p->N;
    std::vector<float_t> tool = to_host(p->tool_particle, n), fixed = to_host(p->fixed, n), h = to_host(p->h, n),
                         rho = to_host(p->rho, n);
    unsigned int n_tool = 0, n_fixed = 0;
    for (unsigned int i = 0; i < n; i++) {
        n_tool += tool[i] == 1.;
        n_fixed += fixed[i] == 1. && tool[i] != 1.;
    }
    FILE *fp = fopen("meta.json", "w");
    if (!fp) die("cannot write meta.json");
    fprintf(fp, "{\n  \"code\": \"iwf-inspire/mfree_iwf-ul_cut_gpu, ported by swarf ci/original/port.py\",\n");
    fprintf(fp, "  \"setup\": \"%s\",\n", g_setup.c_str());
#ifdef USE_DOUBLE
    fprintf(fp, "  \"precision\": \"double\",\n");
#else
    fprintf(fp, "  \"precision\": \"single\",\n");
#endif
    if (g_setup == "ref_cut") {
        fprintf(fp, "  \"units\": {\"length\": \"cm\", \"time\": \"us\", \"mass\": \"g\", \"density\": \"g/cm^3\", "
                    "\"velocity\": \"cm/us\", \"stress\": \"Mbar (1e11 Pa)\", \"temperature\": \"K\", "
                    "\"force\": \"g cm/us^2 per cm of depth (1e7 N/cm = 1e6 N/mm)\"},\n");
    } else {
        fprintf(fp, "  \"units\": \"SI\",\n");
    }
    fprintf(fp, "  \"dt\": %.17g,\n  \"t_final\": %.17g,\n", global_dt, global_t_final);
    fprintf(fp, "  \"particles\": %u,\n  \"tool_particles\": %u,\n  \"fixed_workpiece_particles\": %u,\n", n, n_tool,
            n_fixed);
    fprintf(fp, "  \"h\": %.17g,\n  \"rho_first\": %.17g,\n", h[0], rho[0]);
    if (global_tool) {
        vec2_t v = global_tool->get_vel();
        fprintf(fp, "  \"tool_velocity\": [%.17g, %.17g],\n  \"tool_mu\": %.17g,\n", v.x, v.y, global_tool->mu());
    }
    fprintf(fp, "  \"force_every\": %d,\n  \"cut_mm\": %.17g,\n  \"dumps\": [", g_force_every, g_cut_mm);
    for (size_t i = 0; i < g_dumps.size(); i++) fprintf(fp, "%s%d", i ? ", " : "", g_dumps[i]);
    fprintf(fp, "],\n  \"vtk\": %s\n}\n", g_vtk ? "true" : "false");
    fclose(fp);
}

}  // namespace

void port_begin() {
    if (const char *v = env("ORIG_SETUP")) g_setup = v;
    if (g_setup != "ref_cut" && g_setup != "rings" && g_setup != "impact") die("ORIG_SETUP must be ref_cut, rings or impact, not ", g_setup.c_str());
    if (const char *v = env("ORIG_FORCE_EVERY")) g_force_every = std::max(1, atoi(v));
    if (const char *v = env("ORIG_VTK")) g_vtk = atoi(v) != 0;
    if (const char *v = env("ORIG_FRAME_EVERY")) g_frame_every = atoi(v);
    if (const char *v = env("ORIG_DUMPS")) {
        g_dumps.clear();
        std::string s = v;
        size_t at = 0;
        while (at < s.size()) {
            size_t end = s.find(',', at);
            if (end == std::string::npos) end = s.size();
            std::string item = s.substr(at, end - at);
            if (!item.empty() && item != "none") g_dumps.push_back(atoi(item.c_str()));
            at = end + 1;
        }
    }
    if (const char *v = env("ORIG_OUT")) {
        mkdir_p(v);
        if (chdir(v) != 0) die("cannot enter ", v);
    }
    mkdir_p("dumps");
    mkdir_p("results");
    printf("swarf port: setup %s, forces every %d steps, vtk %d\n", g_setup.c_str(), g_force_every, (int)g_vtk);
}

particle_gpu *port_setup(int ny, grid_base **grid, float_t rake, float_t clear, float_t fillet, float_t speed,
                         float_t feed) {
    if (g_setup == "rings") return setup_rings(80, grid);
    if (g_setup == "impact") return setup_impact(20, grid);
    return setup_ref_cut(ny, grid, rake, clear, fillet, speed, feed);
}

bool port_has_tool() {
    return g_setup == "ref_cut";
}

int port_last_step(int last_step) {
    if (const char *v = env("ORIG_STEPS")) {
        last_step = atoi(v);
        global_t_final = last_step * global_dt;
    } else if (const char *v = env("ORIG_CUT_MM")) {
        g_cut_mm = atof(v);
        if (!global_tool || global_tool->get_vel().x <= 0.) die("ORIG_CUT_MM needs a moving tool");
        global_t_final = g_cut_mm * 0.1 / global_tool->get_vel().x;  // mm -> cm, the code's length unit
        last_step = global_t_final / global_dt;                       // as the original computes it
    }
    if (g_cut_mm == 0. && global_tool && global_tool->get_vel().x > 0.) {
        g_cut_mm = last_step * global_dt * global_tool->get_vel().x * 10.;
    }
    printf("swarf port: last step %d (dt %.9g)\n", last_step, global_dt);
    return last_step;
}

int port_frame_every(int freq) {
    if (g_frame_every > 0) return g_frame_every;
    return std::max(1, freq);
}

bool port_vtk() {
    return g_vtk;
}

void port_on_step(particle_gpu *particles, int step) {
    if (!g_orig) {
        g_n = particles->N;
        check(cudaMalloc((void **)&g_orig, sizeof(int) * g_n), "cudaMalloc");
        check(cudaMalloc((void **)&g_orig_tmp, sizeof(int) * g_n), "cudaMalloc");
        thrust::device_ptr<int> t_orig(g_orig);
        thrust::sequence(t_orig, t_orig + g_n);
        g_pos0 = to_host(particles->pos, g_n);
        write_meta(particles);
        if (global_tool) {
            g_forces = fopen("forces.csv", "w");
            if (!g_forces) die("cannot write forces.csv");
            fprintf(g_forces, "step,time,fx,fy\n");
        }
    }
    if (g_forces && step % g_force_every == 0) {
        float2_t f = report_force(particles);
        fprintf(g_forces, "%d,%.17g,%.17g,%.17g\n", step, step * global_dt, f.x, f.y);
        if (step % (100 * g_force_every) == 0) fflush(g_forces);
    }
    if (std::find(g_dumps.begin(), g_dumps.end(), step) != g_dumps.end()) dump_state(particles, step);
}

void port_after_step(particle_gpu *particles) {
    // The step sorted the particles by cell: slot i now holds the particle that was in slot idx[i] (grid_gpu_green's
    // reorder). Carry the set-up index along the same permutation (one asynchronous launch; none without dumps).
    if (g_dumps.empty()) return;
    unsigned int n = particles->N;
    gather_index<<<(n + 255) / 256, 256>>>(particles->idx, g_orig, g_orig_tmp, n);
    std::swap(g_orig, g_orig_tmp);
}

void port_end(double gpu_seconds, int last_step) {
    if (g_forces) fclose(g_forces);
    g_forces = nullptr;
    FILE *fp = fopen("timing.json", "w");
    if (!fp) die("cannot write timing.json");
    fprintf(fp, "{\"gpu_seconds\": %.6f, \"steps\": %d, \"particles\": %u, \"us_per_step\": %.4f, \"vtk\": %s}\n",
            gpu_seconds, last_step + 1, g_n, 1e6 * gpu_seconds / (last_step + 1), g_vtk ? "true" : "false");
    fclose(fp);
}
