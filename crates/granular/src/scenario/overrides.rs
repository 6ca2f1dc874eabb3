//! `--set KEY=VALUE` overrides, applied to the TOML tree before validation so that an
//! override is checked exactly like the file.

use super::ScenarioError;
use super::spans::Segment;

/// Applies one `KEY=VALUE` override, e.g. `collisions.restitution=0.9`,
/// `species[1].mass=4` or `species.1.mass=4`. The value is read as a TOML value (number,
/// boolean, array, inline table), or as a string when it is not one.
pub(crate) fn apply_override(
    table: &mut toml::Table,
    assignment: &str,
) -> Result<(), ScenarioError> {
    let (key, raw) = assignment.split_once('=').ok_or_else(|| ScenarioError {
        key: assignment.to_string(),
        message: "an override must look like KEY=VALUE, e.g. collisions.restitution=0.9".into(),
        line: None,
    })?;
    let key = key.trim();
    let value = parse_value(raw.trim());
    let parts: Vec<String> = super::spans::parse_path(key)
        .map_err(|m| ScenarioError {
            key: key.to_string(),
            message: format!("{m} (in --set {assignment})"),
            line: None,
        })?
        .into_iter()
        .map(|s| match s {
            Segment::Key(k) => k,
            Segment::Index(i) => i.to_string(),
        })
        .collect();
    let bad = |msg: String| ScenarioError {
        key: key.to_string(),
        message: msg,
        line: None,
    };
    let n = parts.len();
    if n == 1 {
        table.insert(parts[0].clone(), value);
        return Ok(());
    }
    let mut node: &mut toml::Value = table
        .entry(parts[0].clone())
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    for (depth, part) in parts.iter().enumerate().skip(1) {
        let last = depth + 1 == n;
        node = match node {
            toml::Value::Table(t) => {
                if last {
                    t.insert(part.clone(), value);
                    return Ok(());
                }
                t.entry(part.clone())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            }
            toml::Value::Array(a) => {
                let i: usize = part
                    .parse()
                    .map_err(|_| bad(format!("`{part}` is not an index into an array")))?;
                let len = a.len();
                let slot = a.get_mut(i).ok_or_else(|| {
                    bad(format!(
                        "index {i} is out of range (the array has {len} entries)"
                    ))
                })?;
                if last {
                    *slot = value;
                    return Ok(());
                }
                slot
            }
            _ => {
                return Err(bad(format!(
                    "`{part}` is inside a value that is not a table"
                )));
            }
        };
    }
    Ok(())
}

fn parse_value(raw: &str) -> toml::Value {
    let doc = format!("v = {raw}");
    match toml::from_str::<toml::Table>(&doc) {
        Ok(mut t) => t
            .remove("v")
            .unwrap_or_else(|| toml::Value::String(raw.to_string())),
        Err(_) => toml::Value::String(raw.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_reach_nested_keys_and_array_entries() {
        let mut t: toml::Table = toml::from_str("[collisions]\nrestitution = 1.0\n[[species]]\nname = \"a\"\nmass = 1.0\n[[species]]\nname = \"b\"\nmass = 1.0\n").unwrap();
        apply_override(&mut t, "collisions.restitution=0.9").unwrap();
        apply_override(&mut t, "species[1].mass=4").unwrap();
        apply_override(&mut t, "species.0.name=light").unwrap();
        assert_eq!(t["collisions"]["restitution"].as_float(), Some(0.9));
        assert_eq!(t["species"][1]["mass"].as_integer(), Some(4));
        assert_eq!(t["species"][0]["name"].as_str(), Some("light"));
        assert!(apply_override(&mut t, "species[5].mass=4").is_err());
        assert!(apply_override(&mut t, "nonsense").is_err());
        for bad in [
            "species[0.mass=2",
            "species[x].mass=2",
            "species[0]mass=2",
            ".mass=2",
            "=2",
            "species..mass=2",
            "species[0].ma ss=2",
        ] {
            let e = apply_override(&mut t, bad).expect_err(bad);
            assert!(!e.message.is_empty(), "{bad}");
        }
    }
}
