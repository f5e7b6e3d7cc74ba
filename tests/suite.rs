//! The CPU test suite as one binary (Cargo.toml: one compile and link instead of one per file). Each file of
//! tests/ is a module here and reads as before: `cargo test --release --test suite cutting::` runs the tests of
//! tests/cutting.rs. The files apart from it are declared in Cargo.toml.

mod common;

mod analytic_nairn;
mod av_switch;
mod blanking;
mod check;
mod checkpoint;
mod chip_frame;
mod contact;
mod cspm;
mod cutting;
mod cutting_analysis;
mod damage;
mod damage_scenes;
mod early_stop;
mod elastic_benchmarks;
mod energy_audit;
mod ensemble;
mod fields;
mod flow_stress;
mod frame_tool;
mod grinding_wheel;
mod heat_conduction;
mod hostile_input;
mod identify_cli;
mod identify_optim;
mod install_portability;
mod material_point;
mod mesh_tool;
mod mfree_iwf;
mod mixed_precision;
mod mpm;
mod neighbour_search;
mod output;
mod periodic;
mod pic_damping;
mod plastic_impact;
mod plot;
mod render_sweep;
mod return_mapping;
mod run_folder;
mod run_safety;
mod scene;
mod several_tools;
mod sph_cohesive;
mod sph_kernel;
mod stability_contact;
mod stability_energy;
mod stability_solids;
mod stability_thermal;
mod state_table;
mod steady_state;
mod study;
mod thermal_expansion;
mod tool_3d;
mod tool_geometry;
mod tool_rotation;
mod tuning;
mod tutorial;

/// With `autotests = false` a test file that is neither a module here nor a `[[test]]` of Cargo.toml would
/// silently never build or run: every tests/*.rs must be exactly one of the two.
#[test]
fn every_test_file_builds_in_the_suite_or_its_own_binary() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &str| std::fs::read_to_string(root.join(p)).expect("readable");
    let (suite, manifest) = (read("tests/suite.rs"), read("Cargo.toml"));
    let modules: Vec<String> =
        suite.lines().filter_map(|l| l.strip_prefix("mod ")?.strip_suffix(';').map(String::from)).collect();
    let apart: Vec<String> = manifest
        .lines()
        .filter_map(|l| l.strip_prefix("path = \"tests/")?.strip_suffix(".rs\"").map(String::from))
        .collect();
    for entry in std::fs::read_dir(root.join("tests")).expect("tests/") {
        let name = entry.expect("entry").file_name().into_string().expect("utf-8 name");
        let Some(stem) = name.strip_suffix(".rs") else { continue };
        let (m, a) = (modules.iter().any(|x| x == stem), apart.iter().any(|x| x == stem));
        assert!(
            m != a,
            "tests/{name}: a module of tests/suite.rs ({m}) or a [[test]] of Cargo.toml ({a}), one of them"
        );
    }
}
