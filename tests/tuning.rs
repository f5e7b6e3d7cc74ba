//! The tuning switches (host/tuning.rs): read once, recorded in `summary.json`, printed by `swarf info`, and a
//! bad value refused with the variable and the accepted values named. Each case runs the `swarf` binary, whose
//! environment is its own.

use std::process::Command;

fn swarf() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_swarf"));
    // The switches of the test's own environment do not leak into the cases.
    for (k, _) in std::env::vars().filter(|(k, _)| k.starts_with("SWARF_") && k != "SWARF_TEST_BACKEND") {
        c.env_remove(k);
    }
    c
}

/// summary.json carries a `tuning` object with every switch: null / false where unset, the value where set.
#[test]
fn summary_records_the_tuning() {
    let out = std::env::temp_dir().join(format!("swarf-test-tuning-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let st = swarf()
        .env("SWARF_LANES", "2")
        .env("SWARF_PAIR_ORDER", "forward")
        .args(["--backend", "cpu", "run", "cases/block-translation.toml", "--quiet"])
        .args(["--set", "time.end=1e-6", "--out"])
        .arg(&out)
        .status()
        .expect("swarf runs");
    assert!(st.success());
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary.json"))
            .expect("summary.json parses");
    let t = summary["tuning"].as_object().expect("a tuning object");
    let keys = [
        "lanes",
        "no_graphs",
        "no_fuse",
        "no_fuse_prepare",
        "no_fuse_contact",
        "no_conditional",
        "maxnreg",
        "plastic_maxnreg",
        "pair_block",
        "plastic_block",
        "pair_order",
        "plastic_order",
        "ptx_target",
        "fast_math",
    ];
    assert_eq!(t.len(), keys.len());
    for k in keys {
        assert!(t.contains_key(k), "tuning.{k} missing");
    }
    assert_eq!(t["lanes"], 2);
    assert_eq!(t["pair_order"], "forward");
    assert_eq!(t["pair_block"], serde_json::Value::Null);
    assert_eq!(t["no_graphs"], false);
    let _ = std::fs::remove_dir_all(&out);
}

/// A block size that is not a multiple of 32 stops `swarf run` and `swarf info` with the variable named and the
/// values it accepts.
#[test]
fn bad_pair_block_is_refused_naming_the_variable() {
    let out = std::env::temp_dir().join(format!("swarf-test-tuning-bad-{}", std::process::id()));
    let run = swarf()
        .env("SWARF_PAIR_BLOCK", "100")
        .args(["--backend", "cpu", "run", "cases/block-translation.toml", "--quiet", "--out"])
        .arg(&out)
        .output()
        .expect("swarf runs");
    let info = swarf().env("SWARF_PAIR_BLOCK", "100").args(["--backend", "cpu", "info"]).output().expect("swarf runs");
    for o in [run, info] {
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("SWARF_PAIR_BLOCK") && err.contains("a multiple of 32 from 32 to 1024"), "{err}");
    }
    assert!(!out.join("summary.json").exists());
}

/// `swarf info` prints the switches.
#[test]
fn info_prints_the_tuning() {
    let o = swarf().env("SWARF_NO_FUSE", "1").args(["--backend", "cpu", "info"]).output().expect("swarf runs");
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.lines().any(|l| l.starts_with("tuning:") && l.contains("no_fuse = true")), "{text}");
}

// Moved from host/tuning.rs (the library has no unit tests: one test build, CI time).
use swarf::tuning::{Order, Tuning, TuningError};

fn with(vars: &[(&str, &str)]) -> Result<Tuning, TuningError> {
    Tuning::from_vars(|k| vars.iter().find(|(n, _)| *n == k).map(|(_, v)| v.to_string()))
}

/// Unset variables leave every default to the code that owns it.
#[test]
fn unset_is_default() {
    let t = with(&[]).expect("no variables");
    assert_eq!((t.lanes, t.pair_block, t.no_graphs, t.fast_math), (None, None, false, false));
}

/// The values the README names are read as it says.
#[test]
fn values() {
    let t = with(&[("SWARF_LANES", "4"), ("SWARF_PAIR_BLOCK", "128"), ("SWARF_PAIR_ORDER", "forward")]).expect("valid");
    assert_eq!((t.lanes, t.pair_block, t.pair_order), (Some(4), Some(128), Some(Order::Forward)));
}

/// A bad value is refused with the variable and the expected values named.
#[test]
fn bad_values_name_the_variable() {
    let e = with(&[("SWARF_PAIR_BLOCK", "100")]).expect_err("not a multiple of 32");
    assert_eq!(e.var, "SWARF_PAIR_BLOCK");
    assert!(e.to_string().contains("SWARF_PAIR_BLOCK") && e.to_string().contains("multiple of 32"), "{e}");
    assert_eq!(with(&[("SWARF_LANES", "3")]).expect_err("lanes").var, "SWARF_LANES");
    assert_eq!(with(&[("SWARF_NO_GRAPHS", "yes")]).expect_err("flag").var, "SWARF_NO_GRAPHS");
}
