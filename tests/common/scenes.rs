//! Scene texts and scenes shared by the CPU and GPU tests.

use std::path::Path;
use swarf::ensemble::Job;
use swarf::run::RunOptions;
use swarf::scene::Scene;

/// A Ti6Al4V block (elastic–plastic, 12 × 6 particles, Δx = 10 µm) dropped at `speed` onto the flat top face of a
/// resting tool (rake 0°, clearance 7°, top at y = 0.2 mm).
pub fn drop_scene(speed: f64, kappa: f64, friction: f64, slide: f64) -> String {
    format!(
        r#"
name = "drop"
dim = 2
[discretisation]
dx = 1.0e-5
h_over_dx = 1.5
[material]
name = "Ti6Al4V-V0060-DE-mu035"
[physics]
plastic_heating = false
[[body]]
name = "block"
shape = "rectangle"
min = [-3.0e-4, 2.02e-4]
max = [-1.8e-4, 2.62e-4]
velocity = [{slide}, -{speed}]
[tool]
rake_angle = 0.0
clearance_angle = 7.0
edge_radius = 2.0e-5
length = 4.0e-4
height = 2.0e-4
position = [0.0, 0.0]
velocity = [0.0, 0.0]
contact_stiffness = {kappa}
friction = {friction}
[stabilisation]
artificial_viscosity = {{ alpha = 1.0, beta = 1.0, eta = 0.1 }}
[time]
end = 1.2e-6
[output]
every = 2.0e-9
"#
    )
}

/// [`drop_scene`] at 50 m/s with a sliding component, plastic with heating, the CURRENT friction cap, friction
/// heating and the Usui wear output: every input of the contact pass that the plastic corrector produces. The
/// contact is the theses' undamped step law ([`STEP_CONTACT`]), under which this impact yields within 400 steps;
/// the default damped bulk law absorbs it elastically.
pub fn plastic_drop_scene() -> String {
    drop_scene(50.0, 0.1, 0.35, 10.0)
        .replace("plastic_heating = false", "plasticity = true\nplastic_heating = true")
        .replace(
            "friction = 0.35\n",
            &format!(
                "friction = 0.35\nfriction_cap = \"current\"\nfriction_heating = 0.5\n\
                 usui = {{ psi = 1.0e-9, xi = 5000.0 }}\n{STEP_CONTACT}"
            ),
        )
}

/// The `[tool]` lines of the theses' undamped step-law contact (the default before issue 22).
pub const STEP_CONTACT: &str = "contact_law = \"step\"\ncontact_damping = 0.0\n";

/// V0060 coarsened to Δx = 20 µm (as tests/cutting.rs's CI cut), 4 µs of cut, with `extra` overrides.
pub fn coarse_cut(extra: &[&str]) -> Scene {
    Scene::load("cases/cutting/v0060.toml", &coarse_overrides(extra)).expect("scene")
}

/// The `--set` overrides of [`coarse_cut`]: V0060 at Δx = 20 µm, 4 µs of cut, then `extra` (a later key wins).
pub fn coarse_overrides(extra: &[&str]) -> Vec<String> {
    let mut over: Vec<String> = [
        "discretisation.dx=2.0e-5",
        "body.0.max=[1.0e-3,2.8e-4]",
        "boundary.1.max=[1.0e-9,1.4e-4]",
        "boundary.2.min=[0.9999e-3,-1.0]",
        "tool.position=[-3.6e-5]",
        "tool.depth_of_cut=0.9e-4",
        "time.end=4.0e-6",
        "output.every=1.0e-6",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    over.extend(extra.iter().map(|s| s.to_string()));
    over
}

/// The members: the model, and one change each of friction, material, tool geometry, speed, feed and resolution.
pub fn ensemble_members() -> Vec<Scene> {
    vec![
        coarse_cut(&[]),
        coarse_cut(&["tool.friction=0.2"]),
        coarse_cut(&["material.youngs_modulus=1.0e11"]),
        coarse_cut(&["tool.edge_radius=2.0e-5", "tool.rake_angle=5.0"]),
        coarse_cut(&["tool.velocity=[4.0,0.0]"]),
        coarse_cut(&["tool.depth_of_cut=0.7e-4"]),
        coarse_cut(&["discretisation.dx=2.5e-5"]),
    ]
}

pub fn ensemble_jobs(scenes: Vec<Scene>, root: &Path) -> Vec<Job> {
    scenes
        .into_iter()
        .enumerate()
        .map(|(k, scene)| Job { scene, options: RunOptions::quiet(root.join(format!("{k:02}"))) })
        .collect()
}

/// What a run must repeat bit for bit: its force samples (forces.csv's text: Rust's shortest round-trip numbers)
/// and its energies (energy.csv's text).
pub fn run_record(run: &Path) -> (String, String) {
    let read =
        |f: &str| std::fs::read_to_string(run.join(f)).unwrap_or_else(|e| panic!("{}: {e}", run.join(f).display()));
    (read("forces.csv"), read("energy.csv"))
}

/// A Ti6Al4V strip (21 × 11 particles, Δx = 100 µm) pulled apart at `speed` m/s top and bottom for `end` s, with
/// JC damage, Hillerborg softening and the interaction mask, and a fully damaged pre-crack across its left half.
pub fn pulled_strip_scene(speed: f64, end: f64) -> String {
    moving_pulled_strip_scene(speed, end, 0.0)
}

/// [`pulled_strip_scene`] with every velocity (the strip's and both pulled boundaries') shifted by `u` m/s along x.
pub fn moving_pulled_strip_scene(speed: f64, end: f64, u: f64) -> String {
    format!(
        r#"
name = "strip"
dim = 2
[discretisation]
dx = 1.0e-4
[material]
name = "Ti6Al4V-Klippel-JC"
[physics]
plasticity = true
plastic_heating = true
[[body]]
name = "strip"
shape = "rectangle"
min = [0.0, 0.0]
max = [2.0e-3, 1.0e-3]
velocity = [{u:?}, 0.0]
[[boundary]]
kind = "velocity"
min = [-1.0, -1.0]
max = [1.0, 1.0e-4]
velocity = [{u:?}, -{speed}]
[[boundary]]
kind = "velocity"
min = [-1.0, 0.9e-3]
max = [1.0, 1.0]
velocity = [{u:?}, {speed}]
[stabilisation]
artificial_viscosity = {{ alpha = 1.0, beta = 1.0, eta = 0.1 }}
[damage]
mask = true
[[damage.pre_crack]]
min = [-1.0, 0.45e-3]
max = [1.0e-3, 0.55e-3]
[time]
end = {end}
[output]
every = {every}
"#,
        every = end / 10.0
    )
}

/// [`drop_scene`] in 3D: the block 12 × 6 × 3 particles (Δx = 10 µm, cell centres from y = 202 µm and z = 5 to
/// 25 µm) dropped at `speed` onto the
/// top face of the tool, given by `tool`, the `[tool]` lines of its shape and placement (the parametric tool's
/// outline and `position = [0.0, 0.0]`, or a mesh); the velocity and contact law are the 2D scene's.
pub fn drop_scene_3d(speed: f64, slide: f64, tool: &str) -> String {
    format!(
        r#"
name = "drop3d"
dim = 3
[discretisation]
dx = 1.0e-5
h_over_dx = 1.5
[material]
name = "Ti6Al4V-V0060-DE-mu035"
[physics]
plastic_heating = false
[[body]]
name = "block"
shape = "box"
min = [-3.0e-4, 1.97e-4, 0.0]
max = [-1.8e-4, 2.57e-4, 3.0e-5]
velocity = [{slide}, -{speed}, 0.0]
[tool]
{tool}
contact_stiffness = 0.1
friction = 0.35
[stabilisation]
artificial_viscosity = {{ alpha = 1.0, beta = 1.0, eta = 0.1 }}
[time]
end = 6.0e-7
[output]
every = 3.0e-8
"#
    )
}

/// The `[tool]` lines of the parametric tool of [`drop_scene`] (rake 0°, clearance 7°, sharp, 0.4 × 0.2 mm, its
/// edge at the origin), resting.
pub const PRISM_TOOL: &str = "rake_angle = 0.0\nclearance_angle = 7.0\nlength = 4.0e-4\nheight = 2.0e-4\n\
                              position = [0.0, 0.0]\nvelocity = [0.0, 0.0]";

/// The prism of [`PRISM_TOOL`]'s outline from z = `z0` to `z1` as a Wavefront OBJ text: the outline's four
/// corners (edge at the origin, rake face up to the top, the back, the flank at 7° back down to the edge),
/// counter-clockwise seen from +z, extruded; the caps fanned, the sides split in two, all faces outward.
pub fn prism_obj(z0: f64, z1: f64) -> String {
    prism_obj_long(4.0e-4, z0, z1)
}

/// [`prism_obj`] with the outline `l` long behind the edge.
pub fn prism_obj_long(l: f64, z0: f64, z1: f64) -> String {
    let h = 2.0e-4;
    let flank_y = l * 7f64.to_radians().tan();
    // Counter-clockwise in the x–y plane: edge, rake top, top back, flank back.
    let ring = [[0.0, 0.0], [0.0, h], [-l, h], [-l, flank_y]];
    let mut s = String::from("# the prism of swarf's parametric test tool (tests/common/scenes.rs)\n");
    for z in [z0, z1] {
        for p in ring {
            s.push_str(&format!("v {:e} {:e} {:e}\n", p[0], p[1], z));
        }
    }
    // Bottom cap (z0) seen from −z: clockwise in x–y; top cap (z1) counter-clockwise.
    s.push_str("f 1 4 3 2\nf 5 6 7 8\n");
    for k in 0..4 {
        let (a, b) = (k + 1, (k + 1) % 4 + 1);
        s.push_str(&format!("f {a} {b} {} {}\n", b + 4, a + 4));
    }
    s
}

/// A closed cylinder of radius `r` about the z axis from z = `z0` to `z1`, `n` segments, as Wavefront OBJ text:
/// the two rings, the caps fanned from their centres, every face outward.
pub fn cylinder_obj(r: f64, z0: f64, z1: f64, n: usize) -> String {
    let mut s = String::from("# a cylinder (tests/common/scenes.rs)\n");
    for z in [z0, z1] {
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            s.push_str(&format!("v {:e} {:e} {:e}\n", r * a.cos(), r * a.sin(), z));
        }
    }
    s.push_str(&format!("v 0 0 {z0:e}\nv 0 0 {z1:e}\n"));
    let (c0, c1) = (2 * n + 1, 2 * n + 2);
    for k in 0..n {
        let (a, b) = (k + 1, (k + 1) % n + 1);
        // Side: counter-clockwise seen from outside; bottom cap seen from −z; top cap seen from +z.
        s.push_str(&format!("f {a} {b} {}\nf {a} {} {}\n", b + n, b + n, a + n));
        s.push_str(&format!("f {c0} {b} {a}\nf {c1} {} {}\n", a + n, b + n));
    }
    s
}

/// [`drop_scene_3d`] under several tools: `tools` are the `[[tool]]` tables' own lines (the contact keys of the
/// single-tool scene are appended to the last).
pub fn drop_scene_3d_tools(speed: f64, slide: f64, tools: &[String]) -> String {
    drop_scene_3d(speed, slide, &tools.join("\n[[tool]]\n")).replace("[tool]\n", "[[tool]]\n")
}

/// The `[[tool]]` lines of [`PRISM_TOOL`]'s prism as a mesh (`prism.obj` from z = −1 mm to 1 mm, written to
/// `dir`) with its edge at x = `x`, resting, with `extra` lines.
pub fn prism_mesh_tool(dir: &std::path::Path, x: f64, extra: &str) -> String {
    let file = dir.join("prism.obj");
    std::fs::write(&file, prism_obj(-1e-3, 1e-3)).expect("write the mesh");
    format!(
        "mesh = {{ file = {:?} }}\nposition = [{x:e}, 0.0, 0.0]\nvelocity = [0.0, 0.0, 0.0]\n{extra}",
        file.display().to_string()
    )
}

/// V0060 at Δx = 20 µm (as [`coarse_cut`]), 4 µs of cut, on one block, or on two equal blocks 1 mm apart in y,
/// each cut by its own tool (`[[tool]]`, the second tool's depth measured on the upper block). The blocks' extents
/// and fixed regions end between lattice rows, so that rounding cannot make the blocks differ by a row.
pub fn twin_cut_scene(two: bool) -> String {
    let block = |name: &str, y0: f64| {
        format!(
            r#"
[[body]]
name = "{name}"
shape = "rectangle"
lattice = "nodes"
min = [0.0, {y0:e}]
max = [1.0e-3, {:e}]
[[boundary]]
kind = "fixed"
body = "{name}"
min = [-1.0, {:e}]
max = [1.0, {:e}]
[[boundary]]
kind = "fixed"
body = "{name}"
min = [-1.0e-9, {:e}]
max = [1.0e-9, {:e}]
[[boundary]]
kind = "fixed"
body = "{name}"
min = [0.9999e-3, {:e}]
max = [1.0, {:e}]
"#,
            y0 + 2.81e-4,
            y0 - 1e-9,
            y0 + 1e-9,
            y0 - 1e-9,
            y0 + 1.5e-4,
            y0 - 1e-9,
            y0 + 3.0e-4,
        )
    };
    let tool = |body: &str| {
        format!(
            r#"
[[tool]]
rake_angle = 0.0
clearance_angle = 7.0
edge_radius = 33.0e-6
length = 4.0e-4
height = 4.0e-4
position = [-3.6e-5]
depth_of_cut = 0.9e-4
body = "{body}"
velocity = [6.355, 0.0]
friction = 0.35
"#
        )
    };
    let mut text = String::from(
        r#"
name = "twin-cut"
dim = 2
[discretisation]
dx = 2.0e-5
h_over_dx = 1.5
[material]
name = "Ti6Al4V-V0060-DE-mu035"
[physics]
plasticity = true
plastic_heating = true
initial_temperature = 298.0
[stabilisation]
artificial_viscosity = { alpha = 1.0, beta = 1.0, eta = 0.1 }
artificial_stress = { epsilon = 0.3, exponent = 4 }
xsph = { epsilon = 0.5 }
[time]
end = 4.0e-6
cfl = 0.5
[output]
every = 1.0e-6
"#,
    );
    text += &block("lower", 0.0);
    if two {
        text += &block("upper", 1.0e-3);
    }
    text += &tool("lower");
    if two {
        text += &tool("upper");
    }
    text
}

/// An MPM sweep of `file` over `grids` with the overrides `sets`, `width` runs at once, into `out`; and each
/// point's forces.csv text (for comparing a batch with solo runs).
pub fn mpm_sweep(
    b: &swarf::backend::AnyBackend,
    file: &str,
    sets: &[&str],
    grids: &[&str],
    width: usize,
    out: &Path,
) -> (swarf::sweep::Sweep, Vec<String>) {
    let _ = std::fs::remove_dir_all(out);
    let opts = swarf::sweep::SweepOptions {
        scene: file.into(),
        overrides: sets.iter().map(|s| s.to_string()).collect(),
        grids: grids.iter().map(|g| swarf::sweep::Grid::parse(g).expect("grid")).collect(),
        out_dir: out.to_path_buf(),
        precision: None,
        frames: false,
        quiet: true,
        width: Some(width),
    };
    let sweep = swarf::sweep::sweep(b, &opts).expect("sweep");
    let forces =
        sweep.points.iter().map(|p| std::fs::read_to_string(p.dir.join("forces.csv")).expect("forces.csv")).collect();
    (sweep, forces)
}
