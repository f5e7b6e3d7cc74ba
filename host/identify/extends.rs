//! `extends` in an identification file (docs/identification.md, "Variants of a file: `extends`"): the file is its
//! base file's table with its own keys laid over it, so that a variant (another model switch, replicas, another
//! optimiser) states only what differs. Tables merge key by key; every other value, arrays of tables such as
//! `[[parameter]]` and `[[experiment]]` included, replaces the base's whole. A base may extend another, up to
//! [`MAX_DEPTH`] files, without a cycle. Relative paths in the merged table (`data`, an experiment's `scene`) are
//! read from the extending file's folder, so a base and its variants share one.

use std::path::{Path, PathBuf};

use crate::{Error, Result};

/// The key that names the base file, relative to the extending file's folder.
pub const KEY: &str = "extends";

/// The longest chain of bases.
pub const MAX_DEPTH: usize = 8;

/// The table of the file `path` whose text is `text`, with its `extends` chain resolved (the key removed), and
/// whether it had one.
pub fn resolve(path: &Path, text: &str) -> Result<(toml::Table, bool)> {
    let mut chain = vec![path.to_path_buf()];
    let table = resolve_chain(text, &mut chain)?;
    Ok((table, chain.len() > 1))
}

/// Parses `text`, the last file of `chain`, and lays it over its base's resolved table.
fn resolve_chain(text: &str, chain: &mut Vec<PathBuf>) -> Result<toml::Table> {
    let path = chain.last().cloned().unwrap_or_default();
    let mut table: toml::Table =
        toml::from_str(text).map_err(|e| Error::Scene(crate::error::toml_parse_message(&path, text, &e)))?;
    let Some(base) = table.remove(KEY) else { return Ok(table) };
    let bad = |found: &dyn std::fmt::Display, expected: &str| {
        Error::Scene(format!("{}: {KEY} = {found}: expected {expected}", path.display()))
    };
    let toml::Value::String(name) = &base else {
        return Err(bad(&base, "the base identification file's path, a string"));
    };
    let base_path = path.parent().unwrap_or(Path::new("")).join(name);
    // Compared canonically (`a/../a.toml` is `a.toml`); a base that does not exist fails its read below.
    let canonical = base_path.canonicalize().ok();
    if canonical.is_some() && chain.iter().any(|p| p.canonicalize().ok() == canonical) {
        return Err(bad(&base, "a file that does not extend this one (a cycle)"));
    }
    if chain.len() >= MAX_DEPTH {
        return Err(bad(&base, &format!("at most {MAX_DEPTH} files in a chain of bases")));
    }
    let base_text = std::fs::read_to_string(&base_path)
        .map_err(|e| bad(&base, &format!("a readable file ({}: {e})", base_path.display())))?;
    chain.push(base_path);
    let mut merged = resolve_chain(&base_text, chain)?;
    overlay(&mut merged, table);
    Ok(merged)
}

/// Lays `over` on `base`: a table merges into the base's table of the same key, key by key; any other value
/// replaces the base's.
pub fn overlay(base: &mut toml::Table, over: toml::Table) {
    for (k, v) in over {
        match (base.get_mut(&k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => overlay(b, o),
            (_, v) => {
                base.insert(k, v);
            }
        }
    }
}
