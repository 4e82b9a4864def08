//! Reading typed fields out of a parsed TOML document, each error with its line and path.

use crate::error::{num, Error, Result};
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// The document being read: its name and text (for line numbers), and whether it is a
/// world's structure that a snapshot is restored onto (its balls are taken where the run left
/// them: [`super::parse_structure`]).
pub(super) struct Doc<'a> {
    pub file: &'a str,
    pub text: &'a str,
    pub restoring: bool,
}

/// A table of the document with where it is and its path (`particles[2]`, empty at the top).
#[derive(Clone, Copy)]
pub(super) struct Table<'t, 'i> {
    pub table: &'t DeTable<'i>,
    pub at: usize,
    pub path: &'t str,
}

impl Doc<'_> {
    /// The 1-based line of byte `at`.
    pub fn line(&self, at: usize) -> usize {
        let at = at.min(self.text.len());
        self.text.as_bytes()[..at].iter().filter(|b| **b == b'\n').count() + 1
    }

    /// An error at `span` about `field`.
    pub fn err(&self, at: usize, field: &str, reason: impl Into<String>) -> Error {
        Error::SceneFile {
            file: self.file.into(),
            line: self.line(at),
            field: field.into(),
            reason: reason.into(),
        }
    }

    /// An engine error (a world's check) placed at `span`, under `field`.
    pub fn engine(&self, at: usize, field: &str, e: Error) -> Error {
        self.err(at, field, e.to_string())
    }

    /// Refuses any key of `t` not in `known`.
    pub fn keys(&self, t: Table<'_, '_>, known: &[&str]) -> Result<()> {
        for key in t.table.keys() {
            if !known.contains(&key.get_ref().as_ref()) {
                return Err(self.err(
                    key.span().start,
                    &join(t.path, key.get_ref()),
                    format!("unknown key; valid keys here: {}", known.join(", ")),
                ));
            }
        }
        Ok(())
    }

    /// The value of `key` with its span and path, if present.
    fn get<'t, 'i>(&self, t: Table<'t, 'i>, key: &str) -> Option<(&'t Spanned<DeValue<'i>>, String)> {
        t.table.get(key).map(|v| (v, join(t.path, key)))
    }

    /// A number (TOML float or integer; `inf`, `-inf` allowed, `nan` refused).
    pub fn f64(&self, t: Table<'_, '_>, key: &str) -> Result<Option<f64>> {
        let Some((v, path)) = self.get(t, key) else { return Ok(None) };
        self.number(v, &path).map(Some)
    }

    /// A required number.
    pub fn f64_req(&self, t: Table<'_, '_>, key: &str) -> Result<f64> {
        self.f64(t, key)?.ok_or_else(|| self.missing(t, key, "a number"))
    }

    fn number(&self, v: &Spanned<DeValue<'_>>, path: &str) -> Result<f64> {
        let x = match v.get_ref() {
            DeValue::Float(f) => f.as_str().replace('_', "").parse::<f64>().ok(),
            DeValue::Integer(i) => {
                let digits = i.as_str().replace('_', "");
                match i64::from_str_radix(&digits, i.radix()) {
                    Ok(n) => Some(n as f64),
                    // Past 64 bits (99999999999999999999): the number it is, as a float; a
                    // non-decimal one that long is refused by name.
                    Err(_) if i.radix() == 10 => digits.parse::<f64>().ok(),
                    Err(_) => {
                        return Err(self.err(
                            v.span().start,
                            path,
                            format!("= {i}: a hexadecimal, octal or binary number must fit in 64 bits"),
                        ))
                    }
                }
            }
            other => {
                return Err(self.err(
                    v.span().start,
                    path,
                    format!("is {}: must be a number", other.type_str()),
                ))
            }
        };
        match x {
            Some(x) if !x.is_nan() => Ok(x),
            _ => Err(self.err(v.span().start, path, "must be a number (nan is not one)")),
        }
    }

    /// A whole number >= 0 (an index or a count).
    pub fn index(&self, t: Table<'_, '_>, key: &str) -> Result<Option<usize>> {
        let Some((v, path)) = self.get(t, key) else { return Ok(None) };
        match v.get_ref() {
            DeValue::Integer(i) => {
                let n = i64::from_str_radix(&i.as_str().replace('_', ""), i.radix()).ok();
                n.and_then(|n| usize::try_from(n).ok()).map(Some).ok_or_else(|| {
                    self.err(v.span().start, &path, format!("= {i}: must be a whole number >= 0"))
                })
            }
            other => Err(self.err(
                v.span().start,
                &path,
                format!("is {}: must be a whole number >= 0", other.type_str()),
            )),
        }
    }

    /// A required whole number >= 0.
    pub fn index_req(&self, t: Table<'_, '_>, key: &str) -> Result<usize> {
        self.index(t, key)?.ok_or_else(|| self.missing(t, key, "a particle index"))
    }

    /// A string.
    pub fn str<'t>(&self, t: Table<'t, '_>, key: &str) -> Result<Option<&'t str>> {
        let Some((v, path)) = self.get(t, key) else { return Ok(None) };
        match v.get_ref() {
            DeValue::String(s) => Ok(Some(s.as_ref())),
            other => {
                Err(self.err(v.span().start, &path, format!("is {}: must be a string", other.type_str())))
            }
        }
    }

    /// A boolean.
    pub fn bool(&self, t: Table<'_, '_>, key: &str) -> Result<Option<bool>> {
        let Some((v, path)) = self.get(t, key) else { return Ok(None) };
        match v.get_ref() {
            DeValue::Boolean(b) => Ok(Some(*b)),
            other => Err(self.err(
                v.span().start,
                &path,
                format!("is {}: must be true or false", other.type_str()),
            )),
        }
    }

    /// An array of numbers, of length `len` when given.
    pub fn vec(&self, t: Table<'_, '_>, key: &str, len: Option<usize>) -> Result<Option<Vec<f64>>> {
        let Some((v, path)) = self.get(t, key) else { return Ok(None) };
        let DeValue::Array(items) = v.get_ref() else {
            return Err(self.err(
                v.span().start,
                &path,
                format!("is {}: must be an array of numbers", v.get_ref().type_str()),
            ));
        };
        let out = items
            .iter()
            .enumerate()
            .map(|(k, item)| self.number(item, &format!("{path}[{k}]")))
            .collect::<Result<Vec<f64>>>()?;
        match len {
            Some(n) if out.len() != n => {
                Err(self.err(v.span().start, &path, format!("has {} numbers: must have {n}", out.len())))
            }
            _ => Ok(Some(out)),
        }
    }

    /// A required array of `len` numbers.
    pub fn vec_req(&self, t: Table<'_, '_>, key: &str, len: usize) -> Result<Vec<f64>> {
        self.vec(t, key, Some(len))?
            .ok_or_else(|| self.missing(t, key, &format!("an array of {len} numbers")))
    }

    /// An array of arrays of numbers, each of length `len` (mesh vertices and triangles).
    pub fn rows(&self, t: Table<'_, '_>, key: &str, len: usize) -> Result<Option<Vec<Vec<f64>>>> {
        let Some((v, path)) = self.get(t, key) else { return Ok(None) };
        let DeValue::Array(items) = v.get_ref() else {
            return Err(self.err(
                v.span().start,
                &path,
                format!("is {}: must be an array of arrays", v.get_ref().type_str()),
            ));
        };
        let mut out = Vec::new();
        for (k, item) in items.iter().enumerate() {
            let p = format!("{path}[{k}]");
            let DeValue::Array(row) = item.get_ref() else {
                return Err(self.err(
                    item.span().start,
                    &p,
                    format!("is {}: must be an array of {len} numbers", item.get_ref().type_str()),
                ));
            };
            let row = row
                .iter()
                .enumerate()
                .map(|(j, x)| self.number(x, &format!("{p}[{j}]")))
                .collect::<Result<Vec<f64>>>()?;
            if row.len() != len {
                return Err(self.err(
                    item.span().start,
                    &p,
                    format!("has {} numbers: must have {len}", row.len()),
                ));
            }
            out.push(row);
        }
        Ok(Some(out))
    }

    /// A sub-table.
    pub fn table<'t, 'i>(&self, t: Table<'t, 'i>, key: &str) -> Result<Option<(&'t DeTable<'i>, usize)>> {
        let Some((v, path)) = self.get(t, key) else { return Ok(None) };
        match v.get_ref() {
            DeValue::Table(inner) => Ok(Some((inner, v.span().start))),
            other => {
                Err(self.err(v.span().start, &path, format!("is {}: must be a table", other.type_str())))
            }
        }
    }

    /// An array of tables (`[[particles]]`), each with its span.
    pub fn tables<'t, 'i>(&self, t: Table<'t, 'i>, key: &str) -> Result<Vec<(&'t DeTable<'i>, usize)>> {
        let Some((v, path)) = self.get(t, key) else { return Ok(Vec::new()) };
        let DeValue::Array(items) = v.get_ref() else {
            return Err(self.err(
                v.span().start,
                &path,
                format!("is {}: must be an array of tables ([[{key}]])", v.get_ref().type_str()),
            ));
        };
        items
            .iter()
            .enumerate()
            .map(|(k, item)| match item.get_ref() {
                DeValue::Table(inner) => Ok((inner, item.span().start)),
                other => Err(self.err(
                    item.span().start,
                    &format!("{path}[{k}]"),
                    format!("is {}: must be a table", other.type_str()),
                )),
            })
            .collect()
    }

    fn missing(&self, t: Table<'_, '_>, key: &str, what: &str) -> Error {
        self.err(t.at, &join(t.path, key), format!("is missing: must be {what}"))
    }

    /// An error for a number out of its range.
    pub fn range(&self, t: Table<'_, '_>, key: &str, x: f64, expected: &str) -> Error {
        let at = t.table.get(key).map_or(t.at, |v| v.span().start);
        self.err(at, &join(t.path, key), format!("= {}: must be {expected}", num(x)))
    }
}

/// `path.key`, or `key` at the top.
pub(super) fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}
