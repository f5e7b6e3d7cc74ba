//! Time series (forces, energies, temperatures per step) as CSV.
//!
//! The series is kept in memory and the whole file is rewritten atomically on [`TimeSeries::write`], so the CSV is
//! complete and parseable whenever a plotting script reads it, even mid-run or after a crash. The cost is
//! O(rows) per write, negligible for the thousands of rows of a run's history.
//!
//! Numbers are written so that they parse back to the same f64 (see `fmt_f64`): plain decimals for ordinary
//! magnitudes (`123456.789`, `-0`), exponent form only for tiny or huge ones (`1e-300`). Column names are quoted
//! per RFC 4180 where they contain a comma, a quote or a line break, or are empty.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use super::atomic::{with_path, write_atomic};
use super::text::fmt_f64;

/// A CSV time series with a fixed header.
#[derive(Clone, Debug)]
pub struct TimeSeries {
    path: PathBuf,
    header: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl TimeSeries {
    /// An empty series to be written at `path`; nothing is written until [`TimeSeries::write`].
    pub fn new(path: impl Into<PathBuf>, header: &[&str]) -> Self {
        Self { path: path.into(), header: header.iter().map(|s| s.to_string()).collect(), rows: Vec::new() }
    }

    /// Appends a row; a row whose length differs from the header's is refused with
    /// [`io::ErrorKind::InvalidInput`], so a column can never silently shift.
    pub fn push(&mut self, row: &[f64]) -> io::Result<()> {
        if row.len() != self.header.len() {
            let (path, got, columns) = (self.path.display(), row.len(), self.header.len());
            let msg = format!("{path}: row of {got} values, header has {columns} columns");
            return Err(io::Error::new(io::ErrorKind::InvalidInput, msg));
        }
        self.rows.push(row.to_vec());
        Ok(())
    }

    /// Rewrites the whole file atomically: the header line, then every row.
    pub fn write(&self) -> io::Result<()> {
        let mut s = self.header.iter().map(|h| quote(h)).collect::<Vec<_>>().join(",");
        s.push('\n');
        for row in &self.rows {
            s.push_str(&row.iter().map(|&x| fmt_f64(x)).collect::<Vec<_>>().join(","));
            s.push('\n');
        }
        write_atomic(&self.path, s.as_bytes())
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn header(&self) -> &[String] {
        &self.header
    }

    pub fn rows(&self) -> &[Vec<f64>] {
        &self.rows
    }
}

/// Quotes a column name per RFC 4180 where needed (and always when empty, so that an empty name is not an empty
/// line).
fn quote(s: &str) -> String {
    if s.is_empty() || s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Reads a CSV written by [`TimeSeries::write`]: the header and the rows. Malformed content is refused with
/// [`io::ErrorKind::InvalidData`] naming the path and the line.
pub fn read(path: &Path) -> io::Result<(Vec<String>, Vec<Vec<f64>>)> {
    let text = fs::read_to_string(path).map_err(|e| with_path(path, e))?;
    parse(&text).map_err(|msg| io::Error::new(io::ErrorKind::InvalidData, format!("{}: {msg}", path.display())))
}

fn parse(text: &str) -> Result<(Vec<String>, Vec<Vec<f64>>), String> {
    let mut records = records(text)?.into_iter();
    let (_, header) = records.next().ok_or("empty file, no header")?;
    let mut rows = Vec::new();
    for (line, fields) in records {
        if fields.len() != header.len() {
            return Err(format!("line {line}: {} values, header has {} columns", fields.len(), header.len()));
        }
        let row =
            fields.iter().map(|f| f.trim().parse::<f64>().map_err(|_| format!("line {line}: {f:?} is not a number")));
        rows.push(row.collect::<Result<Vec<_>, _>>()?);
    }
    Ok((header, rows))
}

/// RFC 4180 records with the line each starts on; an empty line is a record of no fields.
fn records(text: &str) -> Result<Vec<(usize, Vec<String>)>, String> {
    let mut out = Vec::new();
    let (mut fields, mut field) = (Vec::new(), String::new());
    // Whether the current record has any content (an empty line is a record of zero fields, not one empty field).
    let mut started = false;
    let (mut line, mut start_line) = (1, 1);
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if field.is_empty() => {
                started = true;
                loop {
                    match chars.next() {
                        Some('"') if chars.peek() == Some(&'"') => {
                            chars.next();
                            field.push('"');
                        }
                        Some('"') => break,
                        Some(c) => {
                            line += usize::from(c == '\n');
                            field.push(c);
                        }
                        None => return Err(format!("line {start_line}: unterminated quoted field")),
                    }
                }
            }
            ',' => {
                started = true;
                fields.push(std::mem::take(&mut field));
            }
            '\r' => {}
            '\n' => {
                if started {
                    fields.push(std::mem::take(&mut field));
                }
                out.push((start_line, std::mem::take(&mut fields)));
                started = false;
                line += 1;
                start_line = line;
            }
            c => {
                started = true;
                field.push(c);
            }
        }
    }
    if started {
        fields.push(field);
        out.push((start_line, fields));
    }
    Ok(out)
}
