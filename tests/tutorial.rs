//! docs/tutorial.md runs as written (issue 27, item 8): every `$ swarf ...` line of its `console` blocks is run,
//! in order, in a fresh folder outside the repository, with the files its `<!-- file: NAME -->` blocks give, and
//! must succeed; then the files the tutorial says they make must be there. The one other command, `cargo install
//! --locked --path .`, is run by `.ci/run`'s install step, which then runs this test with the installed binary
//! (`SWARF_TUTORIAL_BIN`).

use std::path::Path;
use std::process::Command;

/// The tutorial's steps in order: a file to write (name, contents) or a command line (without the `$ `).
enum Step {
    File(String, String),
    Command(String),
}

fn steps(md: &str) -> Vec<Step> {
    let mut out = Vec::new();
    let mut pending_file: Option<String> = None;
    let mut block: Option<(String, Vec<String>)> = None;
    for line in md.lines() {
        if let Some((lang, lines)) = block.as_mut() {
            if line.trim_start().starts_with("```") {
                let (lang, lines) = (lang.clone(), std::mem::take(lines));
                block = None;
                if let Some(name) = pending_file.take() {
                    out.push(Step::File(name, lines.join("\n") + "\n"));
                } else if lang == "console" {
                    out.extend(lines.iter().filter_map(|l| l.strip_prefix("$ ")).map(|c| Step::Command(c.into())));
                }
            } else {
                lines.push(line.to_string());
            }
            continue;
        }
        if let Some(name) = line.trim().strip_prefix("<!-- file:").and_then(|r| r.strip_suffix("-->")) {
            pending_file = Some(name.trim().to_string());
        } else if let Some(lang) = line.trim_start().strip_prefix("```") {
            block = Some((lang.trim().to_string(), Vec::new()));
        }
    }
    out
}

#[test]
fn the_tutorial_runs_as_written() {
    let md = std::fs::read_to_string("docs/tutorial.md").expect("docs/tutorial.md");
    let dir = std::env::temp_dir().join(format!("swarf-tutorial-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a fresh folder");
    // The installed binary where .ci/run gives it (after `cargo install`), else this build's.
    let bin = std::env::var("SWARF_TUTORIAL_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_swarf").to_string());
    let (mut files, mut commands) = (0, 0);
    for step in steps(&md) {
        match step {
            Step::File(name, text) => {
                std::fs::write(dir.join(&name), text).expect("write the tutorial's file");
                files += 1;
            }
            Step::Command(line) => {
                let words: Vec<&str> = line.split_whitespace().collect();
                if words[..2] == ["cargo", "install"] {
                    continue;
                }
                assert_eq!(words[0], "swarf", "a tutorial command that is not swarf's: {line}");
                let out = Command::new(&bin).args(&words[1..]).current_dir(&dir).output().expect("swarf starts");
                assert!(
                    out.status.success(),
                    "`{line}` failed ({}):\n{}{}",
                    out.status,
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                );
                commands += 1;
            }
        }
    }
    assert_eq!(files, 1, "the tutorial writes my-cut.toml");
    assert_eq!(commands, 11, "the tutorial's swarf commands, each run");
    // What the tutorial says the commands make.
    for f in [
        "runs/first-cut/summary.json",
        "runs/first-cut/particles.pvd",
        "runs/my-cut/summary.json",
        "runs/my-cut/forces.csv",
        "runs/friction/sweep.csv",
        "runs/friction/sweep.md",
        "runs/friction/sweep-tool.friction.png",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing after the tutorial");
    }
    let pngs = |d: &Path| {
        std::fs::read_dir(d).map_or(0, |r| {
            r.filter(|e| e.as_ref().is_ok_and(|e| e.path().extension().is_some_and(|x| x == "png"))).count()
        })
    };
    assert!(pngs(&dir.join("runs/my-cut/render")) >= 1, "swarf render drew nothing in runs/my-cut/render");
    assert!(pngs(&dir.join("runs/my-cut/pictures")) >= 2, "--frame all drew fewer than two pictures");
    let _ = std::fs::remove_dir_all(&dir);
}
