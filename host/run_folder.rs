//! The folder a new run writes into: new or empty, or with `--force` cleared first, so that the frames and the
//! checkpoint of an earlier run never sit beside the new run's (issue 27). `--force` clears only a folder that
//! holds a swarf run, never an arbitrary one named by mistake.

use crate::{Error, Result};
use std::path::Path;

/// Files of which any one marks a folder as a swarf run folder.
const MARKERS: &[&str] = &["run.log", "scene.toml", "energy.csv", "summary.json", "checkpoint.bin", "particles.pvd"];

/// Makes `dir` ready for a new run: creates it, or checks that it is empty; a non-empty run folder is refused,
/// naming it, unless `force`, which removes what it holds. Returns how many entries were removed.
pub fn prepare(dir: &Path, force: bool) -> Result<usize> {
    let err = |what: String| Error::Output(format!("{}: {what}", dir.display()));
    if dir.exists() && !dir.is_dir() {
        return Err(err("exists and is not a folder: choose another --out".into()));
    }
    let entries: Vec<std::path::PathBuf> = match std::fs::read_dir(dir) {
        Ok(rd) => rd.map(|e| e.map(|e| e.path())).collect::<std::io::Result<_>>().map_err(|e| err(e.to_string()))?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Vec::new(),
        Err(e) => return Err(err(e.to_string())),
    };
    if entries.is_empty() {
        return Ok(0);
    }
    let is_run = MARKERS.iter().any(|m| dir.join(m).exists());
    if !force || !is_run {
        let mut names: Vec<String> =
            entries.iter().filter_map(|p| p.file_name()).map(|n| n.to_string_lossy().into_owned()).collect();
        names.sort();
        let shown = names.iter().take(3).cloned().collect::<Vec<_>>().join(", ");
        let more = if names.len() > 3 { ", …" } else { "" };
        let holds = format!("the run folder is not empty ({} entries: {shown}{more})", names.len());
        return Err(err(if !is_run {
            format!(
                "{holds} and is not a swarf run folder (no run.log or scene.toml): not cleared; choose another --out"
            )
        } else if dir.join("checkpoint.bin").is_file() {
            format!(
                "{holds}: an earlier run. Continue it with `swarf run --resume {}`, write to another folder with \
                 --out DIR, or replace it with --force",
                dir.display()
            )
        } else {
            format!("{holds}: an earlier run. Write to another folder with --out DIR, or replace it with --force")
        }));
    }
    for p in &entries {
        let r = if p.is_dir() && !p.is_symlink() { std::fs::remove_dir_all(p) } else { std::fs::remove_file(p) };
        r.map_err(|e| Error::Output(format!("--force: cannot remove {}: {e}", p.display())))?;
    }
    Ok(entries.len())
}

/// The scene the run in `dir` ran: its `scene.toml` with the run's `--set` [`overrides`] (`swarf render`,
/// `swarf chip`, `swarf neck`).
pub fn scene(dir: &Path) -> std::result::Result<crate::scene::Scene, crate::scene::SceneError> {
    crate::scene::Scene::load(dir.join("scene.toml"), &overrides(dir))
}

/// The `--set` overrides the run in `dir` was made with: summary.json's, else the checkpoint's, else none (for
/// reading its `scene.toml` as it ran: [`scene`]).
pub fn overrides(dir: &Path) -> Vec<String> {
    let from_summary = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| serde_json::from_value::<Vec<String>>(v.get("overrides")?.clone()).ok());
    from_summary
        .or_else(|| crate::checkpoint::read(&dir.join("checkpoint.bin")).ok().map(|(h, _)| h.overrides))
        .unwrap_or_default()
}
