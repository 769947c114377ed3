//! Reading a TOML table field by field, so that every error names the field's full path and what was
//! expected, e.g. `objects[2].material.bump.scale: expected a number, got "big"`.

use crate::{Error, Result};
use glam::{Vec2, Vec3};
use toml::Value;

pub struct Fields<'a> {
    pub path: String,
    table: &'a toml::Table,
}

/// The most characters of a value an error message echoes.
const ECHO: usize = 60;

/// A value as error messages echo it: tables and arrays by their kind, strings by `quoted`.
pub fn describe(v: &Value) -> String {
    match v {
        Value::Table(_) => "a table".into(),
        Value::Array(_) => "an array".into(),
        Value::String(s) => quoted(s),
        other => other.to_string(),
    }
}

/// The first `ECHO` characters of `s`, and the length of `s` in characters where it has more.
fn head(s: &str) -> (&str, Option<usize>) {
    match s.char_indices().nth(ECHO) {
        None => (s, None),
        Some((cut, _)) => (&s[..cut], Some(s.chars().count())),
    }
}

/// A string as error messages echo it: in quotes, escaped (a newline as \n, so that the message stays one
/// line), and cut after `ECHO` characters with an ellipsis and the full length: `"xxxx…" (52428800 characters)`.
pub fn quoted(s: &str) -> String {
    match head(s) {
        (all, None) => format!("{all:?}"),
        (start, Some(n)) => {
            let shown = format!("{start:?}");
            format!("{}…\" ({n} characters)", &shown[..shown.len() - 1])
        }
    }
}

/// A message from elsewhere (the TOML parser's) with every part it quotes in backticks cut like `quoted`:
/// ``duplicate key `xxxx…` (52428800 characters)``.
pub fn clip_backquoted(message: &str) -> String {
    let (mut out, mut after) = (String::new(), String::new());
    for (i, part) in message.split('`').enumerate() {
        if i > 0 {
            out.push('`');
            out += &std::mem::take(&mut after);
        }
        match head(part) {
            (start, Some(n)) if i % 2 == 1 => {
                out += start;
                out.push('…');
                after = format!(" ({n} characters)");
            }
            _ => out += part,
        }
    }
    out + &after
}

/// A key as an error path shows it: as written when it is a bare key of at most `ECHO` characters, else
/// quoted like a TOML quoted key.
fn key_in_path(key: &str) -> String {
    let bare =
        key.len() <= ECHO && !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || "_-".contains(c));
    if bare {
        key.to_string()
    } else {
        quoted(key)
    }
}

impl<'a> Fields<'a> {
    /// The table at `path`; `known` lists the fields it may have, anything else is an error (a typo).
    pub fn new(path: impl Into<String>, value: &'a Value, known: &[&str]) -> Result<Fields<'a>> {
        let path = path.into();
        let table = value
            .as_table()
            .ok_or_else(|| Error::scene(&path, format!("expected a table, got {}", describe(value))))?;
        let fields = Fields { path, table };
        for key in table.keys() {
            if !known.contains(&key.as_str()) {
                let message = format!("unknown field (expected one of: {})", known.join(", "));
                return Err(fields.error(&key_in_path(key), message));
            }
        }
        Ok(fields)
    }

    /// A constructor's error in the scene's words: a parameter (`Error::Parameter`) named by its field's
    /// path in this table, anything else not tied to one parameter by the table's path.
    pub fn named(&self, e: Error) -> Error {
        match e {
            Error::Parameter { name, message } => Error::scene(self.at(name), message),
            Error::Invalid(m) => Error::scene(&self.path, m),
            other => other,
        }
    }

    pub fn at(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.path)
        }
    }

    pub fn get(&self, key: &str) -> Option<&'a Value> {
        self.table.get(key)
    }

    fn error(&self, key: &str, message: impl Into<String>) -> Error {
        Error::scene(self.at(key), message)
    }

    /// A table whose fields depend on its kind: any of `fields` present but not in `allowed` is an error.
    pub fn only_of_kind(&self, fields: &[&str], allowed: &[&str], kind: &str) -> Result<()> {
        match fields.iter().find(|key| self.get(key).is_some() && !allowed.contains(key)) {
            Some(key) => Err(self.error(key, format!("not a field of {kind} (it has: {})", allowed.join(", ")))),
            None => Ok(()),
        }
    }

    pub fn required<T>(&self, key: &str, v: Option<T>) -> Result<T> {
        v.ok_or_else(|| self.error(key, "missing field"))
    }

    pub fn number(&self, key: &str) -> Result<Option<f32>> {
        self.get(key).map(|v| number_value(&self.at(key), v)).transpose()
    }

    pub fn number_or(&self, key: &str, default: f32) -> Result<f32> {
        Ok(self.number(key)?.unwrap_or(default))
    }

    /// A number checked against a condition, e.g. `positive`.
    pub fn number_where(&self, key: &str, default: Option<f32>, ok: fn(f32) -> bool, what: &str) -> Result<f32> {
        let v = match (self.number(key)?, default) {
            (Some(v), _) => v,
            (None, Some(d)) => d,
            (None, None) => return Err(self.error(key, "missing field")),
        };
        if ok(v) {
            Ok(v)
        } else {
            Err(self.error(key, format!("expected {what}, got {v}")))
        }
    }

    pub fn integer_where(&self, key: &str, default: usize, min: usize, max: usize) -> Result<usize> {
        match self.get(key) {
            None => Ok(default),
            Some(Value::Integer(i)) if (min as i64..=max as i64).contains(i) => Ok(*i as usize),
            Some(v) => Err(self.error(key, format!("expected an integer from {min} to {max}, got {}", describe(v)))),
        }
    }

    pub fn string(&self, key: &str) -> Result<Option<&'a str>> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::String(s)) => Ok(Some(s.as_str())),
            Some(v) => Err(self.error(key, format!("expected a string, got {}", describe(v)))),
        }
    }

    /// One of a fixed set of names.
    pub fn choice<T: Copy>(&self, key: &str, default: T, options: &[(&str, T)]) -> Result<T> {
        let Some(s) = self.string(key)? else { return Ok(default) };
        options.iter().find(|(name, _)| *name == s).map(|&(_, v)| v).ok_or_else(|| {
            let names: Vec<String> = options.iter().map(|(n, _)| format!("\"{n}\"")).collect();
            self.error(key, format!("expected one of {}, got {}", names.join(", "), quoted(s)))
        })
    }

    pub fn boolean(&self, key: &str, default: bool) -> Result<bool> {
        match self.get(key) {
            None => Ok(default),
            Some(Value::Boolean(b)) => Ok(*b),
            Some(v) => Err(self.error(key, format!("expected true or false, got {}", describe(v)))),
        }
    }

    pub fn vec3(&self, key: &str) -> Result<Option<Vec3>> {
        self.get(key).map(|v| vec3_value(&self.at(key), v)).transpose()
    }

    pub fn vec2(&self, key: &str) -> Result<Option<Vec2>> {
        let Some(v) = self.get(key) else { return Ok(None) };
        let a = numbers(&self.at(key), v, 2)?;
        Ok(Some(Vec2::new(a[0], a[1])))
    }

    /// An array of tables (`[[object]]`), empty when absent.
    pub fn tables(&self, key: &str) -> Result<&'a [Value]> {
        match self.get(key) {
            None => Ok(&[]),
            Some(Value::Array(a)) => Ok(a.as_slice()),
            Some(v) => Err(self.error(key, format!("expected an array of tables, got {}", describe(v)))),
        }
    }
}

/// A finite number (integers are accepted).
pub fn number_value(path: &str, v: &Value) -> Result<f32> {
    let x = match v {
        Value::Float(f) => *f,
        Value::Integer(i) => *i as f64,
        other => return Err(Error::scene(path, format!("expected a number, got {}", describe(other)))),
    };
    if !x.is_finite() {
        return Err(Error::scene(path, format!("expected a finite number, got {x}")));
    }
    if x.abs() > f32::MAX as f64 {
        return Err(Error::scene(path, format!("expected a number of magnitude at most {:e}, got {x:e}", f32::MAX)));
    }
    Ok(x as f32)
}

/// An array of exactly `n` finite numbers.
pub fn numbers(path: &str, v: &Value, n: usize) -> Result<Vec<f32>> {
    let Value::Array(a) = v else {
        return Err(Error::scene(path, format!("expected an array of {n} numbers, got {}", describe(v))));
    };
    if a.len() != n {
        return Err(Error::scene(path, format!("expected an array of {n} numbers, got {} elements", a.len())));
    }
    a.iter().enumerate().map(|(i, x)| number_value(&format!("{path}[{i}]"), x)).collect()
}

pub fn vec3_value(path: &str, v: &Value) -> Result<Vec3> {
    let a = numbers(path, v, 3)?;
    Ok(Vec3::new(a[0], a[1], a[2]))
}

/// An array of `n` points [x, y, z].
pub fn points(path: &str, v: &Value, n: usize) -> Result<Vec<Vec3>> {
    let Value::Array(a) = v else {
        return Err(Error::scene(path, format!("expected an array of {n} points [x, y, z], got {}", describe(v))));
    };
    if a.len() != n {
        return Err(Error::scene(path, format!("expected {n} points [x, y, z], got {}", a.len())));
    }
    a.iter().enumerate().map(|(i, p)| vec3_value(&format!("{path}[{i}]"), p)).collect()
}
