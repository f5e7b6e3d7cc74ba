//! Atomic file replacement: write a temporary file beside the destination, fsync it, rename it over the
//! destination, fsync the directory.
//!
//! A reader (ParaView polling a .pvd, a plotting script tailing a CSV, a restart after a crash or a killed job)
//! therefore sees either the old file or the new one, never a truncated one. The temporary file lives in the
//! destination's directory because `rename` is atomic only within one file system.
//!
//! The temporary name is `.<name>.tmp-<pid>`: hidden, and distinct per process, so two runs writing into the same
//! directory do not clobber each other's temporaries. Two threads of one process must not write the same
//! destination at the same time (they would share the temporary file).

use std::ffi::OsString;
use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// Buffer between the caller's many small writes and the file: large enough that a frame of 10⁶ particles goes
/// out in few system calls.
const BUFFER: usize = 1 << 20;

/// Writes `bytes` to `path` atomically (see the module docs).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// Streams the output of `f` to `path` atomically (see the module docs), through a buffered writer, so that
/// large frames need not be assembled in memory first.
///
/// If `f`, the flush, the fsync or the rename fails, the temporary file is removed and the destination is left as
/// it was. Every error names `path` and keeps the kind of the underlying error.
pub fn write_atomic_with(path: &Path, f: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    let tmp = temp_path(path)?;
    let mut guard = TempFile { path: tmp, armed: true };
    let result = write_temp(&guard.path, f).and_then(|()| fs::rename(&guard.path, path));
    if let Err(e) = result {
        if is_link(&guard.path) {
            // Not ours: leave a planted link where it is.
            guard.armed = false;
            return Err(with_path(path, e));
        }
        // The original error is the one to report; a failed clean-up is appended rather than dropped.
        return Err(match guard.remove() {
            Ok(()) => with_path(path, e),
            Err(r) => io::Error::new(
                e.kind(),
                format!("{}: {e} (temporary file {} not removed: {r})", path.display(), guard.path.display()),
            ),
        });
    }
    guard.armed = false;
    sync_dir(path).map_err(|e| with_path(path, e))
}

fn is_link(p: &Path) -> bool {
    fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_symlink())
}

/// Wraps an I/O error with the path it concerns, keeping its kind: the OS message alone ("No such file or
/// directory") does not say which file.
pub(crate) fn with_path(path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// `.<name>.tmp-<pid>` in the directory of `path`.
fn temp_path(path: &Path) -> io::Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, format!("{}: not a file name", path.display())))?;
    let mut tmp = OsString::from(".");
    tmp.push(name);
    tmp.push(format!(".tmp-{}", std::process::id()));
    Ok(path.with_file_name(tmp))
}

fn write_temp(tmp: &Path, f: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    let mut w = BufWriter::with_capacity(BUFFER, create_exclusive(tmp)?);
    f(&mut w)?;
    let file = w.into_inner().map_err(io::IntoInnerError::into_error)?;
    // The data must be on disk before the rename makes it visible, or a crash could expose an empty file.
    file.sync_all()
}

/// Creates `tmp` new (O_CREAT | O_EXCL, which never follows a symbolic link), so that a link planted at the
/// temporary name cannot redirect the write to another file (issue 27). A plain file left there by a killed
/// process with the same id is removed and the creation tried once more; a link is refused.
fn create_exclusive(tmp: &Path) -> io::Result<File> {
    let open = || fs::OpenOptions::new().write(true).create_new(true).open(tmp);
    match open() {
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
            if fs::symlink_metadata(tmp)?.file_type().is_symlink() {
                return Err(io::Error::new(
                    io::ErrorKind::AlreadyExists,
                    format!("temporary file {} is a symbolic link; refusing to write through it", tmp.display()),
                ));
            }
            fs::remove_file(tmp)?;
            open()
        }
        r => r,
    }
}

/// Makes the rename itself durable: the new directory entry is on disk once this returns.
#[cfg(unix)]
pub(crate) fn sync_dir(path: &Path) -> io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    File::open(dir)?.sync_all()
}

/// Directories cannot be opened as files here; the rename is still atomic, only its durability is up to the OS.
#[cfg(not(unix))]
pub(crate) fn sync_dir(_path: &Path) -> io::Result<()> {
    Ok(())
}

/// Removes the temporary file if the write is abandoned, including by a panic in the caller's closure.
pub(crate) struct TempFile {
    pub(crate) path: PathBuf,
    pub(crate) armed: bool,
}

impl TempFile {
    pub(crate) fn remove(&mut self) -> io::Result<()> {
        self.armed = false;
        match fs::remove_file(&self.path) {
            // Nothing was created (e.g. the directory does not exist): nothing to clean up.
            Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
            r => r,
        }
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if self.armed {
            // Only reached while unwinding from a panic in the closure; there is no caller to report to.
            let _ = fs::remove_file(&self.path);
        }
    }
}
