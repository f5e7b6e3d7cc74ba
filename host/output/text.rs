//! Text helpers shared by the writers and readers: round-tripping number formatting and the few pieces of XML
//! that the .vtu and .pvd files need (attribute escaping and a tag scanner for reading our own files back).

use std::borrow::Cow;

/// Formats `x` so that `str::parse::<f64>` gives back the same bits (apart from NaN payloads), and so that
/// spreadsheets, NumPy and VTK's `strtod`-style parsers read it.
///
/// Both `{}` and `{:e}` print the shortest string that round-trips; `{}` never uses an exponent, which is
/// readable for ordinary magnitudes but prints 300 zeros for 1e-300, so tiny and huge magnitudes use `{:e}`.
pub(crate) fn fmt_f64(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() || (1e-5..1e16).contains(&a) { format!("{x}") } else { format!("{x:e}") }
}

/// Escapes a string for a double-quoted XML attribute. Control characters become character references because
/// XML parsers replace literal tabs and newlines in attributes by spaces.
pub(crate) fn escape_attr(s: &str) -> Cow<'_, str> {
    if !s.chars().any(|c| matches!(c, '&' | '<' | '>' | '"' | '\'') || c.is_control()) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if c.is_control() => out.push_str(&format!("&#{};", u32::from(c))),
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// Undoes [`escape_attr`] (the five named entities and numeric references); `None` on a malformed reference.
pub(crate) fn unescape_attr(s: &str) -> Option<String> {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find('&') {
        out.push_str(&rest[..i]);
        rest = &rest[i + 1..];
        let end = rest.find(';')?;
        let entity = &rest[..end];
        let c = match entity {
            "amp" => '&',
            "lt" => '<',
            "gt" => '>',
            "quot" => '"',
            "apos" => '\'',
            _ => {
                let code = if let Some(hex) = entity.strip_prefix("#x") {
                    u32::from_str_radix(hex, 16).ok()?
                } else {
                    entity.strip_prefix('#')?.parse().ok()?
                };
                char::from_u32(code)?
            }
        };
        out.push(c);
        rest = &rest[end + 1..];
    }
    out.push_str(rest);
    Some(out)
}

/// One XML tag: `<name a="1" b="2">`, `</name>` or `<name .../>`.
#[derive(Debug)]
pub(crate) struct Tag<'a> {
    pub name: &'a str,
    pub closing: bool,
    pub self_closing: bool,
    attrs: Vec<(&'a str, &'a str)>,
}

impl<'a> Tag<'a> {
    /// The raw (still escaped) value of attribute `key`.
    pub fn attr(&self, key: &str) -> Option<&'a str> {
        self.attrs.iter().find(|(k, _)| *k == key).map(|&(_, v)| v)
    }
}

/// The tags of `text` in order, skipping the XML declaration and comments; text between tags is ignored. This is
/// enough for the files this module writes and deliberately no more: it is not an XML parser.
pub(crate) fn tags(text: &str) -> Result<Vec<Tag<'_>>, String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find('<') {
        rest = &rest[i + 1..];
        if let Some(r) = rest.strip_prefix("!--") {
            let end = r.find("-->").ok_or("unterminated comment")?;
            rest = &r[end + 3..];
            continue;
        }
        let end = rest.find('>').ok_or("unterminated tag")?;
        let inner = &rest[..end];
        rest = &rest[end + 1..];
        if inner.starts_with('?') {
            continue;
        }
        out.push(parse_tag(inner)?);
    }
    Ok(out)
}

fn parse_tag(inner: &str) -> Result<Tag<'_>, String> {
    let (closing, inner) = match inner.strip_prefix('/') {
        Some(s) => (true, s),
        None => (false, inner),
    };
    let (self_closing, inner) = match inner.strip_suffix('/') {
        Some(s) => (true, s),
        None => (false, inner),
    };
    let inner = inner.trim();
    let name_end = inner.find(char::is_whitespace).unwrap_or(inner.len());
    let name = &inner[..name_end];
    if name.is_empty() {
        return Err(format!("tag without a name: <{inner}>"));
    }
    let mut attrs = Vec::new();
    let mut rest = inner[name_end..].trim_start();
    while !rest.is_empty() {
        let eq = rest.find('=').ok_or_else(|| format!("attribute without value in <{name}>"))?;
        let key = rest[..eq].trim();
        let after = rest[eq + 1..].trim_start();
        let quote = after.chars().next().filter(|c| *c == '"' || *c == '\'');
        let quote = quote.ok_or_else(|| format!("unquoted attribute {key} in <{name}>"))?;
        let body = &after[1..];
        let close = body.find(quote).ok_or_else(|| format!("unterminated attribute {key} in <{name}>"))?;
        attrs.push((key, &body[..close]));
        rest = body[close + 1..].trim_start();
    }
    Ok(Tag { name, closing, self_closing, attrs })
}
