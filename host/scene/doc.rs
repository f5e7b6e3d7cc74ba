//! The TOML document of a scene before it is typed: a tree whose every node remembers where it came from (a line
//! of the file, or a `--set` argument), and the `--set key=value` overrides applied to it.

use crate::error::line_of;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::error::{Location, SceneError};

/// Where a node came from.
#[derive(Clone, Copy, Debug)]
pub(crate) enum At {
    /// The whole document.
    Root,
    /// A 1-based line of the file.
    Line(usize),
    /// The `--set` argument with this index.
    Set(usize),
}

#[derive(Clone, Debug)]
pub(crate) enum Val {
    /// A string, number, boolean or datetime.
    Leaf(toml::Value),
    Array(Vec<Node>),
    /// Entries in the order the parser gives them.
    Table(Vec<Entry>),
}

#[derive(Clone, Debug)]
pub(crate) struct Node {
    pub val: Val,
    /// For a value under a key, the key's position; for an array element, the element's.
    pub at: At,
}

#[derive(Clone, Debug)]
pub(crate) struct Entry {
    pub key: String,
    pub node: Node,
}

/// A parsed scene document with its overrides applied.
pub(crate) struct Doc {
    pub root: Node,
    /// The file name (or origin) used in messages.
    pub file: String,
    /// The `--set` arguments, indexed by [`At::Set`].
    pub sets: Vec<String>,
    /// Where the scene's material names are looked up (by default the search path of a scene file `file`).
    pub materials: crate::material::search::Search,
}

/// Builds the tree from the spanned parse (positions) and the plain parse (values), walked in lockstep.
fn build(de: &Spanned<DeValue<'_>>, at: At, value: toml::Value, text: &str) -> Node {
    match (de.get_ref(), value) {
        (DeValue::Table(dt), toml::Value::Table(mut t)) => {
            let entries = dt
                .iter()
                .filter_map(|(k, dv)| {
                    let key: &str = k.get_ref();
                    let v = t.remove(key)?;
                    Some(Entry {
                        key: key.to_string(),
                        node: build(dv, At::Line(line_of(text, k.span().start)), v, text),
                    })
                })
                .collect();
            Node { val: Val::Table(entries), at }
        }
        (DeValue::Array(da), toml::Value::Array(a)) => {
            let items =
                da.iter().zip(a).map(|(dv, v)| build(dv, At::Line(line_of(text, dv.span().start)), v, text)).collect();
            Node { val: Val::Array(items), at }
        }
        (_, value) => from_value(value, at),
    }
}

/// A tree from a plain TOML value, every node at `at` (used for `--set` values).
fn from_value(value: toml::Value, at: At) -> Node {
    let val = match value {
        toml::Value::Table(t) => {
            Val::Table(t.into_iter().map(|(key, v)| Entry { key, node: from_value(v, at) }).collect())
        }
        toml::Value::Array(a) => Val::Array(a.into_iter().map(|v| from_value(v, at)).collect()),
        leaf => Val::Leaf(leaf),
    };
    Node { val, at }
}

/// The value of a node as TOML text, for messages.
pub(crate) fn show(node: &Node) -> String {
    match &node.val {
        Val::Leaf(v) => v.to_string(),
        Val::Array(items) => format!("[{}]", items.iter().map(show).collect::<Vec<_>>().join(", ")),
        Val::Table(entries) => format!(
            "{{ {} }}",
            entries.iter().map(|e| format!("{} = {}", e.key, show(&e.node))).collect::<Vec<_>>().join(", ")
        ),
    }
}

impl Doc {
    /// Parses `text`; syntax errors name `file` and the line.
    pub fn parse(text: &str, file: &str) -> Result<Doc, SceneError> {
        let syntax = |e: toml::de::Error| SceneError::Syntax {
            at: Location::File { file: file.to_string(), line: e.span().map(|s| line_of(text, s.start)) },
            message: e.message().trim().to_string(),
        };
        let table: toml::Table = toml::from_str(text).map_err(syntax)?;
        let de = DeTable::parse(text).map_err(syntax)?;
        let de = Spanned::new(de.span(), DeValue::Table(de.into_inner()));
        let root = build(&de, At::Root, toml::Value::Table(table), text);
        let materials = crate::material::search::Search::for_scene(file);
        Ok(Doc { root, file: file.to_string(), sets: Vec::new(), materials })
    }

    /// Where a node came from, for messages.
    pub fn loc(&self, at: At) -> Location {
        match at {
            At::Root => Location::File { file: self.file.clone(), line: None },
            At::Line(line) => Location::File { file: self.file.clone(), line: Some(line) },
            At::Set(i) => Location::Set { arg: self.sets[i].clone() },
        }
    }

    /// Applies one `--set key=value` override: `key` is a dotted path (a numeric segment indexes an array),
    /// `value` a TOML value, or else a plain string. Missing intermediate tables are created.
    pub fn apply(&mut self, arg: &str) -> Result<(), SceneError> {
        let fail = |message: String| SceneError::Override { arg: arg.to_string(), message };
        let Some((key, text)) = arg.split_once('=') else {
            return Err(fail("expected key=value (e.g. time.end=1e-4)".into()));
        };
        let key = key.trim();
        let segments: Vec<&str> = key.split('.').map(str::trim).collect();
        if segments.iter().any(|s| s.is_empty()) {
            return Err(fail(format!("bad key '{key}': expected a dotted path such as time.end or body.0.velocity")));
        }
        let at = At::Set(self.sets.len());
        let value = from_value(parse_value(text.trim()), at);
        let mut node = &mut self.root;
        for (i, segment) in segments.iter().enumerate() {
            let path = segments[..i].join(".");
            let here = if path.is_empty() { "the document".to_string() } else { format!("'{path}'") };
            node = match &mut node.val {
                Val::Table(entries) => {
                    let pos = match entries.iter().position(|e| e.key == *segment) {
                        Some(pos) => pos,
                        // An index into an array the scene does not have (it was blamed on the table made here).
                        None if segments.get(i + 1).is_some_and(|s| s.parse::<usize>().is_ok()) => {
                            return Err(fail(format!(
                                "index {} out of range: the scene has no [[{}]] entries; add one to the scene file",
                                segments[i + 1],
                                segments[..=i].join(".")
                            )));
                        }
                        None => {
                            entries.push(Entry {
                                key: segment.to_string(),
                                node: Node { val: Val::Table(Vec::new()), at },
                            });
                            entries.len() - 1
                        }
                    };
                    &mut entries[pos].node
                }
                Val::Array(items) => {
                    let Ok(index) = segment.parse::<usize>() else {
                        return Err(fail(format!("{here} is an array: expected an index, found '{segment}'")));
                    };
                    let len = items.len();
                    match items.get_mut(index) {
                        Some(item) => item,
                        None => {
                            return Err(fail(format!(
                                "index {index} out of range: {here} has {len} entr{}",
                                if len == 1 { "y" } else { "ies" }
                            )));
                        }
                    }
                }
                Val::Leaf(v) => {
                    return Err(fail(format!(
                        "{here} is a {}, not a table: cannot set '{segment}' inside it",
                        v.type_str()
                    )));
                }
            };
        }
        *node = value;
        self.sets.push(arg.to_string());
        Ok(())
    }
}

/// A `--set` value: TOML when it parses as one value, else the text as a string.
fn parse_value(text: &str) -> toml::Value {
    if let Ok(mut t) = toml::from_str::<toml::Table>(&format!("v = {text}"))
        && t.len() == 1
        && let Some(v) = t.remove("v")
    {
        return v;
    }
    toml::Value::String(text.to_string())
}
