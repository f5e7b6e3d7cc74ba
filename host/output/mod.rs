//! Output: binary VTU frames with a PVD index, CSV time series, all written atomically.
//!
//! Nothing is ever half-written. Every file goes to a temporary file in the destination's directory
//! (`.<name>.tmp-<pid>`), is flushed and fsync'ed, then renamed over the destination (see [`atomic`]). A reader
//! — ParaView on a running job, a script plotting the force history, a restart after a crash — sees the previous
//! complete version or the new complete version. Indexes (.pvd, .csv) are rewritten whole after every record for
//! the same reason: they are valid after every frame.
//!
//! I/O errors are returned, never swallowed or unwrapped, and name the file they concern; invalid input (array
//! lengths, row lengths, names) is refused with [`std::io::ErrorKind::InvalidInput`] before any file is created.
//!
//! - [`vtu`]: particle frames as binary VTK XML unstructured grids (vertex cells, raw or base64 + zlib appended
//!   data).
//! - [`pvd`]: the ParaView collection listing the frames with their times.
//! - [`vtp`]: the tool's outline beside each frame (PolyData, one closed polyline).
//! - [`csv`]: per-step time series.

pub mod atomic;
pub mod base64;
pub mod csv;
#[cfg(feature = "hdf5")]
pub mod hdf5;
pub mod progress;
pub mod pvd;
mod text;
pub mod vtp;
pub mod vtu;

pub use atomic::{write_atomic, write_atomic_with};
pub use csv::TimeSeries;
pub use pvd::Collection;
pub use vtu::{Array, Frame, OwnedValues, ReadFrame, Values};

/// An output error naming `path` once (the atomic writes' errors already start with it).
pub fn io_err(path: &std::path::Path, e: std::io::Error) -> crate::Error {
    let (p, text) = (path.display().to_string(), e.to_string());
    crate::Error::Output(if text.starts_with(&p) { text } else { format!("{p}: {text}") })
}
