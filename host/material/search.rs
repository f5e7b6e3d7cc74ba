//! Where a scene's named materials are found. A name is taken from the first of:
//!
//! 1. the folders of `SWARF_MATERIALS` (one folder, or several separated by `:`), in order;
//! 2. a `materials/` folder beside the scene file, then one in the scene's parent folder (as `cases/cutting/*.toml`
//!    uses `cases/materials/`);
//! 3. the built-in library: `cases/materials/*.toml` of the source tree, embedded at build time (build.rs).
//!
//! So a user file shadows a built-in material of the same name, and swarf runs from any folder. A run folder
//! records the materials it ran in its own `materials/` folder; resuming it reads those first
//! ([`Search::recorded`]), ignoring `SWARF_MATERIALS`, so that the run continues with the values it started with.

use std::fmt;
use std::path::{Path, PathBuf};

use super::{Library, Material, MaterialError};

include!(concat!(env!("OUT_DIR"), "/materials_embed.rs"));

/// The environment variable of the user's material folders.
pub const ENV: &str = "SWARF_MATERIALS";

/// The folder of a run folder (or scene) that holds its materials, one `<name>.toml` each.
pub const FOLDER: &str = "materials";

/// The built-in library, parsed from the embedded files.
pub fn builtin() -> Result<Library, MaterialError> {
    let mut lib = Library::default();
    for (file, text) in EMBEDDED {
        let stem = file.strip_suffix(".toml").unwrap_or(file);
        let m = Material::parse(text, &format!("built-in:{file}"), Some(stem))?;
        lib.materials.insert(m.name.clone(), m);
    }
    Ok(lib)
}

/// One folder of a search path.
#[derive(Clone, Debug, PartialEq)]
enum Folder {
    /// Named by the user (`SWARF_MATERIALS`, `--library`): it must exist.
    Required(PathBuf),
    /// Beside the scene or a run's record: used where it exists.
    Optional(PathBuf),
}

/// A search path for material names: folders in order, then the built-in library.
#[derive(Clone, Debug, PartialEq)]
pub struct Search {
    folders: Vec<Folder>,
}

impl Search {
    /// No scene file (the built-in default scene, `swarf material`): `SWARF_MATERIALS`, then the built-in library.
    pub fn without_scene() -> Search {
        let folders = match std::env::var_os(ENV) {
            Some(v) if !v.is_empty() => {
                std::env::split_paths(&v).filter(|p| !p.as_os_str().is_empty()).map(Folder::Required).collect()
            }
            _ => Vec::new(),
        };
        Search { folders }
    }

    /// For the scene file `origin`: `SWARF_MATERIALS`, `materials/` beside it and in its parent folder, built-in.
    pub fn for_scene(origin: &str) -> Search {
        let mut s = Search::without_scene();
        if let Some(dir) = Path::new(origin).parent() {
            s.folders.push(Folder::Optional(dir.join(FOLDER)));
            if let Some(up) = dir.parent() {
                s.folders.push(Folder::Optional(up.join(FOLDER)));
            }
        }
        s
    }

    /// For resuming the run folder `run`: the materials it recorded, then the built-in library (a run folder
    /// written before runs recorded their materials).
    pub fn recorded(run: &Path) -> Search {
        Search { folders: vec![Folder::Optional(run.join(FOLDER))] }
    }

    /// Only the folder `dir` (it must exist), then the built-in library: `swarf material --library DIR`.
    pub fn folder(dir: &Path) -> Search {
        Search { folders: vec![Folder::Required(dir.to_path_buf())] }
    }

    /// The library this path sees: each name from the first place that has it.
    pub fn library(&self) -> Result<Library, MaterialError> {
        let mut lib = Library::default();
        for f in &self.folders {
            match f {
                Folder::Required(dir) => lib.add_missing(Library::load_dir(dir)?),
                Folder::Optional(dir) if dir.is_dir() => lib.add_missing(Library::load_dir(dir)?),
                Folder::Optional(_) => {}
            }
        }
        lib.add_missing(builtin()?);
        Ok(lib)
    }
}

/// The places searched, for messages: e.g. `/x, cases/materials, the built-in library`
/// (optional folders only where they exist).
impl fmt::Display for Search {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for folder in &self.folders {
            match folder {
                Folder::Required(d) => write!(f, "{}, ", d.display())?,
                Folder::Optional(d) if d.is_dir() => write!(f, "{}, ", d.display())?,
                Folder::Optional(_) => {}
            }
        }
        write!(f, "the built-in library")
    }
}
