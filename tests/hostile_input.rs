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
        assert!(Scene::from_str(&text, "cases/rings.toml", &[set.clone()]).is_err(), "--set {set} accepted");
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
