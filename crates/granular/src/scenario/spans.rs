//! Where a key is in the scenario text, and which key a parser error points at, from the
//! TOML parser's own spans (`toml::de::DeTable`) rather than by searching lines.

use super::ScenarioError;
use std::ops::Range;
use toml::de::{DeTable, DeValue};

/// One step of a dotted key path: a table key or an array index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum Segment {
    /// A table key.
    Key(String),
    /// An array index.
    Index(usize),
}

/// Splits `species[1].velocity.speed` (or `species.1.velocity.speed`) into segments. A
/// malformed key (an unclosed or empty bracket, an empty part, a character that cannot
/// appear in a bare TOML key) is an error that says what is wrong.
pub(super) fn parse_path(key: &str) -> Result<Vec<Segment>, String> {
    if key.is_empty() {
        return Err(
            "the key is empty; write it as in the file, e.g. collisions.restitution".into(),
        );
    }
    let mut out = Vec::new();
    for part in key.split('.') {
        let (name, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if name.is_empty() && rest.is_empty() {
            return Err(format!(
                "`{key}` has an empty part; separate keys with single dots"
            ));
        }
        if !name.is_empty() {
            if let Some(c) = name
                .chars()
                .find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '-'))
            {
                return Err(format!(
                    "`{key}` contains {c:?}; keys are letters, digits, `_` and `-`, with `[i]` for an array entry"
                ));
            }
            match name.parse::<usize>() {
                Ok(i) if !out.is_empty() => out.push(Segment::Index(i)),
                _ => out.push(Segment::Key(name.to_string())),
            }
        }
        while !rest.is_empty() {
            let close = rest.find(']').ok_or_else(|| {
                format!("`{key}` has an unclosed `[`; write an array entry as name[i], e.g. species[0].mass")
            })?;
            let index = rest[1..close].parse::<usize>().map_err(|_| {
                format!(
                    "`{key}`: `{}` is not an array index; write a whole number in brackets, e.g. species[0]",
                    &rest[..=close]
                )
            })?;
            if out.is_empty() {
                return Err(format!(
                    "`{key}` starts with an index; name the array first"
                ));
            }
            out.push(Segment::Index(index));
            rest = &rest[close + 1..];
            if !rest.is_empty() && !rest.starts_with('[') {
                return Err(format!(
                    "`{key}`: `{rest}` follows `]`; separate the next key with a dot"
                ));
            }
        }
    }
    Ok(out)
}

/// Writes segments back as `species[1].velocity.speed`.
pub(super) fn path_text(path: &[Segment]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            Segment::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Segment::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// The 1-based line of byte `offset` in `source`.
pub(super) fn line_of(source: &str, offset: usize) -> usize {
    let end = offset.min(source.len());
    source.as_bytes()[..end]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// The span of `key` in `source`: the key itself when it is written there, else the
/// deepest enclosing table or array entry that is (so that a missing key points at its
/// table). `None` when the text does not parse or nothing of the path is in it.
pub(super) fn span_of(source: &str, key: &str) -> Option<Range<usize>> {
    let path = parse_path(key).ok()?;
    let doc = DeTable::parse(source).ok()?;
    let mut best = None;
    let mut value: &DeValue = &DeValue::Table(DeTable::default());
    let mut table = Some(doc.get_ref());
    for seg in &path {
        let next = match (seg, table, value) {
            (Segment::Key(k), Some(t), _) => t
                .iter()
                .find(|(key, _)| key.get_ref().as_ref() == k.as_str())
                .map(|(key, v)| (key.span(), v)),
            (Segment::Index(i), _, DeValue::Array(a)) => a.get(*i).map(|v| (v.span(), v)),
            _ => None,
        };
        let Some((span, v)) = next else { break };
        best = Some(span);
        value = v.get_ref();
        table = match value {
            DeValue::Table(t) => Some(t),
            _ => None,
        };
    }
    best
}

/// The 1-based line of dotted `key` (`species[1].velocity.speed`) in TOML `source`, from
/// the parser's spans: the key's own line when it is written there, else the line of the
/// deepest enclosing table or entry that is; `None` when nothing of it is in the text.
pub fn locate(source: &str, key: &str) -> Option<usize> {
    span_of(source, key).map(|s| line_of(source, s.start))
}

/// The dotted path of the innermost key whose key or value contains byte `offset`.
pub(super) fn path_at(source: &str, offset: usize) -> Option<String> {
    let doc = DeTable::parse(source).ok()?;
    let mut path = Vec::new();
    walk_table(doc.get_ref(), offset, &mut path);
    (!path.is_empty()).then(|| path_text(&path))
}

fn walk_table(t: &DeTable, offset: usize, path: &mut Vec<Segment>) {
    for (k, v) in t.iter() {
        let (ks, vs) = (k.span(), v.span());
        let inside = |s: &Range<usize>| s.start <= offset && offset < s.end.max(s.start + 1);
        if inside(&ks) || inside(&vs) || within_table(v.get_ref(), offset) {
            path.push(Segment::Key(k.get_ref().to_string()));
            walk_value(v.get_ref(), offset, path);
            return;
        }
    }
}

/// Whether `offset` falls on a key of table `v` (tables from `[header]` sections have
/// spans that do not cover their body).
fn within_table(v: &DeValue, offset: usize) -> bool {
    match v {
        DeValue::Table(t) => t.iter().any(|(k, v)| {
            let (ks, vs) = (k.span(), v.span());
            (ks.start <= offset && offset < ks.end)
                || (vs.start <= offset && offset < vs.end)
                || within_table(v.get_ref(), offset)
        }),
        DeValue::Array(a) => a.iter().any(|e| {
            let s = e.span();
            (s.start <= offset && offset < s.end) || within_table(e.get_ref(), offset)
        }),
        _ => false,
    }
}

fn walk_value(v: &DeValue, offset: usize, path: &mut Vec<Segment>) {
    match v {
        DeValue::Table(t) => walk_table(t, offset, path),
        DeValue::Array(a) => {
            for (i, e) in a.iter().enumerate() {
                let s = e.span();
                if (s.start <= offset && offset < s.end) || within_table(e.get_ref(), offset) {
                    path.push(Segment::Index(i));
                    walk_value(e.get_ref(), offset, path);
                    return;
                }
            }
        }
        _ => {}
    }
}

/// A parser or type error of `text` as a scenario error: the key from the error's span,
/// the line from `source` (the file; `text` may be the file with `--set` applied).
pub(super) fn parse_error(source: &str, text: &str, e: &toml::de::Error) -> ScenarioError {
    let span = e.span();
    let raw = e.message().trim().to_string();
    if raw.starts_with("duplicate key")
        && let Some(s) = &span
        && let Some(dup) = duplicate_key(text, s.start)
    {
        return dup;
    }
    let message = plain_words(&raw);
    let key = span
        .as_ref()
        .and_then(|s| path_at(text, s.start))
        .unwrap_or_default();
    let key = unknown_field_key(&message, key);
    let line = if std::ptr::eq(source, text) {
        span.map(|s| line_of(source, s.start))
    } else {
        locate(source, &key)
    };
    let fix = if message.contains("unknown field") {
        " (check the spelling; docs/scenario.md lists every key)"
    } else if message.contains("missing field") {
        " (add it; docs/scenario.md describes it)"
    } else if message.starts_with("invalid type") || message.starts_with("invalid value") {
        " (docs/scenario.md gives the type of every key)"
    } else {
        ""
    };
    ScenarioError {
        key,
        message: format!("{message}{fix}"),
        line,
    }
}

/// For an unknown key the error's span may cover its table: append the key's name when the
/// path does not end with it.
fn unknown_field_key(message: &str, key: String) -> String {
    let Some(rest) = message.strip_prefix("unknown field `") else {
        return key;
    };
    let Some(name) = rest.split('`').next() else {
        return key;
    };
    if key.is_empty() || name.starts_with(&format!("{key}.")) {
        return name.to_string();
    }
    if key == name || key.ends_with(&format!(".{name}")) {
        return key;
    }
    format!("{key}.{name}")
}

/// A second definition of a key or a table at byte `offset` of `text`: the error names the
/// key and the lines of both definitions.
fn duplicate_key(text: &str, offset: usize) -> Option<ScenarioError> {
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let line_text = text[line_start..].lines().next()?.trim();
    let second = line_of(text, offset);
    // `[box]`, `[[species]]` or `key = value`.
    let (name, header) = if let Some(h) = line_text.strip_prefix('[') {
        (
            h.trim_start_matches('[')
                .split(']')
                .next()?
                .trim()
                .to_string(),
            true,
        )
    } else {
        (line_text.split('=').next()?.trim().to_string(), false)
    };
    if name.is_empty() {
        return None;
    }
    let first = text.lines().enumerate().find_map(|(i, l)| {
        let l = l.trim();
        let same = if header {
            l.starts_with('[') && l.trim_matches(|c| c == '[' || c == ']').trim() == name
        } else {
            l.split('=').next().is_some_and(|k| k.trim() == name) && l.contains('=')
        };
        (same && i + 1 < second).then_some(i + 1)
    });
    let what = if header {
        format!("the table `[{name}]`")
    } else {
        format!("the key `{name}`")
    };
    let lines = match first {
        Some(f) => format!("on lines {f} and {second}"),
        None => format!("again on line {second}"),
    };
    let fix = if header {
        "merge them into one table"
    } else {
        "keep one"
    };
    Some(ScenarioError {
        key: name,
        message: format!("{what} is given twice, {lines}; {fix}"),
        line: Some(second),
    })
}

/// Serde's and TOML's words for types (`usize`, `f64`, `struct RawVelocity`, `i128`) in the
/// words of the scenario: "a whole number", "a number", "a table like ...".
pub(super) fn plain_words(message: &str) -> String {
    // What a value is, as serde says it ("invalid type: floating point `1.5`, ...").
    let mut m = message.to_string();
    if let Some(rest) = m.strip_prefix("invalid type: integer `")
        && let Some((value, tail)) = rest.split_once("` as i128")
    {
        return format!(
            "the whole number {value} is too large (whole numbers go up to 9223372036854775807){}",
            tail.split_once(", expected any valid TOML value")
                .map_or(String::new(), |(_, t)| t.to_string())
        );
    }
    if let Some(rest) = m.strip_prefix("invalid type: string \"")
        && let Some((value, tail)) = rest.split_once('"')
        && !value.is_empty()
        && value.bytes().all(|b| b.is_ascii_digit())
        && tail.contains("expected")
    {
        return format!(
            "the whole number {value} is too large (whole numbers go up to 9223372036854775807)"
        );
    }
    let replacements: [(&str, &str); 22] = [
        ("invalid type: floating point `", "got the number `"),
        ("invalid type: integer `", "got the whole number `"),
        ("invalid type: string ", "got the text "),
        ("invalid type: boolean `", "got `"),
        ("invalid type: sequence", "got a list"),
        ("invalid type: map", "got a table"),
        ("invalid value: integer `", "got the whole number `"),
        ("invalid value: floating point `", "got the number `"),
        (
            "expected struct RawVelocity",
            "expected a table like `{ distribution = \"maxwell_boltzmann\", temperature = 1.0 }`",
        ),
        ("expected usize", "expected a whole number, 0 or more"),
        ("expected u64", "expected a whole number, 0 or more"),
        (
            "expected u32",
            "expected a whole number from 0 to 4294967295",
        ),
        ("expected u16", "expected a whole number from 0 to 65535"),
        ("expected u8", "expected a whole number from 0 to 255"),
        ("expected i64", "expected a whole number"),
        ("expected i32", "expected a whole number"),
        ("expected f64", "expected a number"),
        ("expected f32", "expected a number"),
        ("expected a sequence", "expected a list, e.g. `[1.0, 2.0]`"),
        ("expected a boolean", "expected true or false"),
        ("expected a map", "expected a table"),
        ("expected any valid TOML value", "expected a value"),
    ];
    for (rust, words) in replacements {
        m = m.replace(rust, words);
    }
    // Any other `struct Name` or `enum Name`: a table / one of the names listed.
    for (rust, words) in [
        ("expected struct ", "expected a table"),
        (
            "expected enum ",
            "expected one of the names listed in docs/scenario.md",
        ),
    ] {
        if let Some(i) = m.find(rust) {
            let end = m[i + rust.len()..]
                .find(|c: char| !c.is_alphanumeric() && c != '_')
                .map_or(m.len(), |j| i + rust.len() + j);
            m.replace_range(i..end, words);
        }
    }
    m
}
