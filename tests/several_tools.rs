//! Issue 24: several rigid tools in one scene (`[[tool]]`, docs/3d.md "Several tools"). Each tool has its own
//! shape, motion and contact law; a particle inside several is taken by the first; forces.csv gives every further
//! tool's force, moment and contacts. CPU; the GPU twin is tests/gpu.rs's `several_tools_equal_cpu`.

use crate::common;

use common::scenes::{PRISM_TOOL, drop_scene_3d, drop_scene_3d_tools, prism_mesh_tool, prism_obj_long, twin_cut_scene};
use std::path::{Path, PathBuf};
use swarf::run::{RunOptions, run};
use swarf::scene::Scene;

fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("swarf-test-tools-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// forces.csv of a run of `text` into `dir`: its header and rows.
fn run_csv(text: &str, dir: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let scene = Scene::from_str(text, "tools.toml", &[]).expect("scene");
    run(&common::test_backend(), &scene, &RunOptions::quiet(dir.to_path_buf())).expect("run");
    swarf::output::csv::read(&dir.join("forces.csv")).expect("forces.csv")
}

fn column(head: &[String], name: &str) -> usize {
    head.iter().position(|c| c == name).unwrap_or_else(|| panic!("no column {name} in {head:?}"))
}

/// Two mesh tools side by side whose top faces make the top face of one tool twice as long (the test prism's
/// mesh with its edge at x = −0.24 mm, and another at 0.16 mm, whose back face meets the first's rake face): a
/// block dropped at 10 m/s across the seam, sliding at 2 m/s, is pushed by the pair as by the long tool alone (the
/// same prism 0.8 mm long, edge at 0.16 mm, whose vertices span the pair's: the same neighbour grid). Every
/// particle touches the plane y = 0.2 mm in both runs, so the pair's summed force equals the long tool's to
/// rounding (1e-9 of the peak: the triangles differ), both tools carry part of it, and their contacts add up.
#[test]
fn two_tools_that_make_one_push_as_that_tool() {
    let dir = scratch("pair");
    // The scene appends its contact law to the last tool; the first gets the same.
    let law = "contact_stiffness = 0.1\nfriction = 0.35";
    let tools = [prism_mesh_tool(&dir, -2.4e-4, law), prism_mesh_tool(&dir, 1.6e-4, "")];
    let (head, pair) = run_csv(&drop_scene_3d_tools(10.0, 2.0, &tools), &dir.join("pair"));
    let file = dir.join("long.obj");
    std::fs::write(&file, prism_obj_long(8.0e-4, -1e-3, 1e-3)).expect("write the mesh");
    let long = format!(
        "mesh = {{ file = {:?} }}\nposition = [1.6e-4, 0.0, 0.0]\nvelocity = [0.0, 0.0, 0.0]",
        file.display().to_string()
    );
    let (head1, one) = run_csv(&drop_scene_3d(10.0, 2.0, &long), &dir.join("one"));
    assert_eq!(head1, swarf::cutting::record::force_columns(3, 1));
    assert_eq!(head, swarf::cutting::record::force_columns(3, 2));
    assert_eq!(pair.len(), one.len(), "sample counts");
    let (fx, fx2, n, n2) =
        (column(&head, "fx_n"), column(&head, "fx_n_t2"), column(&head, "contacts"), column(&head, "contacts_t2"));
    let peak = one.iter().map(|r| r[fx + 1].abs()).fold(0.0, f64::max);
    assert!(peak > 0.0, "the block must land");
    let (mut worst, mut both) = (0.0f64, 0);
    for (p, o) in pair.iter().zip(&one) {
        assert_eq!(p[n] + p[n2], o[n], "contacts at t = {}", p[0]);
        if p[n] > 0.0 && p[n2] > 0.0 {
            both += 1;
        }
        for k in 0..3 {
            worst = worst.max((p[fx + k] + p[fx2 + k] - o[fx + k]).abs() / peak);
        }
    }
    eprintln!("pair against one tool: worst |F_A + F_B − F| / peak = {worst:.2e}; {both} samples with both in contact");
    assert!(worst < 1e-9, "the pair's force differs from the long tool's by {worst:e} of the peak");
    assert!(both > 0, "both tools must carry the block");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two equal blocks 1 mm apart, each cut by its own tool (V0060 at Δx = 20 µm, 4 µs): the cut is translation
/// invariant, so each tool's force equals the one-block run's, and the second tool's columns of forces.csv
/// report the second cut (to 1e-6 of the peak: the blocks differ only in the rounding of their positions). With
/// Usui wear on both tools of the twin run (an output only: the forces are the one-block run's), the second
/// tool's wear rate equals the first's to 1e-6 of the largest.
#[test]
fn twin_cuts_give_each_tool_the_force_of_one_cut() {
    let dir = scratch("twin");
    let (h1, one) = run_csv(&twin_cut_scene(false), &dir.join("one"));
    let worn = twin_cut_scene(true).replace("friction = 0.35\n", "friction = 0.35\nusui = {}\n");
    let (h2, two) = run_csv(&worn, &dir.join("two"));
    assert_eq!(h1, swarf::cutting::record::force_columns(2, 1));
    assert_eq!(h2, swarf::cutting::record::force_columns(2, 2));
    let (fc, ff, fx2, fy2) =
        (column(&h2, "fc_n_per_mm"), column(&h2, "ff_n_per_mm"), column(&h2, "fx_n_t2"), column(&h2, "fy_n_t2"));
    let peak = one.iter().map(|r| r[fc].abs().max(r[ff].abs())).fold(0.0, f64::max);
    assert!(peak > 10.0, "the tool must cut (peak {peak} N/mm)");
    let mut worst = 0.0f64;
    for (a, b) in one.iter().zip(&two) {
        // The second tool's F_c = F_x, F_f = −F_y, per m of depth (×1e-3: per mm).
        for d in [a[fc] - b[fc], a[ff] - b[ff], a[fc] - 1e-3 * b[fx2], a[ff] + 1e-3 * b[fy2]] {
            worst = worst.max(d.abs() / peak);
        }
    }
    eprintln!("twin cuts: worst force difference {worst:.2e} of the peak {peak:.1} N/mm over {} samples", two.len());
    assert_eq!(one.len(), two.len(), "sample counts");
    assert!(worst < 1e-6, "the twin cuts differ by {worst:e} of the peak");
    let (w1, w2) = (column(&h2, "wear_rate_m_per_s"), column(&h2, "wear_rate_m_per_s_t2"));
    let top = two.iter().map(|r| r[w1]).filter(|w| w.is_finite()).fold(0.0, f64::max);
    assert!(top > 0.0, "the tools must wear");
    for r in &two {
        assert_eq!(r[w1].is_nan(), r[w2].is_nan(), "contact at t = {}", r[0]);
        assert!(r[w1].is_nan() || (r[w1] - r[w2]).abs() <= 1e-6 * top, "wear at t = {}: {} {}", r[0], r[w1], r[w2]);
    }
    // summary.json's `tools`: each tool's accumulated wear Σ Ẇ Δt over the samples with contact (recomputed here from
    // forces.csv, 1e-12), the twins' equal (1e-6); none recorded without `usui`.
    let summary = |d: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join(d).join("summary.json")).expect("summary"))
            .expect("json")
    };
    let (s2, s1) = (summary("two"), summary("one"));
    let n1 = column(&h2, "contacts");
    let mut sum = 0.0;
    for (k, r) in two.iter().enumerate() {
        let dt = r[0] - if k == 0 { 0.0 } else { two[k - 1][0] };
        if r[n1] > 0.0 && r[w1].is_finite() {
            sum += r[w1] * dt;
        }
    }
    let (a, b) = (s2["tools"][0]["wear_m"].as_f64().expect("wear"), s2["tools"][1]["wear_m"].as_f64().expect("wear"));
    assert!(sum > 0.0 && (a - sum).abs() <= 1e-12 * sum, "accumulated wear {a} against {sum}");
    assert!((a - b).abs() <= 1e-6 * a, "the twins' wear {a} {b}");
    assert!(s1["tools"][0]["wear_m"].is_null() && s1["tools"][0]["contact_time_s"].as_f64() > Some(0.0));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `[[tool]]` input is checked before the run: tools of mixed kinds, a thermal tool among several, and a second
/// tool that never meets the workpiece are refused, naming the tool's key.
#[test]
fn several_tools_input_is_checked() {
    let dir = scratch("input");
    let mesh = prism_mesh_tool(&dir, 1.6e-4, "");
    let mixed = drop_scene_3d_tools(10.0, 2.0, &[mesh.clone(), PRISM_TOOL.to_string()]);
    let e = Scene::from_str(&mixed, "mixed.toml", &[]).expect_err("mixed kinds").to_string();
    assert!(e.contains("tool.1") && e.contains("every tool of one kind"), "{e}");
    // `[tool.thermal]` after the first `[[tool]]` belongs to it.
    let thermal_tool = format!("{mesh}\n[tool.thermal]\nmaterial = \"WC-C2D\"\ntemperature = 300.0");
    let thermal = drop_scene_3d_tools(10.0, 2.0, &[thermal_tool, mesh.clone()]);
    let e = Scene::from_str(&thermal, "thermal.toml", &[]).map(|_| ()).expect_err("thermal with several").to_string();
    assert!(e.contains("tool.0.thermal") && e.contains("with several tools"), "{e}");
    let far = prism_mesh_tool(&dir, 5.0e-3, "");
    let text = drop_scene_3d_tools(10.0, 2.0, &[mesh, far]);
    let scene = Scene::from_str(&text, "far.toml", &[]).expect("scene");
    let e = run(&common::test_backend(), &scene, &RunOptions::quiet(dir.join("far"))).expect_err("never meets");
    assert!(e.to_string().contains("tool.1: the tool never meets the workpiece"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
