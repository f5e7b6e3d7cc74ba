//! `swarf run --resume`: whether a run folder can be continued, checked before any work. The checkpoint's
//! checksums and values must hold ([`crate::checkpoint::validate`]; never overridden), and the run folder's
//! `scene.toml` with the recorded overrides, its materials and the swarf version must be those the checkpoint was
//! written with; differences are listed, and refused unless accepted (`--accept-changes`).

use crate::checkpoint::{Header, VERSION};
use crate::provenance::Provenance;
use crate::scene::Scene;
use crate::{Error, Result};
use std::path::Path;

/// A run folder ready to continue.
pub struct Resumable {
    pub scene: Scene,
    /// The `--set` overrides the run was started with.
    pub overrides: Vec<String>,
    /// The differences from the checkpoint that were accepted (empty unless `accept_changes`).
    pub accepted: Vec<String>,
}

/// Reads and checks `dir/checkpoint.bin` and the scene it continues; with `accept_changes`, differences of the
/// scene, materials and version are returned instead of refused.
pub fn open(dir: &Path, accept_changes: bool) -> Result<Resumable> {
    let path = dir.join("checkpoint.bin");
    let (h, state) = crate::checkpoint::read(&path)?;
    crate::checkpoint::validate(&h, &state).map_err(|e| Error::Checkpoint(format!("{}: {e}", path.display())))?;
    // The scene as the folder holds it, its material names looked up first in the materials the run recorded
    // (`materials/`), so that a run folder resumes from any folder.
    let scene_path = dir.join("scene.toml");
    let text =
        std::fs::read_to_string(&scene_path).map_err(|e| Error::Scene(format!("{}: {e}", scene_path.display())))?;
    let search = crate::material::search::Search::recorded(dir);
    let scene = Scene::from_str_in(&text, &scene_path.display().to_string(), &h.overrides, search)
        .map_err(|e| Error::Scene(e.to_string()))?;
    let changes = differences(&h, &scene);
    if !changes.is_empty() && !accept_changes {
        return Err(Error::Checkpoint(format!(
            "{} does not match the run it continues:\n  {}\nrestore the run folder's scene.toml (and materials), rerun \
             the scene into a fresh folder, or continue anyway with --accept-changes (the continuation is then not \
             the run it would have been)",
            path.display(),
            changes.join("\n  ")
        )));
    }
    Ok(Resumable { scene, overrides: h.overrides, accepted: changes })
}

/// What differs between the checkpoint's record and `scene` now, one line each.
fn differences(h: &Header, scene: &Scene) -> Vec<String> {
    let mut out = Vec::new();
    if h.version.is_empty() || h.provenance.is_none() || h.checksums.is_empty() {
        out.push("the checkpoint records no version, scene or checksums (written by an older swarf)".to_string());
    } else if h.version != VERSION {
        out.push(format!("swarf version: {} then, {VERSION} now", h.version));
    }
    if let Some(was) = &h.provenance {
        let now = Provenance::of(scene);
        out.extend(now.differences(was).into_iter().map(|d| format!("scene.toml: {d}")));
    }
    out
}
