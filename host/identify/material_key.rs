//! Parameters of the scene's library material: `material.flow_stress.<key>` (e.g. `material.flow_stress.A` in
//! Pa). The scene file names its material, so these are not scene keys; each run's scene gets a copy of the
//! material with the values replaced, and the run folder records that copy (`materials/<name>.toml`), so that it
//! holds the values it ran. Only keys the material's `[flow_stress]` already has are accepted.

use crate::material::Material;
use crate::scene::Scene;

/// The prefix of a material parameter.
pub const PREFIX: &str = "material.flow_stress.";

/// The flow-stress key of a material parameter, or None for a scene key.
pub fn flow_key(key: &str) -> Option<&str> {
    key.strip_prefix(PREFIX)
}

/// `m` with its `[flow_stress]` values replaced by `edits` (key, value); the name kept unless `rename`. Refused
/// (what is expected) for a key the material lacks or a value it refuses.
pub fn with_values(m: &Material, edits: &[(&str, f64)], rename: Option<(&str, &str)>) -> Result<Material, String> {
    let mut doc: toml::Table = toml::from_str(&m.text).map_err(|e| format!("{}: {e}", m.file.display()))?;
    let flow = doc
        .get_mut("flow_stress")
        .and_then(toml::Value::as_table_mut)
        .ok_or_else(|| format!("a material with [flow_stress] (material {} has none)", m.name))?;
    for (k, v) in edits {
        if !flow.contains_key(*k) {
            let keys: Vec<&str> = flow.keys().map(String::as_str).filter(|k| *k != "model").collect();
            return Err(format!(
                "{PREFIX}<key> with a key of material {}'s [flow_stress]: {}",
                m.name,
                keys.join(", ")
            ));
        }
        flow.insert(k.to_string(), toml::Value::Float(*v));
    }
    let name = match rename {
        Some((name, description)) => {
            doc.insert("name".into(), toml::Value::String(name.into()));
            doc.insert("description".into(), toml::Value::String(description.into()));
            name.to_string()
        }
        None => m.name.clone(),
    };
    let text = toml::to_string(&doc).map_err(|e| e.to_string())?;
    let mut out = Material::parse(&text, &m.file.display().to_string(), Some(&name))
        .map_err(|e| format!("values the material accepts: {e}"))?;
    out.file = m.file.clone();
    Ok(out)
}

/// Replaces the scene's library material (and any body's of the same name) by its copy with `edits`.
pub fn apply(scene: &mut Scene, edits: &[(&str, f64)]) -> Result<(), String> {
    if edits.is_empty() {
        return Ok(());
    }
    let lib = scene.material.library.as_ref().ok_or("a scene whose [material] names a library material")?;
    let edited = with_values(lib, edits, None)?;
    for b in scene.bodies.iter_mut() {
        if b.material.as_ref().is_some_and(|m| m.name == edited.name) {
            b.material = Some(edited.clone());
        }
    }
    scene.material.library = Some(edited);
    Ok(())
}
