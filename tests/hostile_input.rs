//! Input a new or hostile user gives (issue 27's list): each case failed before its fix. A scene's name becomes
//! its run folder `runs/<name>`, so it must be one plain file name; `swarf material --at` takes finite numbers only.

use std::process::Command;
use swarf::scene::Scene;

fn rings_text() -> String {
    std::fs::read_to_string("cases/rings.toml").expect("cases/rings.toml")
}

/// A name with a separator, `..` or an absolute path is refused, from the file and from `--set`, naming the key
/// and what is expected; a plain name passes.
#[test]
fn scene_names_must_be_plain_file_names() {
    let text = rings_text();
    let named = |n: &str| text.replacen("name = \"rings\"", &format!("name = {n:?}"), 1);
    assert!(named("x").contains("name = \"x\""), "cases/rings.toml names its scene \"rings\"");
    for bad in ["../../x", "/an/absolute/path", "a/b", "..", ".", "a\\b", " "] {
        let err =
            Scene::from_str(&named(bad), "cases/rings.toml", &[]).err().unwrap_or_else(|| panic!("{bad:?} accepted"));
        let msg = err.to_string();
        assert!(msg.contains("name") && msg.contains("plain file name"), "{bad:?}: {msg}");
        let set = format!("name={bad:?}");
        assert!(
            Scene::from_str(&text, "cases/rings.toml", std::slice::from_ref(&set)).is_err(),
            "--set {set} accepted"
        );
    }
    for good in ["rings-2", "v0060_f32", "a.b"] {
        let s = Scene::from_str(&named(good), "cases/rings.toml", &[]).unwrap_or_else(|e| panic!("{good}: {e}"));
        assert_eq!(s.name, good);
    }
}

/// `swarf material NAME --at nan,nan,nan` (or inf) exits with status 2 and says what it expects.
#[test]
fn material_points_must_be_finite() {
    for at in ["nan,nan,nan", "0.1,inf,300", "0.1,1e3,-inf", "0.1,1e3,nan"] {
        let out = Command::new(env!("CARGO_BIN_EXE_swarf"))
            .args(["material", "Ti6Al4V-Roethlin", "--at", at])
            .output()
            .expect("swarf runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "--at {at}: {err}");
        assert!(err.contains("finite"), "--at {at}: {err}");
    }
    let ok = Command::new(env!("CARGO_BIN_EXE_swarf"))
        .args(["material", "Ti6Al4V-Roethlin", "--at", "0.1,1e3,300"])
        .output()
        .expect("swarf runs");
    assert!(ok.status.success());
}

/// A symbolic link planted at the temporary name (`.<name>.tmp-<pid>`) is not followed: the write fails, naming
/// the link, the file it points at is untouched, and the link stays. A plain file left there (a killed run with
/// the same process id) is replaced.
#[cfg(unix)]
#[test]
fn atomic_writes_do_not_follow_a_planted_link() {
    use swarf::output::write_atomic;
    let dir = std::env::temp_dir().join(format!("swarf-test-link-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, b"precious").unwrap();
    let dest = dir.join("energy.csv");
    let tmp = dir.join(format!(".energy.csv.tmp-{}", std::process::id()));
    std::os::unix::fs::symlink(&victim, &tmp).unwrap();
    let err = write_atomic(&dest, b"new data").expect_err("a planted link must stop the write");
    assert!(err.to_string().contains("symbolic link"), "{err}");
    assert_eq!(std::fs::read(&victim).unwrap(), b"precious");
    assert!(!dest.exists());
    assert!(std::fs::symlink_metadata(&tmp).unwrap().file_type().is_symlink());
    std::fs::remove_file(&tmp).unwrap();
    std::fs::write(&tmp, b"stale").unwrap();
    write_atomic(&dest, b"new data").expect("a stale plain temporary is replaced");
    assert_eq!(std::fs::read(&dest).unwrap(), b"new data");
    assert!(!tmp.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The progress line says `ETA -` until the time left can be estimated (it printed `ETA NaN s`); in a log (not a
/// terminal) it prints plain lines, one per tenth of the run, with no carriage return.
#[test]
fn progress_lines_have_no_nan_and_no_carriage_returns_in_logs() {
    use swarf::output::progress::{Progress, progress_line};
    let first = progress_line(0.0, 0.0, 0.0, 5640.0, None);
    assert!(first.contains("ETA -") && !first.contains("NaN"), "{first}");
    assert!(progress_line(0.5, 1e-4, 1e4, 5640.0, Some(12.4)).contains("ETA 12 s"));
    let mut log = Progress::new(false);
    let printed: Vec<String> =
        (0..=200).filter_map(|k| log.update(k as f64 / 200.0, k as f64 * 1e-6, 1e4, 5640.0, Some(1.0))).collect();
    assert_eq!(printed.len(), 11, "one line at 0 %, 10 %, …, 100 %");
    assert!(printed.iter().all(|l| !l.contains('\r') && l.ends_with('\n')));
    let mut tty = Progress::new(true);
    let t = tty.update(0.3, 1e-6, 1e4, 5640.0, None).expect("a terminal line every output step");
    assert!(t.starts_with('\r') && !t.ends_with('\n'));
}

/// A run that needs more host memory than is available is refused on the CPU before anything is allocated (a
/// 1e8-particle request aborted with an allocation failure), naming the bytes; one that fits passes.
#[test]
fn cpu_runs_that_cannot_fit_host_memory_are_refused_first() {
    use swarf::backend::DeviceInfo;
    let Some((free, total)) = swarf::check::host_memory() else { return };
    assert!(free > 0 && free <= total);
    let cpu = DeviceInfo { backend: "cpu", ..Default::default() };
    let err = swarf::check::fits(total.saturating_mul(4), &cpu).expect_err("four times the host's memory");
    assert!(err.to_string().contains("host memory"), "{err}");
    swarf::check::fits(1 << 20, &cpu).expect("a megabyte fits");
}
