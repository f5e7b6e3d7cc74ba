//! The embedded PTX split into one module per entry point, so that the driver JIT-compiles only the entries a
//! run launches (issue 21, item 5: compiling all ~200 entries took most of a fresh H200's first 53 s run).
//!
//! LLVM writes the PTX as a header (`.version`, `.target`, `.address_size`) followed by top-level items, each
//! starting at column 0: `.extern` declarations (`cudaGraphSetConditional`), `.global` data, `.func` bodies and
//! `.visible .entry` kernels. A module for one entry is the header, the shared items that entry reaches (by name,
//! transitively, in their original order, so that each is declared before its use) and the entry itself.

use std::ops::Range;

/// A top-level PTX item.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Item<'a> {
    /// The symbol it declares or defines.
    pub name: &'a str,
    /// A kernel entry point (else an item the entries share).
    pub entry: bool,
    pub text: &'a str,
}

/// Where the header and the items of one PTX text are (byte ranges, so that the loader keeps the text and the
/// split side by side).
#[derive(Clone, Debug)]
pub struct SplitPtx {
    header: Range<usize>,
    items: Vec<(Range<usize>, Range<usize>, bool)>,
}

/// The directive an item starts with, at column 0.
const ITEM_STARTS: [&str; 8] =
    [".visible ", ".extern ", ".weak ", ".func ", ".entry ", ".global ", ".const ", ".shared "];

/// The symbol an item's first line declares: the word before the parameter list, the array bounds or the
/// initialiser.
fn symbol(line: &str) -> &str {
    // A function with a return value declares it first: `.func (.param .b64 func_retval0) name(`.
    let line = match line.find(".func") {
        Some(p) if line[p + 5..].trim_start().starts_with('(') => {
            let after = &line[p + 5..];
            after.find(')').map_or(line, |q| &after[q + 1..])
        }
        _ => line,
    };
    let head = line.split(['(', '[', '=', ';']).next().unwrap_or(line);
    head.split_whitespace().last().unwrap_or("")
}

/// The byte range of `part`, a slice of `whole`.
fn range_of(whole: &str, part: &str) -> Range<usize> {
    let at = part.as_ptr() as usize - whole.as_ptr() as usize;
    at..at + part.len()
}

impl SplitPtx {
    /// Splits `ptx`; None where it has no header or an item has no name.
    pub fn parse(ptx: &str) -> Option<Self> {
        let mut starts = Vec::new();
        let mut at = 0;
        for line in ptx.split_inclusive('\n') {
            if ITEM_STARTS.iter().any(|s| line.starts_with(s)) {
                starts.push(at);
            }
            at += line.len();
        }
        let first = *starts.first()?;
        let header = &ptx[..first];
        if !header.contains(".version") || !header.contains(".target") {
            return None;
        }
        let mut items = Vec::with_capacity(starts.len());
        for (k, &s) in starts.iter().enumerate() {
            let end = starts.get(k + 1).copied().unwrap_or(ptx.len());
            let text = trim_tail(&ptx[s..end]);
            let first_line = text.lines().next().unwrap_or("");
            let name = symbol(first_line);
            if name.is_empty() {
                return None;
            }
            items.push((range_of(ptx, name), range_of(ptx, text), first_line.contains(".entry ")));
        }
        Some(SplitPtx { header: 0..first, items })
    }

    /// The items of `ptx` (the text this split was parsed from), in its order.
    pub fn items<'a>(&'a self, ptx: &'a str) -> impl Iterator<Item = Item<'a>> + 'a {
        self.items.iter().map(|(n, t, e)| Item { name: &ptx[n.clone()], entry: *e, text: &ptx[t.clone()] })
    }

    /// The indices (in [`SplitPtx::items`]) of the shared items that `entry` reaches, in their original order.
    pub fn reached(&self, ptx: &str, entry: &str) -> Option<Vec<usize>> {
        let items: Vec<Item> = self.items(ptx).collect();
        let e = items.iter().find(|i| i.entry && i.name == entry)?;
        let mut used = vec![false; items.len()];
        let mut texts = vec![e.text];
        // Each pass adds the items named by the texts taken so far; a handful of passes reach the fixed point.
        loop {
            let mut grew = false;
            for (k, it) in items.iter().enumerate() {
                if !it.entry && !used[k] && texts.iter().any(|t| names(t, it.name)) {
                    used[k] = true;
                    texts.push(it.text);
                    grew = true;
                }
            }
            if !grew {
                break;
            }
        }
        Some((0..items.len()).filter(|&k| used[k]).collect())
    }

    /// The module of one entry of `ptx`: the header, the shared items it reaches and the entry; None for an
    /// unknown entry.
    pub fn module(&self, ptx: &str, entry: &str) -> Option<String> {
        let reached = self.reached(ptx, entry)?;
        let items: Vec<Item> = self.items(ptx).collect();
        let e = items.iter().find(|i| i.entry && i.name == entry)?;
        let header = &ptx[self.header.clone()];
        let mut m = String::with_capacity(header.len() + e.text.len() + 1024);
        m.push_str(header);
        for k in reached {
            m.push_str(items[k].text);
            m.push('\n');
        }
        m.push_str(e.text);
        m.push('\n');
        Some(m)
    }
}

/// Whether `text` names the symbol `name` as a whole word (PTX symbols: letters, digits, `_`, `$`, `.`).
fn names(text: &str, name: &str) -> bool {
    let word = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '$' | '.');
    text.match_indices(name).any(|(at, _)| {
        let before = text[..at].chars().next_back();
        let after = text[at + name.len()..].chars().next();
        !before.is_some_and(word) && !after.is_some_and(word)
    })
}

/// `text` without its trailing blank and comment lines (LLVM's `// .globl` line of the next item).
fn trim_tail(text: &str) -> &str {
    let mut end = text.len();
    loop {
        let body = text[..end].trim_end_matches(['\n', '\r', ' ', '\t']);
        let line_start = body.rfind('\n').map_or(0, |p| p + 1);
        let last = body[line_start..].trim_start();
        if body.is_empty() || !(last.starts_with("//") || last.is_empty()) {
            return body;
        }
        end = line_start;
    }
}
