//! Issue 24: rigid tools in 3D (docs/3d.md). The contact pass with the parametric tool's prism and with a triangle
//! mesh, the scene keys of a mesh tool, the forces and moments of `forces.csv` in 3D and the tool's surface beside
//! the frames. CPU; the GPU twin of these runs is tests/gpu.rs's `tool_3d_runs_equal_cpu`.

use crate::common;

use common::scenes::{PRISM_TOOL, drop_scene_3d, prism_obj};
use std::path::{Path, PathBuf};
use swarf::run::{RunOptions, run};
use swarf::scene::Scene;

fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("swarf-test-tool3d-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// The `[tool]` lines of the mesh tool that is [`PRISM_TOOL`]'s prism from z = −1 mm to 1 mm, written to `dir`.
fn mesh_tool(dir: &Path, obj: &str) -> String {
    let file = dir.join("prism.obj");
    std::fs::write(&file, obj).expect("write the mesh");
    format!(
        "mesh = {{ file = {:?} }}\nposition = [0.0, 0.0, 0.0]\nvelocity = [0.0, 0.0, 0.0]",
        file.display().to_string()
    )
}

/// forces.csv's rows (with its header checked against the 3D columns) of a run of `text` into `dir`.
fn run_rows(text: &str, dir: &Path, frames: bool) -> Vec<Vec<f64>> {
    let scene = Scene::from_str(text, "drop3d.toml", &[]).expect("scene");
    let opts = RunOptions { frames, ..RunOptions::quiet(dir.to_path_buf()) };
    run(&common::test_backend(), &scene, &opts).expect("run");
    let (head, rows) = swarf::output::csv::read(&dir.join("forces.csv")).expect("forces.csv");
    assert_eq!(head, swarf::cutting::record::force_columns(3, 1));
    rows
}

/// Columns of forces.csv in 3D: F = (F_x, F_y, F_z) [N] and M [N·m].
const FX: usize = swarf::cutting::record::FORCE_COLUMNS.len();
const MX: usize = FX + 3;

/// The prism of the parametric tool and the same prism as a triangle mesh are one tool: a Ti6Al4V block dropped at
/// 10 m/s (sliding at 2 m/s) onto its top face gets the same contact forces from both, to 1e-9 of the largest
/// force (the two queries compute the same exact distances by different arithmetic: the outline's segments, or
/// Ericson's closest point on the triangles, so the runs differ by rounding only).
#[test]
fn parametric_prism_and_its_mesh_give_the_same_forces() {
    let dir = scratch("same");
    let prism = run_rows(&drop_scene_3d(10.0, 2.0, PRISM_TOOL), &dir.join("prism"), false);
    let mesh = run_rows(&drop_scene_3d(10.0, 2.0, &mesh_tool(&dir, &prism_obj(-1e-3, 1e-3))), &dir.join("mesh"), false);
    assert_eq!(prism.len(), mesh.len(), "sample counts");
    let scale = prism.iter().map(|r| r[FX + 1].abs()).fold(0.0, f64::max);
    assert!(scale > 0.0 && prism.iter().any(|r| r[4] > 0.0), "the block must land on the tool");
    let mut worst = 0.0f64;
    for (a, b) in prism.iter().zip(&mesh) {
        assert_eq!(a[4], b[4], "particles in contact at t = {}", a[0]);
        for k in FX..FX + 3 {
            worst = worst.max((a[k] - b[k]).abs() / scale);
        }
    }
    eprintln!("prism against mesh: {} samples, peak F_y {scale:e} N, worst difference {worst:e} of it", prism.len());
    assert!(worst <= 1e-9, "the mesh prism's forces differ from the parametric prism's by {worst:e} of the peak");
    let _ = std::fs::remove_dir_all(&dir);
}

/// forces.csv's 3D columns: the block (z from 0 to 30 µm) lands on the prism, whose normals lie in the x–y plane,
/// so by the block's mirror symmetry about z_c = 15 µm the force has no z component and the moment about the tool's
/// origin has M_x = −z_c F_y (Σ z f_y = z_c Σ f_y; Σ y f_z = 0), M_y = z_c F_x, to 1e-6 of the peak (rounding,
/// grown over the run). F_y > 0: the tool pushes the block up; the friction opposes its slide (F_x < 0).
#[test]
fn forces_and_moments_of_a_3d_contact_follow_the_mirror_symmetry() {
    let dir = scratch("moment");
    let rows = run_rows(&drop_scene_3d(10.0, 2.0, PRISM_TOOL), &dir, false);
    let zc = 1.5e-5;
    let peak = rows.iter().map(|r| r[FX + 1].abs()).fold(0.0, f64::max);
    let (mut fz, mut mx, mut my) = (0.0f64, 0.0f64, 0.0f64);
    for r in &rows {
        fz = fz.max(r[FX + 2].abs() / peak);
        mx = mx.max((r[MX] + zc * r[FX + 1]).abs() / (zc * peak));
        my = my.max((r[MX + 1] - zc * r[FX]).abs() / (zc * peak));
    }
    let contact: Vec<_> = rows.iter().filter(|r| r[4] > 0.0).collect();
    eprintln!("3D drop: peak F_y {peak:e} N; |F_z| {fz:e}, M_x {mx:e}, M_y {my:e} of the peak");
    assert!(!contact.is_empty() && contact.iter().all(|r| r[FX + 1] > 0.0), "the tool pushes the block up");
    assert!(contact.iter().any(|r| r[FX] < 0.0), "friction opposes the slide in +x");
    assert!(fz <= 1e-6 && mx <= 1e-6 && my <= 1e-6, "F_z {fz:e}, M_x {mx:e}, M_y {my:e} of the peak");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The frames carry the mesh tool's surface: `tool_*.vtp` with the mesh's 12 triangles (36 corners), where the
/// tool's motion puts it (a tool moving at 1 m/s along x has moved by v·t).
#[test]
fn frames_carry_the_mesh_tool_surface() {
    let dir = scratch("frames");
    let tool =
        mesh_tool(&dir, &prism_obj(-1e-3, 1e-3)).replace("velocity = [0.0, 0.0, 0.0]", "velocity = [1.0, 0.0, 0.0]");
    run_rows(&drop_scene_3d(10.0, 0.0, &tool), &dir.join("run"), true);
    let (time, points) = swarf::output::vtp::read_outline(&dir.join("run/tool_00002.vtp")).expect("tool frame");
    assert_eq!(points.len(), 36, "12 triangles, 3 corners each");
    let xmax = points.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max);
    assert!((xmax - time).abs() <= 1e-12, "the rake face at x = v t = {time:e}, found {xmax:e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A mesh tool's input is checked when the scene is read: only in 3D, not beside the outline keys, and a mesh that
/// is not closed is refused with the key, the file and what is wrong.
#[test]
fn mesh_tool_input_is_checked() {
    let dir = scratch("input");
    let good = drop_scene_3d(10.0, 0.0, &mesh_tool(&dir, &prism_obj(-1e-3, 1e-3)));
    let refused = |text: &str| Scene::from_str(text, "drop3d.toml", &[]).expect_err("refused").to_string();
    let e = refused(&good.replace("dim = 3", "dim = 2"));
    assert!(e.contains("tool.mesh") || e.contains("dim"), "{e}");
    let e = refused(&good.replace("[tool]\n", "[tool]\nrake_angle = 0.0\n"));
    assert!(e.contains("rake_angle") && e.contains("mesh"), "{e}");
    let open: String = prism_obj(-1e-3, 1e-3).lines().filter(|l| *l != "f 5 6 7 8").map(|l| format!("{l}\n")).collect();
    let holed = dir.join("holed");
    std::fs::create_dir_all(&holed).expect("folder");
    let e = refused(&drop_scene_3d(10.0, 0.0, &mesh_tool(&holed, &open)));
    assert!(e.contains("tool.mesh.file") && e.contains("prism.obj") && e.contains("not closed"), "{e}");
    let e = refused(&good.replace("position = [0.0, 0.0, 0.0]", "position = [0.0, 0.0]"));
    assert!(e.contains("tool.position") && e.contains("[x, y, z]"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A rotating mesh tool: a wheel (a cylinder of radius R = 100 µm about z, 512 segments) spinning at ωR = 20 m/s
/// (right-handed about +z) is fed down at 10 m/s onto a Ti6Al4V block (fixed at its bottom), μ = 0.2. At the
/// contact the wheel's surface slides at v + ω × r ≈ +20 m/s along x, far faster than anything else moves, so every
/// contact slides: the friction drags the block along +x with F_x = μ |F_y| (the friction ratio column = μ, to 2 %;
/// measured 8e-16) while the wheel pushes it down (F_y < 0), and the moment about the wheel's axis is that friction
/// at the rim, M_z = R F_x, to 5 % (measured 4.4 %: the contacts sit a penetration depth inside the rim, and the
/// patch's lever arms along x cancel only nearly). The normal forces point through the axis and add nothing.
#[test]
fn a_spinning_wheel_drags_the_block_with_its_rim_speed() {
    let dir = scratch("wheel");
    let obj = dir.join("wheel.obj");
    std::fs::write(&obj, common::scenes::cylinder_obj(1.0e-4, -1.0e-3, 1.0e-3, 512)).expect("mesh");
    let (r, rpm) = (1.0e-4, 20.0 / 1.0e-4 * 60.0 / std::f64::consts::TAU);
    let tool = format!(
        "mesh = {{ file = {:?} }}\nposition = [0.0, 1.57e-4, 0.0]\nvelocity = [0.0, -10.0, 0.0]\n\
         rotation = {{ axis = [0.0, 0.0, 1.0], centre = [0.0, 0.0, 0.0], rpm = {rpm} }}\nfriction = 0.2\n",
        obj.display().to_string()
    );
    let text = common::scenes::drop_scene_3d(0.0, 0.0, &tool)
        .replace("friction = 0.35\n", "")
        .replace(
            "min = [-3.0e-4, 1.97e-4, 0.0]\nmax = [-1.8e-4, 2.57e-4, 3.0e-5]",
            "min = [-1.5e-4, 0.0, 0.0]\nmax = [1.5e-4, 6.0e-5, 3.0e-5]",
        )
        .replace(
            "[tool]",
            "[[boundary]]\nkind = \"fixed\"\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0e-5, 1.0]\n[tool]",
        );
    let rows = run_rows(&text, &dir.join("run"), false);
    let contact: Vec<_> = rows.iter().filter(|row| row[4] >= 3.0).collect();
    assert!(contact.len() >= 5, "the wheel must press into the block ({} samples in contact)", contact.len());
    let (mut ratio, mut lever) = (0.0f64, 0.0f64);
    for row in &contact {
        let (fx, fy, mz) = (row[FX], row[FX + 1], row[MX + 2]);
        assert!(fx > 0.0 && fy < 0.0, "the rim drags the block along +x and pushes it down: F = ({fx:e}, {fy:e})");
        ratio = ratio.max((row[8] / 0.2 - 1.0).abs());
        lever = lever.max((mz / (r * fx) - 1.0).abs());
    }
    eprintln!(
        "spinning wheel: {} samples in contact; friction ratio within {ratio:e} of mu, M_z/(R F_x) within {lever:e} of 1",
        contact.len()
    );
    assert!(ratio <= 0.02, "every contact slides: friction ratio off mu by {ratio:e}");
    assert!(lever <= 0.05, "M_z = R F_x: off by {lever:e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The thermal particles of a mesh tool (`[tool.thermal]` with `mesh`): a box tool of 16 × 10 × 3 lattice cells is
/// filled by exactly its 480 cell centres (each at least dx/2 inside), and a hot block (800 K) landing on the cold
/// diamond (300 K, nothing held) heats it by conduction while Σ m c_p T over the block and the tool stays what it
/// was (Brookshaw's pair exchange is antisymmetric: to 1e-9 of the block's heat; heat_conduction.rs holds it to
/// 1e-12 on one material).
#[test]
fn a_mesh_tool_filled_with_thermal_particles_takes_heat_and_conserves_it() {
    let dir = scratch("thermal");
    let (lo, hi) = ([-3.2e-4, 1.0e-4, 0.0], [-1.6e-4, 2.0e-4, 3.0e-5]);
    let c = |x: usize, y: usize, z: usize| [[lo[0], hi[0]][x], [lo[1], hi[1]][y], [lo[2], hi[2]][z]];
    let mut obj = String::new();
    for z in 0..2 {
        for y in 0..2 {
            for x in 0..2 {
                let p = c(x, y, z);
                obj.push_str(&format!("v {:e} {:e} {:e}\n", p[0], p[1], p[2]));
            }
        }
    }
    // Vertex 1 + x + 2y + 4z; the six faces counter-clockwise seen from outside.
    obj.push_str("f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n");
    std::fs::write(dir.join("box.obj"), obj).expect("mesh");
    let tool = format!(
        "mesh = {{ file = {:?} }}\nposition = [0.0, 0.0, 0.0]\nvelocity = [0.0, 0.0, 0.0]\n\
         [tool.thermal]\nmaterial = \"Diamond-C3D\"\ntemperature = 300.0\nfixed_width = 0.0\n",
        dir.join("box.obj").display().to_string()
    );
    let text = drop_scene_3d(10.0, 0.0, &tool)
        .replace("plastic_heating = false", "plastic_heating = false\nconduction = \"brookshaw\"")
        .replace("velocity = [0, -10, 0.0]", "velocity = [0, -10, 0.0]\ntemperature = 800.0")
        .replace("contact_stiffness = 0.1\nfriction = 0.35\n", "")
        .replace("[tool]\n", "[tool]\ncontact_stiffness = 0.1\nfriction = 0.35\n");
    let scene = Scene::from_str(&text, "drop3d.toml", &[]).expect("scene");
    // The original code's node sampling is of a 2D outline's bounding box: a mesh tool is filled by cells only.
    let e = Scene::from_str(&text, "drop3d.toml", &["tool.thermal.lattice=\"nodes\"".into()]).expect_err("nodes");
    let e = e.to_string();
    assert!(e.contains("tool.thermal.lattice: expected \"cells\" (a mesh tool is filled by cells)"), "{e}");
    let lib = |name: &str| {
        swarf::material::search::Search::for_scene("drop3d.toml")
            .library()
            .expect("library")
            .get(name)
            .cloned()
            .expect("material")
    };
    let (work, diamond) = (lib("Ti6Al4V-V0060-DE-mu035"), lib("Diamond-C3D"));
    let dx3 = 1.0e-15;
    let mc = |m: &swarf::material::Material, fallback_rho: f64| {
        let th = m.thermal.expect("thermal data");
        th.density.unwrap_or(fallback_rho) * dx3 * th.specific_heat.expect("c_p")
    };
    let mc_work = scene.material.density * dx3 * work.thermal.and_then(|t| t.specific_heat).expect("c_p");
    let mc_tool = mc(&diamond, scene.material.density);
    let mut seen = Vec::new();
    let mut obs = |s: &swarf::run::Snapshot| {
        let t = s.temperature.expect("temperatures");
        let (mut heat, mut tool_n, mut tool_max) = (0.0, 0, 0.0f64);
        for (k, b) in s.body.iter().enumerate() {
            if *b == 1 {
                heat += mc_tool * t[k];
                tool_n += 1;
                tool_max = tool_max.max(t[k]);
            } else {
                heat += mc_work * t[k];
            }
        }
        seen.push((heat, tool_n, tool_max));
        true
    };
    let opts = swarf::run::RunOptions::quiet(dir.join("run"));
    swarf::run::run_observed(&common::test_backend(), &scene, &opts, Some(&mut obs)).expect("run");
    let (first, last) = (seen[0], *seen.last().expect("snapshots"));
    let block_heat = 12.0 * 6.0 * 3.0 * mc_work * 800.0;
    eprintln!(
        "thermal mesh tool: {} particles; hottest tool particle {:.3} K at the end; heat {:e} -> {:e} J ({:e} of the block's)",
        last.1,
        last.2,
        first.0,
        last.0,
        (last.0 - first.0).abs() / block_heat
    );
    assert_eq!(first.1, 480, "16 x 10 x 3 cell centres fill the box");
    assert!(last.2 > 300.0 + 1e-6, "the tool must take heat from the block (hottest {:.6} K)", last.2);
    assert!((last.0 - first.0).abs() <= 1e-9 * block_heat, "heat not conserved: {:e} -> {:e}", first.0, last.0);
    let _ = std::fs::remove_dir_all(&dir);
}
