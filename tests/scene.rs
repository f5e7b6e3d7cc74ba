//! Scene files: the benchmark scenes generate the particle counts of the theses, overrides take effect, and every
//! class of bad input is refused with a message naming the file (or `--set`), the key and what was expected.

use std::path::{Path, PathBuf};

use swarf::scene::{Bc, BoundaryKind, Lattice, Precision, Scene, SceneError, Shape};

fn case(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases").join(name)
}

fn load(name: &str, sets: &[&str]) -> Scene {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Scene::load(case(name), &sets).unwrap_or_else(|e| panic!("{e}"))
}

fn rings_text() -> String {
    std::fs::read_to_string(case("rings.toml")).unwrap()
}

/// The text of rings.toml with `from` replaced by `to` (which must occur exactly once).
fn rings_with(from: &str, to: &str) -> String {
    let text = rings_text();
    assert_eq!(text.matches(from).count(), 1, "'{from}' must occur once in rings.toml");
    text.replacen(from, to, 1)
}

/// 1-based line of the first occurrence of `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    let at = text.find(needle).unwrap_or_else(|| panic!("'{needle}' not in the text"));
    text[..at].matches('\n').count() + 1
}

/// The message of the error that `text` (as cases/rings.toml, with `sets`) must produce, at load or generation.
fn refused(text: &str, sets: &[&str]) -> String {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let err = match Scene::from_str(text, "cases/rings.toml", &sets) {
        Err(e) => e,
        Ok(scene) => match scene.generate() {
            Err(e) => e,
            Ok(p) => panic!("accepted a bad scene ({} particles)", p.len()),
        },
    };
    let msg = err.to_string();
    eprintln!("{msg}");
    msg
}

fn assert_has(msg: &str, parts: &[&str]) {
    for part in parts {
        assert!(msg.contains(part), "message lacks '{part}':\n{msg}");
    }
}

// ---------------------------------------------------------------------------------------------- the benchmarks

#[test]
fn rings_have_4232_particles_2116_per_ring_and_opposite_velocities() {
    let scene = load("rings.toml", &[]);
    assert_eq!(scene.discretisation.dx, 0.08 / 79.0);
    let p = scene.generate().unwrap();
    assert_eq!(p.len(), 4232);
    assert_eq!(p.body.iter().filter(|&&b| b == 0).count(), 2116);
    assert_eq!(p.body.iter().filter(|&&b| b == 1).count(), 2116);
    let dx = scene.discretisation.dx;
    assert_eq!(p.mass, 1.0 * dx * dx);
    assert_eq!(p.volume, dx * dx);
    let total = p.mass * p.len() as f64;
    assert!((total - 4232.0 * 1.0 * dx * dx).abs() <= 1e-15 * total);
    for i in 0..p.len() {
        let vx = if p.body[i] == 0 { 180.0 } else { -180.0 };
        assert_eq!(p.vel[i], [vx, 0.0, 0.0]);
        assert_eq!(p.pos[i][2], 0.0);
        assert_eq!(p.bc[i], Bc::Free);
    }
    // Σ m v_x = 0 (AT-68 b): ≤ 1e-10 Σ m |v|.
    let momentum: f64 = p.vel.iter().map(|v| p.mass * v[0]).sum();
    let scale: f64 = p.vel.iter().map(|v| p.mass * v[0].abs()).sum();
    assert!(momentum.abs() <= 1e-10 * scale, "Σ m v_x = {momentum}");
}

#[test]
fn rings_reproduce_the_thesis_timing_series_nbox_80k() {
    // Tabs 6.5/6.6 of Röthlin: nbox = 80k, dx = 0.08/(nbox − 1).
    let expected = [4232, 17344, 39160, 69920, 109304, 157504, 214656, 280472, 355064, 438496];
    for (k, &n) in (1..=10).zip(&expected) {
        let nbox = 80 * k;
        let dx = 0.08 / (nbox - 1) as f64;
        let set = format!("discretisation.dx={dx:e}");
        let scene = Scene::from_str(&rings_text(), "cases/rings.toml", &[set]).unwrap();
        assert_eq!(scene.discretisation.dx, dx);
        assert_eq!(scene.generate().unwrap().len(), n, "nbox = {nbox}");
    }
}

#[test]
fn disk_rotation_has_276_particles_in_rigid_rotation() {
    let scene = load("disk-rotation.toml", &[]);
    assert_eq!(scene.bodies[0].lattice, Lattice::Nodes);
    let p = scene.generate().unwrap();
    assert_eq!(p.len(), 276);
    for (x, v) in p.pos.iter().zip(&p.vel) {
        let expected = [50.0 * -x[1], 50.0 * x[0], 0.0];
        for k in 0..3 {
            assert!((v[k] - expected[k]).abs() <= 1e-12 * 50.0, "v = {v:?} at {x:?}");
        }
    }
    assert!(scene.stabilisation.artificial_viscosity.is_some());
    assert!(scene.stabilisation.artificial_stress.is_none() && scene.stabilisation.xsph.is_none());
}

/// Brute-force count of the node lattice of a (tube) cylinder, from the rule as stated: nodes of the bounding box
/// [c − r, c + r]² × [c_z, c_z + height], kept if r_in ≤ ρ < r; here 2r/dx is an integer m, so the offsets from
/// the centre are (k − m/2)·dx.
fn cylinder_count(r_in: f64, r: f64, height: f64, dx: f64) -> usize {
    let m = (2.0 * r / dx + 1e-9).floor() as usize;
    assert!((2.0 * r / dx - m as f64).abs() < 1e-9);
    let nz = (height / dx + 1e-9).floor() as usize;
    let mut count = 0;
    for _kz in 0..=nz {
        for ky in 0..=m {
            for kx in 0..=m {
                let x = (kx as f64 - 0.5 * m as f64) * dx;
                let y = (ky as f64 - 0.5 * m as f64) * dx;
                let rho = (x * x + y * y).sqrt();
                if r_in <= rho && rho < r {
                    count += 1;
                }
            }
        }
    }
    count
}

#[test]
fn cylinders_3d_count_matches_brute_force() {
    let scene = load("cylinders-3d.toml", &[]);
    assert_eq!(scene.dim, 3);
    let p = scene.generate().unwrap();
    let one = cylinder_count(0.035, 0.04, 0.005, 0.0025);
    assert!(one > 0);
    assert_eq!(p.len(), 2 * one);
    // The two tubes are the same lattice translated: equal counts.
    assert_eq!(p.body.iter().filter(|&&b| b == 0).count(), one);
    assert_eq!(p.mass, 0.0025f64.powi(3));
    for i in 0..p.len() {
        let (c, vx) = if p.body[i] == 0 { (-0.041, 250.0) } else { (0.041, -250.0) };
        let x = p.pos[i];
        let rho = ((x[0] - c).powi(2) + x[1].powi(2)).sqrt();
        assert!((0.035..0.04).contains(&rho) && (0.0..=0.005).contains(&x[2]), "{x:?}");
        assert_eq!(p.vel[i], [vx, 0.0, 0.0]);
    }
    // Three layers in z: 0, dx, 2dx.
    let mut zs: Vec<f64> = p.pos.iter().map(|x| x[2]).collect();
    zs.sort_by(f64::total_cmp);
    zs.dedup();
    assert_eq!(zs, vec![0.0, 0.0025, 0.005]);
}

#[test]
fn block_translation_count_matches_brute_force() {
    let scene = load("block-translation.toml", &[]);
    let p = scene.generate().unwrap();
    // Cell centres of [0, 0.01]^2 with dx = 2.5e-4: count them by brute force over a wider lattice.
    let dx = 2.5e-4;
    let mut count = 0;
    for j in -10..60 {
        for i in -10..60 {
            let (x, y) = ((i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx);
            if (0.0..=0.01).contains(&x) && (0.0..=0.01).contains(&y) {
                count += 1;
            }
        }
    }
    assert_eq!(count, 1600);
    assert_eq!(p.len(), count);
    assert_eq!(p.mass, 7830.0 * dx * dx);
    assert!(p.vel.iter().all(|v| *v == [100.0, 0.0, 0.0]));
    let s = &scene.stabilisation;
    assert!(s.artificial_viscosity.is_some() && s.artificial_stress.is_some() && s.xsph.is_some());
}

#[test]
fn every_case_file_loads_and_generates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
            let p = scene.generate().unwrap_or_else(|e| panic!("{e}"));
            assert!(!p.is_empty(), "{}", path.display());
            assert!(scene.summary().contains(&scene.name));
            n += 1;
        }
    }
    assert!(n >= 4, "expected the four benchmark scenes in cases/, found {n}");
}

#[test]
fn defaults_and_summary() {
    let scene = load("rings.toml", &[]);
    assert_eq!(scene.precision, Precision::F64);
    assert_eq!(scene.output.every, scene.time.end / 50.0);
    assert_eq!(scene.time.dt, None);
    assert_eq!(scene.bodies[0].lattice, Lattice::Nodes);
    assert!(matches!(scene.bodies[0].shape, Shape::Ring { .. }));
    assert!((scene.material.sound_speed() - 4082.48).abs() < 0.01);
    let summary = scene.summary();
    assert_has(&summary, &["rings", "c0 = sqrt(K/rho) = 4082.48 m/s", "left", "right", "AV", "AS", "XSPH"]);
    // The resolved scene serialises (for run metadata).
    let json = serde_json::to_string(&scene).unwrap();
    assert!(json.contains("\"shape\":\"ring\""));
}

#[test]
fn boundary_conditions_last_entry_wins_and_set_the_initial_velocity() {
    let text = r#"
        name = "bc"
        dim = 2
        [discretisation]
        dx = 0.25
        [material]
        density = 2.0
        youngs_modulus = 1e7
        poisson_ratio = 0.3
        [[body]]
        name = "a"
        shape = "rectangle"
        min = [0.0, 0.0]
        max = [2.0, 1.0]
        velocity = [1.0, 0.0]
        [[body]]
        name = "b"
        shape = "rectangle"
        min = [3.0, 0.0]
        max = [4.0, 1.0]
        [[boundary]]
        kind = "fixed"
        min = [-1.0, -1.0]
        max = [0.5, 2.0]
        [[boundary]]
        kind = "velocity"
        min = [-1.0, -1.0]
        max = [0.25, 0.5]
        velocity = [0.0, -3.0]
        [[boundary]]
        kind = "fixed"
        min = [-10.0, -10.0]
        max = [10.0, 10.0]
        body = "b"
        [time]
        end = 1.0
    "#;
    let scene = Scene::from_str(text, "bc.toml", &[]).unwrap();
    assert_eq!(scene.boundaries[1].kind, BoundaryKind::Velocity { velocity: [0.0, -3.0, 0.0] });
    assert_eq!(scene.boundaries[2].body, Some(1));
    let p = scene.generate().unwrap();
    assert_eq!(p.len(), 8 * 4 + 4 * 4);
    for i in 0..p.len() {
        let [x, y, _] = p.pos[i];
        let (bc, v) = if p.body[i] == 1 {
            (Bc::Fixed, [0.0; 3])
        } else if x <= 0.25 && y <= 0.5 {
            (Bc::Velocity([0.0, -3.0, 0.0]), [0.0, -3.0, 0.0])
        } else if x <= 0.5 {
            (Bc::Fixed, [0.0; 3])
        } else {
            (Bc::Free, [1.0, 0.0, 0.0])
        };
        assert_eq!((p.bc[i], p.vel[i]), (bc, v), "particle at ({x}, {y})");
    }
}

// ---------------------------------------------------------------------------------------------- overrides

#[test]
fn overrides_take_effect() {
    let scene = load(
        "rings.toml",
        &[
            "time.end=1e-4",
            "body.1.velocity=[-200.0, 0.0]",
            "stabilisation.xsph.enabled=false",
            "precision=f32",
            "output.every=2e-6",
        ],
    );
    assert_eq!(scene.time.end, 1e-4);
    assert_eq!(scene.output.every, 2e-6);
    assert_eq!(scene.bodies[1].velocity, [-200.0, 0.0, 0.0]);
    assert!(scene.stabilisation.xsph.is_none());
    assert!(scene.stabilisation.artificial_stress.is_some());
    assert_eq!(scene.precision, Precision::F32);
    let p = scene.generate().unwrap();
    assert!(p.vel.iter().zip(&p.body).all(|(v, &b)| v[0] == if b == 0 { 180.0 } else { -200.0 }));

    // The default output cadence follows an overridden end time; a missing table is created.
    let scene = load("rings.toml", &["time.end=1e-4", "stabilisation.artificial_stress.enabled=false", "time.dt=1e-7"]);
    assert_eq!(scene.output.every, 1e-4 / 50.0);
    assert!(scene.stabilisation.artificial_stress.is_none());
    assert_eq!(scene.time.dt, Some(1e-7));
    let scene = load("disk-rotation.toml", &["stabilisation.xsph.epsilon=0.25"]);
    assert_eq!(scene.stabilisation.xsph.as_ref().map(|x| x.epsilon), Some(0.25));
    assert_eq!(load("rings.toml", &["precision=\"mixed\""]).precision, Precision::Mixed);
}

#[test]
fn bad_overrides_are_refused() {
    let text = rings_text();
    let msg = refused(&text, &["body.5.velocity=[1.0, 0.0]"]);
    assert_has(&msg, &["--set body.5.velocity=[1.0, 0.0]", "index 5 out of range", "'body' has 2 entries"]);
    let msg = refused(&text, &["time..end=1"]);
    assert_has(&msg, &["--set time..end=1", "bad key 'time..end'"]);
    let msg = refused(&text, &["time.end"]);
    assert_has(&msg, &["--set time.end", "expected key=value"]);
    let msg = refused(&text, &["time.ned=1"]);
    assert_has(&msg, &["--set time.ned=1: unknown key 'time.ned' (expected one of: end, cfl, dt, max_steps)"]);
    let msg = refused(&text, &["time.end.x=1"]);
    assert_has(&msg, &["--set time.end.x=1", "'time.end' is a float, not a table"]);
    let msg = refused(&text, &["time.end=-1"]);
    assert_eq!(msg, "--set time.end=-1: time.end: expected a positive time in seconds");
    let msg = refused(&text, &["body.0.velocity=[1.0]"]);
    assert_has(&msg, &["--set body.0.velocity=[1.0]: body.0.velocity: expected a velocity [x, y] in m/s"]);
    let msg = refused(&text, &["stabilisation.xsph.enabled=maybe"]);
    assert_has(&msg, &["--set stabilisation.xsph.enabled=maybe: stabilisation.xsph.enabled: expected true or false"]);
    let msg = refused(&text, &["precision=\"f16\""]);
    assert_has(&msg, &["--set precision=\"f16\"", "expected \"f32\", \"f64\" or \"mixed\""]);
}

// ---------------------------------------------------------------------------------------------- bad input

#[test]
fn unknown_key_is_refused_with_its_line() {
    let text = rings_with("[material]", "[materail]");
    let line = line_of(&text, "[materail]");
    let msg = refused(&text, &[]);
    assert_eq!(
        msg,
        format!(
            "cases/rings.toml:{line}: unknown key 'materail' (expected one of: name, dim, precision, discretisation, \
             material, body, boundary, stabilisation, time, output, physics, tool, experiment, analysis, model, \
             damage, blanking, method, cohesive)"
        )
    );
    let text = rings_with("h_over_dx = 1.7", "h_over_dx = 1.7\nkernel = \"wendland\"");
    let msg = refused(&text, &[]);
    let line = line_of(&text, "kernel =");
    assert_has(&msg, &[&format!("cases/rings.toml:{line}: unknown key 'discretisation.kernel'"), "dx, h_over_dx"]);
    let text = rings_with("xsph = { epsilon = 0.5 }", "xsph = { epsilon = 0.5, epsilom = 1 }");
    let msg = refused(&text, &[]);
    assert_has(&msg, &["unknown key 'stabilisation.xsph.epsilom' (expected one of: epsilon, pic, enabled)"]);
}

#[test]
fn wrong_type_is_refused() {
    let text = rings_with("dim = 2", "dim = \"two\"");
    let msg = refused(&text, &[]);
    assert_eq!(
        msg,
        format!("cases/rings.toml:{}: dim = \"two\": expected 2 (plane strain) or 3", line_of(&text, "dim ="))
    );
    let text = rings_with("density = 1.0 ", "density = \"heavy\" ");
    let msg = refused(&text, &[]);
    assert_has(&msg, &["cases/rings.toml:", "material.density = \"heavy\": expected a positive density in kg/m^3"]);
    let text = rings_with("name = \"rings\"", "name = 5");
    let line = line_of(&text, "name = 5");
    assert_eq!(
        refused(&text, &[]),
        format!(
            "cases/rings.toml:{line}: name = 5: expected a non-empty string naming the scene, a plain file name for \
             its run folder (no '/' or '\\', not '.' or '..')"
        )
    );
    let msg = refused(&rings_text(), &["body=5"]);
    assert_eq!(msg, "--set body=5: body: expected one or more [[body]] tables");
    let text = rings_with("exponent = 4", "exponent = 4.0");
    assert_has(&refused(&text, &[]), &["stabilisation.artificial_stress.exponent = 4.0: expected an integer >= 1"]);
}

#[test]
fn poisson_ratio_out_of_range_is_refused() {
    for nu in ["0.5", "-1.0", "0.7", "nan"] {
        let text = rings_with("poisson_ratio = 0.4", &format!("poisson_ratio = {nu}"));
        let line = line_of(&text, "poisson_ratio =");
        assert_eq!(
            refused(&text, &[]),
            format!("cases/rings.toml:{line}: material.poisson_ratio = {nu}: expected a value in (-1, 0.5)")
        );
    }
}

#[test]
fn non_positive_moduli_density_spacing_and_times_are_refused() {
    let cases = [
        (
            "youngs_modulus = 1.0e7",
            "youngs_modulus = -1.0e7",
            "material.youngs_modulus = -10000000.0",
            "a positive Young's modulus in Pa",
        ),
        ("density = 1.0 ", "density = 0.0 ", "material.density = 0.0", "a positive density in kg/m^3"),
        ("dx = 1.0126582278481013e-3", "dx = 0.0", "discretisation.dx = 0.0", "a positive lattice spacing in m"),
        ("dx = 1.0126582278481013e-3", "dx = -1e-3", "discretisation.dx = -0.001", "a positive lattice spacing in m"),
        ("end = 5.882352941176471e-4", "end = 0.0", "time.end = 0.0", "a positive time in seconds"),
        ("end = 5.882352941176471e-4", "end = -1", "time.end = -1", "a positive time in seconds"),
        ("h_over_dx = 1.7", "h_over_dx = 0.5", "discretisation.h_over_dx = 0.5", "a ratio h/dx in [1, 3]"),
        (
            "h_over_dx = 1.7",
            "verlet_offsets = 24\nh_over_dx = 1.7",
            "discretisation.verlet_offsets = 24",
            "16 or 32 (bits per Verlet-list offset)",
        ),
        ("cfl = 0.5", "cfl = 1.5", "time.cfl = 1.5", "a CFL number in (0, 1]"),
        ("epsilon = 0.5 }", "epsilon = 1.5 }", "stabilisation.xsph.epsilon = 1.5", "a value in [0, 1]"),
        ("exponent = 4", "exponent = 0", "stabilisation.artificial_stress.exponent = 0", "an integer >= 1"),
    ];
    for (from, to, key, expected) in cases {
        let text = rings_with(from, to);
        let line = line_of(&text, to);
        let msg = refused(&text, &[]);
        assert_has(&msg, &[&format!("cases/rings.toml:{line}: {key}: expected {expected}")]);
    }
}

#[test]
fn lattice_too_fine_is_refused_before_generation() {
    let msg = refused(&rings_text(), &["discretisation.dx=1e-7"]);
    assert_has(
        &msg,
        &["--set discretisation.dx=1e-7: discretisation.dx: expected a lattice spacing giving at most 2^31 - 1"],
    );
}

#[test]
fn dim_4_is_refused() {
    let text = rings_with("dim = 2", "dim = 4");
    let line = line_of(&text, "dim = 4");
    assert_eq!(refused(&text, &[]), format!("cases/rings.toml:{line}: dim = 4: expected 2 (plane strain) or 3"));
}

#[test]
fn missing_required_keys_are_refused() {
    let text = rings_with("end = 5.882352941176471e-4\n", "");
    let line = line_of(&text, "[time]");
    assert_eq!(
        refused(&text, &[]),
        format!("cases/rings.toml:{line}: time.end: missing; expected a positive time in seconds")
    );
    let text = rings_with("name = \"rings\"\n", "");
    assert_has(&refused(&text, &[]), &["cases/rings.toml: name: missing; expected a non-empty string"]);
    let text = rings_with("outer_radius = 0.04\nvelocity = [-180.0", "velocity = [-180.0");
    assert_has(&refused(&text, &[]), &["body.1.outer_radius: missing; expected a positive radius in m"]);
}

#[test]
fn vector_of_wrong_length_is_refused() {
    let text = rings_with("velocity = [180.0, 0.0]", "velocity = [180.0, 0.0, 0.0]");
    let line = line_of(&text, "velocity = [180.0, 0.0, 0.0]");
    assert_eq!(
        refused(&text, &[]),
        format!("cases/rings.toml:{line}: body.0.velocity = [180.0, 0.0, 0.0]: expected a velocity [x, y] in m/s")
    );
    let text = rings_with("center = [0.041, 0.0]", "center = [0.041]");
    assert_has(&refused(&text, &[]), &["body.1.center = [0.041]: expected a point [x, y] in m"]);
}

#[test]
fn shape_parameter_of_another_shape_is_refused() {
    let text =
        rings_with("outer_radius = 0.04\nvelocity = [180.0", "outer_radius = 0.04\nradius = 0.04\nvelocity = [180.0");
    let line = line_of(&text, "radius = 0.04\nvelocity");
    assert_eq!(
        refused(&text, &[]),
        format!(
            "cases/rings.toml:{line}: unknown key 'body.0.radius' for shape 'ring' (expected one of: name, shape, \
             velocity, angular_velocity, lattice, material, temperature, center, inner_radius, outer_radius)"
        )
    );
    // A 3D shape in a 2D scene.
    let text = rings_with("shape = \"ring\"\ncenter = [0.041", "shape = \"spherical_shell\"\ncenter = [0.041");
    assert_has(
        &refused(&text, &[]),
        &["body.1.shape = \"spherical_shell\": expected one of \"rectangle\", \"disk\", \"ring\" (dim = 2)"],
    );
    // inner >= outer
    let text = rings_with(
        "inner_radius = 0.03\nouter_radius = 0.04\nvelocity = [-180",
        "inner_radius = 0.05\nouter_radius = 0.04\nvelocity = [-180",
    );
    assert_has(&refused(&text, &[]), &["body.1.inner_radius = 0.05: expected a radius in m, >= 0 and < outer_radius"]);
}

const BOUNDARY: &str = "\n[[boundary]]\nkind = \"fixed\"\nmin = [-0.1, -0.1]\nmax = [-0.07, 0.1]\n";

#[test]
fn velocity_on_a_fixed_boundary_is_refused() {
    let text = rings_text() + BOUNDARY + "velocity = [0.0, 0.0]\n";
    let line = line_of(&text, "velocity = [0.0, 0.0]");
    assert_eq!(
        refused(&text, &[]),
        format!(
            "cases/rings.toml:{line}: boundary.0.velocity = [0.0, 0.0]: expected no velocity for kind = \"fixed\" \
             (remove it, or use kind = \"velocity\")"
        )
    );
    let text = rings_text() + &BOUNDARY.replace("\"fixed\"", "\"velocity\"");
    assert_has(
        &refused(&text, &[]),
        &["boundary.0.velocity: missing; expected a velocity [x, y] in m/s for kind = \"velocity\""],
    );
    // The same boundary without the velocity is accepted and fixes the left edge of the left ring.
    let p = Scene::from_str(&(rings_text() + BOUNDARY), "cases/rings.toml", &[]).unwrap().generate().unwrap();
    let fixed = p.bc.iter().filter(|&&b| b == Bc::Fixed).count();
    assert!(fixed > 0 && p.pos.iter().zip(&p.bc).all(|(x, &b)| (b == Bc::Fixed) == (x[0] <= -0.07)));
}

#[test]
fn boundary_naming_an_unknown_body_is_refused() {
    let text = rings_text() + BOUNDARY + "body = \"middle\"\n";
    let line = line_of(&text, "body = \"middle\"");
    assert_eq!(
        refused(&text, &[]),
        format!(
            "cases/rings.toml:{line}: boundary.0.body = \"middle\": expected the name of a body (one of: 'left', 'right')"
        )
    );
    // A region that selects nothing is refused at generation.
    let text = rings_text() + &BOUNDARY.replace("max = [-0.07, 0.1]", "max = [-0.09, 0.1]");
    assert_has(&refused(&text, &[]), &["cases/rings.toml: boundary.0 (kind = \"fixed\") selects no particle"]);
}

#[test]
fn overlapping_bodies_are_refused() {
    let msg = refused(&rings_text(), &["body.1.center=[0.03, 0.0]"]);
    assert_has(&msg, &["cases/rings.toml: bodies 'left' and 'right' overlap", "closer than 0.5·dx"]);
    // Bounding boxes that overlap without particles that do: a disk inside the hole of the left ring.
    let core = "\n[[body]]\nname = \"core\"\nshape = \"disk\"\ncenter = [-0.041, 0.0]\nradius = 0.02\n";
    let p = Scene::from_str(&(rings_text() + core), "cases/rings.toml", &[]).unwrap().generate().unwrap();
    assert!(p.len() > 4232);
    let msg = refused(&(rings_text() + &core.replace("0.02", "0.035")), &[]);
    assert_has(&msg, &["bodies 'left' and 'core' overlap"]);
}

#[test]
fn body_too_small_for_dx_is_refused() {
    let text = rings_text() + "\n[[body]]\nname = \"speck\"\nshape = \"disk\"\ncenter = [0.0, 0.2]\nradius = 1e-4\n";
    assert_eq!(
        refused(&text, &[]),
        "cases/rings.toml: body 'speck' (body.2) contains no lattice point: dx = 0.0010126582278481013 m is too \
         coarse for it"
    );
}

#[test]
fn syntax_and_read_errors_name_the_file() {
    let text = rings_with("dim = 2", "dim = ");
    let line = line_of(&text, "dim = ");
    assert_has(&refused(&text, &[]), &[&format!("cases/rings.toml:{line}: invalid TOML")]);
    let err = Scene::load(case("no-such-scene.toml"), &[]).unwrap_err();
    assert!(matches!(err, SceneError::Read { .. }));
    assert_has(&err.to_string(), &["no-such-scene.toml: cannot read the scene file:"]);
}

// The units of scene values (host/scene/units.rs).
use swarf::scene::units::{Quantity, quantity};

/// The conversions the module's documentation names, and the refusals.
#[test]
fn conversions() {
    let close = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() <= 1e-12 * b.abs().max(1.0));
    assert!(close(Quantity::Speed.parse("381.3 m/min"), 6.355));
    assert!(close(Quantity::Length.parse("33 um"), 33e-6));
    assert!(close(Quantity::Length.parse("33µm"), 33e-6));
    assert!(close(Quantity::Length.parse("0.1 mm"), 1e-4));
    assert!(close(Quantity::Angle.parse("10 deg"), 10.0));
    assert!(close(Quantity::Angle.parse("-0.5 rad"), -0.5 * 180.0 / std::f64::consts::PI));
    assert!(close(Quantity::Temperature.parse("25 C"), 298.15));
    assert!(close(Quantity::Temperature.parse("-5 °C"), 268.15));
    assert!(close(Quantity::Length.parse("1e-3 m"), 1e-3));
    for bad in ["33", "33 uM", "m", "nan m", "inf m", "1e400 m", "33 um um", ""] {
        assert_eq!(Quantity::Length.parse(bad), None, "{bad:?}");
    }
    assert_eq!(quantity("body.12.velocity"), Some(Quantity::Speed));
    assert_eq!(quantity("tool.thermal.temperature"), Some(Quantity::Temperature));
    assert_eq!(quantity("time.end"), None);
}
