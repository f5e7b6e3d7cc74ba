//! Run folders and checkpoints a run can trust (issue 27, defects #2, #3, #4, #6, #9): `swarf run --resume`
//! checks the checkpoint (checksums, header values, ids, positions) and that the scene, materials and version are
//! the run's, before any work; a new run refuses a non-empty folder unless `--force`. Each test says what the code
//! did before its fix.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;
use std::time::{Duration, Instant};
use swarf::checkpoint::{self, Header};

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("swarf-test-safety-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs swarf with `args`, killed (and the test failed) if it has not ended within a minute: a hang fails.
fn swarf(args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_swarf"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("swarf starts");
    let start = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("swarf {args:?} did not end within 60 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn path(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 temporary path")
}

/// A short rings run (about 150 steps) with a checkpoint half way, made once; each test works on a copy.
fn base() -> &'static Path {
    static BASE: OnceLock<PathBuf> = OnceLock::new();
    BASE.get_or_init(|| {
        let d = tmp("base");
        let o = swarf(&[
            "--backend",
            "cpu",
            "run",
            "cases/rings.toml",
            "--quiet",
            "--set",
            "time.end=3e-5",
            "--checkpoint-every",
            "1.5e-5",
            "--out",
            path(&d),
        ]);
        assert!(o.status.success(), "the base run: {}", stderr(&o));
        assert!(d.join("checkpoint.bin").is_file());
        d
    })
}

/// A copy of the base run folder.
fn copy(tag: &str) -> PathBuf {
    let d = tmp(tag);
    std::fs::create_dir_all(&d).unwrap();
    for e in std::fs::read_dir(base()).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, d.join(p.file_name().unwrap())).unwrap();
    }
    d
}

/// Resumes `dir` (with `extra` arguments): must fail with status 1, no panic, and a message holding each of
/// `expect`. Returns the message.
fn refused(dir: &Path, extra: &[&str], expect: &[&str]) -> String {
    let mut args = vec!["--backend", "cpu", "run", "--quiet", "--resume", path(dir)];
    args.extend_from_slice(extra);
    let o = swarf(&args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "resume of {} must be refused: {err}", dir.display());
    assert!(!err.contains("panicked"), "{err}");
    for e in expect {
        assert!(err.contains(e), "expected {e:?} in: {err}");
    }
    err
}

/// Rewrites the checkpoint of `dir` with `edit` applied to its header and buffers (checksums recomputed, so that
/// the values themselves are what is checked).
fn edit(dir: &Path, edit: impl FnOnce(&mut Header, &mut swarf::solver::StateBlobs)) {
    let p = dir.join("checkpoint.bin");
    let (mut h, mut state) = checkpoint::read(&p).expect("the checkpoint reads");
    edit(&mut h, &mut state);
    checkpoint::write(&p, h, &state).expect("written");
}

fn blob<'a>(state: &'a mut swarf::solver::StateBlobs, name: &str) -> &'a mut Vec<u8> {
    &mut state.iter_mut().find(|(n, _)| n == name).expect("the field").1
}

/// A particle id out of range: before, the resumed run panicked in the output thread (`index out of bounds` in
/// host/run.rs). Now refused, naming the field, the entry and the range.
#[test]
fn corrupted_particle_id_is_refused() {
    let d = copy("id");
    edit(&d, |_, s| blob(s, "id")[4..8].copy_from_slice(&4_000_000_000u32.to_le_bytes()));
    refused(&d, &[], &["field 'id'", "entry 1 is 4000000000", "expected each particle id 0 to 4231"]);
}

/// A flipped exponent bit in a position, written after the checkpoint: before, the run went on to its end with a
/// particle at 1e304 m. Now the checksum of the buffer differs, and the message says which and both values.
#[test]
fn flipped_exponent_bit_fails_the_checksum() {
    let d = copy("bitflip");
    let p = d.join("checkpoint.bin");
    let (h, _) = checkpoint::read(&p).unwrap();
    let mut bytes = std::fs::read(&p).unwrap();
    let header_len = u64::from_le_bytes(bytes[8..16].try_into().unwrap()) as usize;
    let before: usize = h.fields.iter().take_while(|(n, _)| n != "pos").map(|(_, n)| n).sum();
    // The top byte of the first position's x (little endian f64): bit 62, the exponent's highest bit.
    bytes[16 + header_len + before + 7] ^= 0x40;
    std::fs::write(&p, bytes).unwrap();
    refused(&d, &[], &["field 'pos': checksum", "expected 0x", "damaged or changed"]);
}

/// A non-finite position with checksums that fit (a checkpoint written from a broken state): refused.
#[test]
fn non_finite_position_is_refused() {
    let d = copy("nan");
    edit(&d, |_, s| blob(s, "pos")[..8].copy_from_slice(&f64::NAN.to_le_bytes()));
    refused(&d, &[], &["field 'pos': value 0 is not finite"]);
}

/// Header values a run cannot continue from: before, dt = 0, dt < 0 and time < 0 hung at 0 %, and a huge frame
/// number dropped a frame from the PVD. Each is refused, naming the value and what is expected.
#[test]
fn header_values_out_of_range_are_refused() {
    type Edit = fn(&mut Header);
    let cases: [(&str, Edit, &[&str]); 6] = [
        ("dt0", |h| h.dt = 0.0, &["header: dt = 0e0", "expected a finite value > 0"]),
        ("dtneg", |h| h.dt = -1e-7, &["header: dt = -1e-7"]),
        ("dttiny", |h| h.dt = 1e-30, &["header: dt = 1e-30 s", "1 % of the scene's"]),
        ("timeneg", |h| h.time = -1e-6, &["header: time = -1e-6", ">= 0"]),
        ("frame", |h| h.frame = 1_000_000_000_000, &["header: frame = 1000000000000", "expected 1 to"]),
        ("frame2", |h| h.frame += 2, &["frames of particles.pvd up to t"]),
    ];
    for (tag, f, expect) in cases {
        let d = copy(tag);
        edit(&d, |h, _| f(h));
        refused(&d, &[], expect);
        std::fs::remove_dir_all(&d).unwrap();
    }
}

/// An edited scene.toml in the run folder: before, taken (or ignored) without a word. Now refused with each
/// changed key, then and now; `--accept-changes` continues, and says what it accepted.
#[test]
fn edited_scene_is_refused_with_what_changed() {
    let d = copy("scene");
    let s = d.join("scene.toml");
    let text = std::fs::read_to_string(&s).unwrap();
    let edited = text.replace("cfl = 0.5", "cfl = 0.3").replace("poisson_ratio = 0.4", "poisson_ratio = 0.45");
    assert_ne!(edited, text, "cases/rings.toml sets cfl = 0.5 and poisson_ratio = 0.4");
    std::fs::write(&s, edited).unwrap();
    refused(
        &d,
        &[],
        &[
            "does not match the run it continues",
            "scene.toml: time.cfl: 0.5 then, 0.3 now",
            "scene.toml: material.poisson_ratio: 0.4 then, 0.45 now",
            "--accept-changes",
        ],
    );
    let o = swarf(&["--backend", "cpu", "run", "--quiet", "--resume", path(&d), "--accept-changes"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("resuming with a change (--accept-changes): scene.toml: time.cfl"));
}

/// A resumed run's summary.json counts the cell-list rebuilds of the whole run: before, only those after the
/// resume. The resumed run equals the uninterrupted one, rebuilds included.
#[test]
fn resumed_summary_counts_all_cell_list_rebuilds() {
    let whole = tmp("whole");
    let o = swarf(&[
        "--backend",
        "cpu",
        "run",
        "cases/rings.toml",
        "--quiet",
        "--set",
        "time.end=3e-5",
        "--out",
        path(&whole),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let d = copy("rebuilds");
    let o = swarf(&["--backend", "cpu", "run", "--quiet", "--resume", path(&d)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rebuilds = |dir: &Path| {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
        v["cell_list_rebuilds"].as_u64().expect("cell_list_rebuilds")
    };
    let (h, _) = checkpoint::read(&d.join("checkpoint.bin")).unwrap();
    assert!(h.rebuilds > 0, "the checkpoint records the rebuilds before it");
    assert_eq!(rebuilds(&d), rebuilds(&whole));
}

/// A new run into a non-empty run folder: before, it was overwritten without a word, and stale frames stayed. Now
/// refused, naming the folder; `--force` clears it first; a folder that holds no swarf run is never cleared.
#[test]
fn non_empty_run_folder_is_refused_unless_forced() {
    let d = copy("force");
    std::fs::write(d.join("frame_09999.vtu"), b"stale").unwrap();
    let args = |extra: &'static [&'static str]| -> Vec<String> {
        let mut a: Vec<String> = ["--backend", "cpu", "run", "cases/rings.toml", "--quiet", "--set", "time.end=2e-6"]
            .map(String::from)
            .to_vec();
        a.extend(["--out".to_string(), path(&d).to_string()]);
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run = |extra| {
        let a = args(extra);
        swarf(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let o = run(&[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains(path(&d)) && err.contains("not empty") && err.contains("--force"), "{err}");
    assert!(err.contains("--resume"), "a folder with a checkpoint suggests resuming it: {err}");
    let o = run(&["--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!d.join("frame_09999.vtu").exists() && !d.join("checkpoint.bin").exists(), "the old run is cleared");
    assert!(d.join("summary.json").is_file());

    let other = tmp("notarun");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::write(other.join("thesis.tex"), b"precious").unwrap();
    let o = swarf(&["--backend", "cpu", "run", "cases/rings.toml", "--quiet", "--force", "--out", path(&other)]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("not a swarf run folder"), "{err}");
    assert_eq!(std::fs::read(other.join("thesis.tex")).unwrap(), b"precious");
}

/// A velocity of 1e300 m/s and `time.dt = 1e-30`: before, `check` said "ok" with 18446744073709551615 steps and
/// `run` hung at 0 %. Both now refuse before any work, naming Δt, where it comes from, and `time.max_steps`.
#[test]
fn runs_that_never_end_are_refused_first() {
    let cases: [(&str, &[&str]); 2] = [
        ("body.0.velocity=[1e300,0.0]", &["the CFL condition", "e300 m/s", "time.max_steps = 1e9"]),
        ("time.dt=1e-30", &["dt = 1e-30 s (time.dt)", "time.max_steps = 1e9"]),
    ];
    for (set, expect) in cases {
        let out = tmp("never");
        for cmd in ["check", "run"] {
            let mut args = vec!["--backend", "cpu", cmd, "cases/rings.toml", "--set", set];
            if cmd == "run" {
                args.extend(["--quiet", "--out", path(&out)]);
            }
            let o = swarf(&args);
            let err = stderr(&o);
            assert_eq!(o.status.code(), Some(1), "{cmd} --set {set}: {err}");
            for e in expect {
                assert!(err.contains(e), "{cmd} --set {set}: expected {e:?} in: {err}");
            }
        }
        assert!(!out.exists(), "refused before the run folder is made");
    }
    // The limit is the scene's: raised, the same scene checks.
    let o =
        swarf(&["--backend", "cpu", "check", "cases/rings.toml", "--set", "time.dt=1e-12", "--set", "time.end=1e-9"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `output.every` below Δt: before, `check` said 11 steps (end/Δt) and the run took 200, each step cut short
/// to the output interval, without a word. Now `check` reports the steps the run takes, and both warn.
#[test]
fn output_every_below_dt_is_reported_truthfully() {
    let set = ["--set", "time.end=2e-6", "--set", "output.every=1e-8"];
    let o = swarf(&[&["--backend", "cpu", "check", "cases/rings.toml"][..], &set].concat());
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "{}", stderr(&o));
    let line = text.lines().find(|l| l.starts_with("steps:")).expect("a steps line");
    let checked: u64 = line.split_whitespace().nth(1).and_then(|n| n.parse().ok()).expect("a step count");
    assert!(text.contains("warning:") && text.contains("output.every = 1e-8 s is below dt"), "{text}");
    let out = tmp("every");
    let o = swarf(&[&["--backend", "cpu", "run", "cases/rings.toml", "--out", path(&out)][..], &set].concat());
    assert!(o.status.success() && stderr(&o).contains("is below dt"), "{}", stderr(&o));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["steps"].as_u64(), Some(checked), "check's step count is the run's");
}

/// Ctrl-C and SIGTERM in the middle of a long stretch without frames (about 3000 steps between two): before,
/// the signal was looked at only between batches of up to 4096 steps (Ctrl-C took 15 s, here the run went on to
/// its end and exited 0), and SIGTERM killed the run with no checkpoint. Now each writes a checkpoint that
/// validates and stops with exit code 130, well before the run would have ended.
#[cfg(unix)]
#[test]
fn signals_checkpoint_and_stop_within_a_batch() {
    for sig in ["-INT", "-TERM"] {
        let d = tmp(&format!("signal{sig}"));
        let mut child = Command::new(env!("CARGO_BIN_EXE_swarf"))
            .args(["--backend", "cpu", "run", "cases/rings.toml", "--quiet", "--set", "output.every=5.8e-4", "--out"])
            .arg(&d)
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("swarf starts");
        // Stepping: the first frame is written.
        let start = Instant::now();
        while !d.join("frame_00000.vtu").exists() && start.elapsed() < Duration::from_secs(30) {
            std::thread::sleep(Duration::from_millis(50));
        }
        std::thread::sleep(Duration::from_millis(1000));
        let sent = Instant::now();
        assert!(Command::new("kill").args([sig, &child.id().to_string()]).status().unwrap().success());
        let code = loop {
            if let Some(st) = child.try_wait().unwrap() {
                break st.code();
            }
            if sent.elapsed() > Duration::from_secs(10) {
                let _ = child.kill();
                panic!("{sig}: still running 10 s after the signal");
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        assert_eq!(code, Some(130), "{sig}: exit code");
        let (h, state) = checkpoint::read(&d.join("checkpoint.bin")).expect("a checkpoint");
        checkpoint::validate(&h, &state).expect("a valid checkpoint");
        assert!(h.frame == 1 && h.steps > 0, "{sig}: written between the first two frames, at step {}", h.steps);
        let log = std::fs::read_to_string(d.join("run.log")).unwrap();
        assert!(log.contains("interrupted at"), "{log}");
    }
}

/// A run whose frames are sparse still gets checkpoints, on the wall-time cadence (`--checkpoint-minutes`), and
/// says so in run.log: before, checkpoints were written only at output steps, so with sparse frames none was,
/// and nobody was told.
#[test]
fn sparse_frames_still_get_wall_time_checkpoints() {
    let d = tmp("wall");
    let o = swarf(&[
        "--backend",
        "cpu",
        "run",
        "cases/rings.toml",
        "--quiet",
        "--set",
        "time.end=1.5e-4",
        "--set",
        "output.every=1.5e-4",
        "--checkpoint-minutes",
        "0.002",
        "--out",
        path(&d),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let log = std::fs::read_to_string(d.join("run.log")).unwrap();
    assert!(log.contains("; checkpoints every 0.12 s of wall time and on Ctrl-C or SIGTERM"), "{log}");
    assert!(log.contains("s of wall time since the last)"), "{log}");
    let (h, state) = checkpoint::read(&d.join("checkpoint.bin")).expect("a checkpoint");
    checkpoint::validate(&h, &state).expect("a valid checkpoint");
    assert_eq!(h.frame, 1, "written between the only two frames");
}

/// `[tool]` in a 3D scene: before issue 24, `tool.rake_angle: missing` although it was present, then a refusal
/// naming the table and the dimension. Now the parametric tool in 3D is the prism of its outline along z (docs/3d.md):
/// the scene loads with the tool where the file puts it (z = 0), and what the prism cannot do is refused, naming
/// the key: a rotation about an axis not along z.
#[test]
fn tool_in_a_3d_scene_is_the_prism_of_its_outline() {
    let taylor = std::fs::read_to_string("cases/taylor-bar.toml").unwrap();
    let v0060 = std::fs::read_to_string("cases/cutting/v0060.toml").unwrap();
    let tool = &v0060[v0060.find("[tool]").unwrap()..v0060.find("friction = 0.35").unwrap()];
    let text = format!("{taylor}\n{tool}");
    let scene = swarf::scene::Scene::from_str(&text, "t3.toml", &[]).expect("the prism in 3D");
    let t = scene.tool.as_ref().expect("a tool");
    assert_eq!((t.position[0], t.position[2], t.rake_angle), (-3.6e-5, 0.0, 0.0));
    let turned = format!("{text}rotation = {{ axis = [1.0, 0.0, 0.0], centre = [0.0, 0.0, 0.0], rpm = 10.0 }}\n");
    let err = swarf::scene::Scene::from_str(&turned, "t3.toml", &[]).expect_err("a turn about x").to_string();
    assert!(err.contains("tool.rotation.axis") && err.contains("an axis along z"), "{err}");
}

/// `--set boundary.0.kind=...` in a scene without boundaries: before, `boundary: expected [[boundary]] tables`,
/// about a table the override itself had made. Now the index and the missing entries are named.
#[test]
fn set_into_a_missing_array_names_it() {
    let set = ["boundary.0.kind=\"fixed\"".to_string()];
    let err = swarf::scene::Scene::load("cases/rings.toml", &set).expect_err("no boundaries").to_string();
    assert!(
        err.contains("--set boundary.0.kind=\"fixed\": index 0 out of range: the scene has no [[boundary]]"),
        "{err}"
    );
}

/// A body too large for the lattice, in the file or by `--set`: before, blamed on `discretisation.dx` (line 13).
/// Now the largest body is named at its own line, with its lattice points; dx is offered as the other fix.
#[test]
fn too_large_body_is_named() {
    let text =
        std::fs::read_to_string("cases/rings.toml").unwrap().replacen("outer_radius = 0.04", "outer_radius = 1e3", 1);
    let err = swarf::scene::Scene::from_str(&text, "cases/rings.toml", &[]).expect_err("too large").to_string();
    assert!(err.starts_with("cases/rings.toml:23: body.0 = 'left', 3.9"), "{err}");
    assert!(err.contains("a smaller body or a larger discretisation.dx"), "{err}");
    let set = ["body.1.outer_radius=1e3".to_string()];
    let err = swarf::scene::Scene::load("cases/rings.toml", &set).expect_err("too large").to_string();
    assert!(err.starts_with("cases/rings.toml:31: body.1 = 'right', 3.9"), "{err}");
}

/// `swarf material --plot` into a missing folder: before, a raw `ImageError(IoError(Os { .. }))`. Now the folder
/// is named.
#[test]
fn plot_into_a_missing_folder_names_it() {
    let dir = tmp("noplot").join("sub");
    let png = dir.join("ti.png");
    let o = swarf(&["material", "Ti6Al4V-Roethlin", "--plot", path(&png)]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains(&format!("the folder {} does not exist", dir.display())), "{err}");
    assert!(!err.contains("ImageError"), "{err}");
}

/// An empty `materials/` beside the scene: before, it hid the library, and the error said `one of ` and an empty
/// list. Now the library is a search path (`material::search`: the folder beside the scene, its parent's, the
/// built-in library, each name from the first that has it), so the empty folder hides nothing: the scene loads,
/// and an unknown name is refused naming every place searched and the names found.
#[test]
fn empty_local_material_folder_hides_nothing_and_errors_say_where_they_looked() {
    let d = tmp("emptylib");
    std::fs::create_dir_all(d.join("materials")).unwrap();
    let scene = d.join("v0060.toml");
    std::fs::copy("cases/cutting/v0060.toml", &scene).unwrap();
    let s = swarf::scene::Scene::load(&scene, &[]).expect("the built-in library behind an empty folder");
    assert_eq!(s.material.library.as_ref().map(|m| m.name.as_str()), Some("Ti6Al4V-V0060-DE-mu035"));
    let err = swarf::scene::Scene::load(&scene, &["material.name=\"No-Such-Material\"".to_string()])
        .expect_err("an unknown material")
        .to_string();
    assert!(err.contains(&d.join("materials").display().to_string()) && err.contains("the built-in library"), "{err}");
    assert!(err.contains("Ti6Al4V-V0060-DE-mu035") && !err.trim_end().ends_with("one of"), "{err}");
}

/// An output file that cannot be written: before, its path was printed twice (`x/energy.csv: x/energy.csv: Is a
/// directory`). Now once.
#[test]
fn output_errors_name_the_path_once() {
    use swarf::backend::{AnyBackend, BackendChoice};
    let d = tmp("twice");
    std::fs::create_dir_all(d.join("energy.csv")).unwrap();
    let scene = swarf::scene::Scene::load("cases/rings.toml", &["time.end=2e-6".to_string()]).unwrap();
    let any = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    let err = swarf::run::run(&any, &scene, &swarf::run::RunOptions::quiet(d.clone())).expect_err("unwritable");
    let msg = err.to_string();
    let p = d.join("energy.csv").display().to_string();
    assert_eq!(msg.matches(&p).count(), 1, "{msg}");
}
