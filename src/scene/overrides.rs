//! `--set dotted.path=value` overrides applied to a parsed TOML table before deserialisation.

use crate::error::SetError;
use toml::{Table, Value};

/// Sets `path` (dot-separated keys, creating tables as needed) to `value` in `table`.
///
/// `value` is parsed as a TOML value (`0.5`, `true`, `"text"`, `[1, 2]`, `{ r = 0.9 }`); if
/// that fails it is taken as a bare string (so `--set plate.scheme=stormer-verlet` works).
pub fn apply(table: &mut Table, assignment: &str) -> Result<(), SetError> {
    let (path, raw) = assignment
        .split_once('=')
        .ok_or_else(|| SetError::NoValue {
            assignment: assignment.to_string(),
        })?;
    let keys: Vec<&str> = path.trim().split('.').collect();
    if keys.iter().any(|k| k.is_empty()) {
        return Err(SetError::EmptyKey {
            assignment: assignment.to_string(),
            path: path.to_string(),
        });
    }
    let value = parse_value(raw.trim());
    let mut cur = table;
    for (i, key) in keys.iter().enumerate() {
        if i + 1 == keys.len() {
            cur.insert((*key).to_string(), value);
            return Ok(());
        }
        let entry = cur
            .entry((*key).to_string())
            .or_insert_with(|| Value::Table(Table::new()));
        cur = match entry {
            Value::Table(t) => t,
            other => {
                return Err(SetError::NotATable {
                    assignment: assignment.to_string(),
                    prefix: keys[..=i].join("."),
                    kind: other.type_str(),
                })
            }
        };
    }
    unreachable!("the loop returns at the last key")
}

fn parse_value(raw: &str) -> Value {
    let doc = format!("v = {raw}");
    match toml::from_str::<Table>(&doc) {
        Ok(mut t) => t
            .remove("v")
            .unwrap_or_else(|| Value::String(raw.to_string())),
        Err(_) => Value::String(raw.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_nested_values_of_each_type() {
        let mut t: Table = toml::from_str("[a]\nb = 1\n").unwrap();
        apply(&mut t, "a.b=2.5").unwrap();
        apply(&mut t, "a.c.d=stormer-verlet").unwrap();
        apply(&mut t, "e=[1, 2]").unwrap();
        assert_eq!(t["a"]["b"].as_float(), Some(2.5));
        assert_eq!(t["a"]["c"]["d"].as_str(), Some("stormer-verlet"));
        assert_eq!(t["e"].as_array().map(|a| a.len()), Some(2));
        assert!(apply(&mut t, "a.b.x=1")
            .unwrap_err()
            .to_string()
            .contains("a.b"));
        assert!(apply(&mut t, "nothing").is_err());
        assert!(apply(&mut t, "a..b=1").is_err());
    }
}
