//! Finite-number checks for every writer: no NaN or infinity leaves the program.
//!
//! serde_json writes a NaN or an infinity as `null`, which a reader cannot tell from an absent
//! optional value, so the check walks the typed value (a serde serializer that only looks at
//! numbers) before it is printed, and names the JSON path of the first non-finite number.
//! CSV text is checked cell by cell, since Rust formats a NaN as `NaN` and infinities as `inf`.

use crate::error::Error;
use serde::ser::{self, Serialize};
use std::fmt;

/// Checks that `value` serialises with finite numbers only; `what` names the output (a file
/// or "JSON output") in the error.
pub fn check_json<T: Serialize + ?Sized>(value: &T, what: &str) -> Result<(), Error> {
    let mut walker = Walker { path: Vec::new() };
    match value.serialize(&mut walker) {
        Ok(()) => Ok(()),
        Err(Found(msg)) => Err(Error::Other(format!(
            "{what}: {msg}; a non-finite number is never written (check the inputs for values out of range)"
        ))),
    }
}

/// Checks the typed values a `serde_json::json!` document is built from, before it is built:
/// json! turns a non-finite number into `null`, which the check of the finished document can
/// no longer tell from an absent value. `what` names the output.
pub fn check_sources<T: Serialize + ?Sized>(sources: &T, what: &str) -> Result<(), Error> {
    check_json(sources, what)
}

/// Checks every cell of a CSV text; the error names the file, the line and the column header.
pub fn check_csv(what: &str, text: &str) -> Result<(), Error> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .map(|h| h.split(',').collect())
        .unwrap_or_default();
    for (i, line) in lines.enumerate() {
        for (j, cell) in line.split(',').enumerate() {
            if is_non_finite_text(cell) {
                let column = header.get(j).copied().unwrap_or("?").trim();
                return Err(Error::Other(format!(
                    "{what}: line {}, column `{column}`: the value is `{}`; a non-finite number is never written (check the inputs for values out of range)",
                    i + 2,
                    cell.trim()
                )));
            }
        }
    }
    Ok(())
}

/// A cell that Rust's float formatting produced from a NaN or an infinity.
fn is_non_finite_text(cell: &str) -> bool {
    let c = cell.trim().trim_matches('"');
    let c = c.strip_prefix(['-', '+']).unwrap_or(c);
    matches!(c, "NaN" | "nan" | "inf" | "Inf" | "infinity" | "Infinity")
}

#[derive(Debug)]
struct Found(String);

impl fmt::Display for Found {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Found {}

impl ser::Error for Found {
    // A serialisation failure that is not a non-finite number (a custom Serialize impl) is
    // reported as is: the JSON writer itself would report it too.
    fn custom<T: fmt::Display>(msg: T) -> Self {
        Found(msg.to_string())
    }
}

/// Walks a value, keeping the path of keys and indices to the current number.
struct Walker {
    path: Vec<String>,
}

impl Walker {
    fn float(&self, v: f64) -> Result<(), Found> {
        if v.is_finite() {
            return Ok(());
        }
        let path = if self.path.is_empty() {
            "(top level)".to_string()
        } else {
            self.path.join("")
        };
        Err(Found(format!("`{path}` is {v}")))
    }
}

type R = Result<(), Found>;

impl<'a> ser::Serializer for &'a mut Walker {
    type Ok = ();
    type Error = Found;
    type SerializeSeq = Compound<'a>;
    type SerializeTuple = Compound<'a>;
    type SerializeTupleStruct = Compound<'a>;
    type SerializeTupleVariant = Compound<'a>;
    type SerializeMap = Compound<'a>;
    type SerializeStruct = Compound<'a>;
    type SerializeStructVariant = Compound<'a>;

    fn serialize_bool(self, _: bool) -> R {
        Ok(())
    }
    fn serialize_i8(self, _: i8) -> R {
        Ok(())
    }
    fn serialize_i16(self, _: i16) -> R {
        Ok(())
    }
    fn serialize_i32(self, _: i32) -> R {
        Ok(())
    }
    fn serialize_i64(self, _: i64) -> R {
        Ok(())
    }
    fn serialize_u8(self, _: u8) -> R {
        Ok(())
    }
    fn serialize_u16(self, _: u16) -> R {
        Ok(())
    }
    fn serialize_u32(self, _: u32) -> R {
        Ok(())
    }
    fn serialize_u64(self, _: u64) -> R {
        Ok(())
    }
    fn serialize_f32(self, v: f32) -> R {
        self.float(v as f64)
    }
    fn serialize_f64(self, v: f64) -> R {
        self.float(v)
    }
    fn serialize_char(self, _: char) -> R {
        Ok(())
    }
    fn serialize_str(self, _: &str) -> R {
        Ok(())
    }
    fn serialize_bytes(self, _: &[u8]) -> R {
        Ok(())
    }
    fn serialize_none(self) -> R {
        Ok(())
    }
    fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> R {
        v.serialize(self)
    }
    fn serialize_unit(self) -> R {
        Ok(())
    }
    fn serialize_unit_struct(self, _: &'static str) -> R {
        Ok(())
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, _: &'static str) -> R {
        Ok(())
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(self, _: &'static str, v: &T) -> R {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        v: &T,
    ) -> R {
        self.path.push(format!(".{variant}"));
        v.serialize(&mut *self)?;
        self.path.pop();
        Ok(())
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Compound<'a>, Found> {
        Ok(Compound::new(self))
    }
    fn serialize_tuple(self, _: usize) -> Result<Compound<'a>, Found> {
        Ok(Compound::new(self))
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Compound<'a>, Found> {
        Ok(Compound::new(self))
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Compound<'a>, Found> {
        Ok(Compound::new(self))
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Compound<'a>, Found> {
        Ok(Compound::new(self))
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Compound<'a>, Found> {
        Ok(Compound::new(self))
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Compound<'a>, Found> {
        Ok(Compound::new(self))
    }
}

/// One array, tuple, map or struct being walked: its elements get `[i]` or `.key` paths.
struct Compound<'a> {
    walker: &'a mut Walker,
    index: usize,
    /// The last map key, rendered, for the value that follows it.
    key: String,
}

impl<'a> Compound<'a> {
    fn new(walker: &'a mut Walker) -> Self {
        Compound {
            walker,
            index: 0,
            key: String::new(),
        }
    }

    fn element<T: Serialize + ?Sized>(&mut self, v: &T) -> R {
        self.walker.path.push(format!("[{}]", self.index));
        self.index += 1;
        v.serialize(&mut *self.walker)?;
        self.walker.path.pop();
        Ok(())
    }

    fn field<T: Serialize + ?Sized>(&mut self, key: &str, v: &T) -> R {
        self.walker.path.push(format!(".{key}"));
        v.serialize(&mut *self.walker)?;
        self.walker.path.pop();
        Ok(())
    }
}

impl ser::SerializeSeq for Compound<'_> {
    type Ok = ();
    type Error = Found;
    fn serialize_element<T: Serialize + ?Sized>(&mut self, v: &T) -> R {
        self.element(v)
    }
    fn end(self) -> R {
        Ok(())
    }
}

impl ser::SerializeTuple for Compound<'_> {
    type Ok = ();
    type Error = Found;
    fn serialize_element<T: Serialize + ?Sized>(&mut self, v: &T) -> R {
        self.element(v)
    }
    fn end(self) -> R {
        Ok(())
    }
}

impl ser::SerializeTupleStruct for Compound<'_> {
    type Ok = ();
    type Error = Found;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, v: &T) -> R {
        self.element(v)
    }
    fn end(self) -> R {
        Ok(())
    }
}

impl ser::SerializeTupleVariant for Compound<'_> {
    type Ok = ();
    type Error = Found;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, v: &T) -> R {
        self.element(v)
    }
    fn end(self) -> R {
        Ok(())
    }
}

impl ser::SerializeMap for Compound<'_> {
    type Ok = ();
    type Error = Found;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, k: &T) -> R {
        // Map keys are strings or integers in every output; render them for the path.
        self.key = serde_json::to_string(k)
            .map(|s| s.trim_matches('"').to_string())
            .unwrap_or_else(|_| "?".into());
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> R {
        let key = std::mem::take(&mut self.key);
        self.field(&key, v)
    }
    fn end(self) -> R {
        Ok(())
    }
}

impl ser::SerializeStruct for Compound<'_> {
    type Ok = ();
    type Error = Found;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, key: &'static str, v: &T) -> R {
        self.field(key, v)
    }
    fn end(self) -> R {
        Ok(())
    }
}

impl ser::SerializeStructVariant for Compound<'_> {
    type Ok = ();
    type Error = Found;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, key: &'static str, v: &T) -> R {
        self.field(key, v)
    }
    fn end(self) -> R {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[derive(serde::Serialize)]
    struct Inner {
        q: f64,
        absent: Option<f64>,
    }

    #[derive(serde::Serialize)]
    struct Outer {
        name: String,
        modes: Vec<Inner>,
    }

    #[test]
    fn finite_values_and_absent_options_pass() {
        let v = Outer {
            name: "a".into(),
            modes: vec![Inner {
                q: 1.5,
                absent: None,
            }],
        };
        check_json(&v, "out").unwrap();
    }

    #[test]
    fn nan_is_reported_with_its_json_path() {
        let v = Outer {
            name: "a".into(),
            modes: vec![
                Inner {
                    q: 1.0,
                    absent: None,
                },
                Inner {
                    q: f64::NAN,
                    absent: None,
                },
            ],
        };
        let e = check_json(&v, "sine.json").unwrap_err().to_string();
        assert!(
            e.contains("sine.json") && e.contains("`.modes[1].q` is NaN"),
            "{e}"
        );
    }

    #[test]
    fn infinity_inside_a_map_and_an_option_is_reported() {
        let mut m = BTreeMap::new();
        m.insert("fs", Some(f64::INFINITY));
        let e = check_json(&m, "out").unwrap_err().to_string();
        assert!(e.contains("`.fs` is inf"), "{e}");
    }

    /// What a json! document would print as `null` is refused in its typed sources: the
    /// tuple's second element, a list whose second value is NaN (serde_json's own `to_value`
    /// makes that a `null`, the reason the sources are checked).
    #[test]
    fn a_nan_in_the_sources_of_a_json_document_is_refused() {
        let sources = (1.0, vec![2.0, f64::NAN]);
        assert_eq!(
            serde_json::to_value(&sources).unwrap()[1][1],
            serde_json::Value::Null
        );
        let e = check_sources(&sources, "psd JSON output")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("psd JSON output") && e.contains("[1][1]") && e.contains("NaN"),
            "{e}"
        );
    }

    #[test]
    fn csv_cells_are_checked_with_line_and_column() {
        check_csv("frf.csv", "f,h\n1,2.5e-3\n").unwrap();
        let e = check_csv("frf.csv", "f,h\n1,2\n2,NaN\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("frf.csv: line 3, column `h`"), "{e}");
        let e = check_csv("x.csv", "a\n-inf\n").unwrap_err().to_string();
        assert!(e.contains("line 2, column `a`"), "{e}");
    }
}
