//! What a run was: the resolved scene and the values of every library material it uses, stored in its
//! checkpoint so that `swarf run --resume` can tell whether the run folder's `scene.toml` (or a material file)
//! changed since, and say what changed. The scene is compared as resolved (after the `--set` overrides, with
//! defaults filled in), without its file path and precision (the checkpoint's header checks the precision).

use crate::hash::fnv1a64;
use crate::scene::Scene;
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// Most differences listed in one message.
const MAX_LISTED: usize = 12;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// FNV-1a 64 of `scene` (its compact JSON text).
    pub scene_hash: u64,
    /// The resolved scene as JSON (keys as in the scene file).
    pub scene: Value,
    /// Each library material the scene uses: where it is used, its name, and FNV-1a 64 of its values.
    pub materials: Vec<MaterialStamp>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaterialStamp {
    /// `material`, `body.<name>.material` or `tool.thermal.material`.
    pub role: String,
    pub name: String,
    pub hash: u64,
}

impl Provenance {
    pub fn of(scene: &Scene) -> Provenance {
        let mut v = serde_json::to_value(scene).unwrap_or(Value::Null);
        if let Some(o) = v.as_object_mut() {
            o.remove("origin");
            o.remove("precision");
        }
        let scene_hash = fnv1a64(v.to_string().as_bytes());
        let mut used = vec![("material".to_string(), scene.material.library.as_ref())];
        used.extend(scene.bodies.iter().map(|b| (format!("body.{}.material", b.name), b.material.as_ref())));
        let tool = scene.tool.as_ref().and_then(|t| t.thermal.as_ref()).and_then(|t| t.material.as_ref());
        used.push(("tool.thermal.material".to_string(), tool));
        let materials = used
            .into_iter()
            .filter_map(|(role, m)| {
                // The values only: not the file it was read from, its description or source.
                let m = m?;
                let values = format!("{:?}", (&m.name, &m.elastic, &m.thermal, &m.flow_stress));
                Some(MaterialStamp { role, name: m.name.clone(), hash: fnv1a64(values.as_bytes()) })
            })
            .collect();
        Provenance { scene_hash, scene: v, materials }
    }

    /// What differs from `was` (the checkpoint's), one line each: `key: <then> then, <now> now`. Empty: the same.
    pub fn differences(&self, was: &Provenance) -> Vec<String> {
        let mut out = Vec::new();
        if self.scene_hash != was.scene_hash {
            diff_values("", &was.scene, &self.scene, &mut out);
            if out.is_empty() {
                out.push(format!("the scene's hash: {:#018x} then, {:#018x} now", was.scene_hash, self.scene_hash));
            }
        }
        for m in &was.materials {
            match self.materials.iter().find(|n| n.role == m.role) {
                None => out.push(format!("{}: {} then, none now", m.role, m.name)),
                Some(n) if n.name != m.name => out.push(format!("{}: {} then, {} now", m.role, m.name, n.name)),
                Some(n) if n.hash != m.hash => out.push(format!(
                    "{} {}: its values changed (hash {:#018x} then, {:#018x} now)",
                    m.role, m.name, m.hash, n.hash
                )),
                Some(_) => {}
            }
        }
        for n in self.materials.iter().filter(|n| !was.materials.iter().any(|m| m.role == n.role)) {
            out.push(format!("{}: none then, {} now", n.role, n.name));
        }
        if out.len() > MAX_LISTED {
            let more = out.len() - MAX_LISTED;
            out.truncate(MAX_LISTED);
            out.push(format!("and {more} more"));
        }
        out
    }
}

/// Appends the keys (dotted, arrays by index) whose values differ between `a` (then) and `b` (now).
fn diff_values(path: &str, a: &Value, b: &Value, out: &mut Vec<String>) {
    let key = |k: &str| if path.is_empty() { k.to_string() } else { format!("{path}.{k}") };
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for (k, va) in x {
                diff_values(&key(k), va, y.get(k).unwrap_or(&Value::Null), out);
            }
            for (k, vb) in y.iter().filter(|(k, _)| !x.contains_key(*k)) {
                diff_values(&key(k), &Value::Null, vb, out);
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() && x.iter().any(|v| v.is_object()) => {
            for (i, (va, vb)) in x.iter().zip(y).enumerate() {
                diff_values(&key(&i.to_string()), va, vb, out);
            }
        }
        _ if a != b => out.push(format!("{path}: {a} then, {b} now")),
        _ => {}
    }
}
