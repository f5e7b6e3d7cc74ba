//! The ParaView collection (.pvd) that lists the frames of a run with their times.
//!
//! The whole index is rewritten (atomically) after every frame rather than appended to, so it is a valid file at
//! every moment: ParaView can open a running or crashed simulation and sees every frame written so far.

use std::fmt::Write as _;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use super::atomic::{with_path, write_atomic};
use super::text::{escape_attr, fmt_f64, tags, unescape_attr};

/// A time series of data files: (time, part, file path relative to the .pvd's directory). Part 0 is the particle
/// frames, part 1 the tool's outline at the same time.
#[derive(Clone, Debug)]
pub struct Collection {
    path: PathBuf,
    entries: Vec<(f64, u32, String)>,
}

impl Collection {
    /// An empty collection to be written at `path`; nothing is written until [`Collection::write`].
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self { path: path.into(), entries: Vec::new() }
    }

    /// Adds a frame. `file` is relative to the directory of the .pvd (ParaView resolves it so), e.g.
    /// `"frames/frame_000010.vtu"`. A non-finite time is refused ([`io::ErrorKind::InvalidInput`]): readers parse
    /// the attribute with `strtod`-like functions that reject `NaN` and `inf`.
    pub fn push(&mut self, time: f64, file: impl Into<String>) -> io::Result<()> {
        self.push_part(time, 0, file)
    }

    /// Adds a file as part `part` of the time step `time` (the particles are part 0).
    pub fn push_part(&mut self, time: f64, part: u32, file: impl Into<String>) -> io::Result<()> {
        let file = file.into();
        if !time.is_finite() {
            let msg = format!("{}: time {time} of {file} is not finite", self.path.display());
            return Err(io::Error::new(io::ErrorKind::InvalidInput, msg));
        }
        self.entries.push((time, part, file));
        Ok(())
    }

    /// Rewrites the whole .pvd atomically with every entry pushed so far.
    pub fn write(&self) -> io::Result<()> {
        let mut s = String::from("<?xml version=\"1.0\"?>\n");
        s.push_str("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n");
        for (time, part, file) in &self.entries {
            // Writing into a String cannot fail.
            let _ = writeln!(
                s,
                r#"    <DataSet timestep="{}" group="" part="{part}" file="{}"/>"#,
                fmt_f64(*time),
                escape_attr(file)
            );
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        write_atomic(&self.path, s.as_bytes())
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn entries(&self) -> &[(f64, u32, String)] {
        &self.entries
    }
}

/// Reads the (time, file) entries of the particle frames (part 0) of a .pvd written by [`Collection::write`], in
/// file order.
pub fn read(path: &Path) -> io::Result<Vec<(f64, String)>> {
    Ok(read_parts(path)?.into_iter().filter(|e| e.1 == 0).map(|(t, _, f)| (t, f)).collect())
}

/// Reads every (time, part, file) entry of a .pvd written by [`Collection::write`], in file order (a missing
/// `part` reads as 0).
pub fn read_parts(path: &Path) -> io::Result<Vec<(f64, u32, String)>> {
    let text = fs::read_to_string(path).map_err(|e| with_path(path, e))?;
    parse(&text).map_err(|msg| io::Error::new(io::ErrorKind::InvalidData, format!("{}: {msg}", path.display())))
}

fn parse(text: &str) -> Result<Vec<(f64, u32, String)>, String> {
    let mut collection = false;
    let mut entries = Vec::new();
    for tag in tags(text)? {
        match tag.name {
            "VTKFile" if !tag.closing => {
                if tag.attr("type") != Some("Collection") {
                    return Err(format!("<VTKFile> type is {:?}, expected \"Collection\"", tag.attr("type")));
                }
                collection = true;
            }
            "DataSet" if !tag.closing => {
                let time = tag.attr("timestep").ok_or("<DataSet> without timestep")?;
                let time = time.trim().parse().map_err(|_| format!("timestep {time:?} is not a number"))?;
                let file = tag.attr("file").ok_or("<DataSet> without file")?;
                let file = unescape_attr(file).ok_or_else(|| format!("bad character reference in file {file:?}"))?;
                let part = tag.attr("part").unwrap_or("0");
                let part = part.trim().parse().map_err(|_| format!("part {part:?} is not a number"))?;
                entries.push((time, part, file));
            }
            _ => {}
        }
    }
    if !collection {
        return Err("no <VTKFile type=\"Collection\"> element".into());
    }
    Ok(entries)
}
