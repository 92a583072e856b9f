//! Arrays longer than their key takes. serde fills a fixed-length array (`[f64; 3]`, a
//! `[f, value]` row) from the first entries and the TOML reader does not object to more, so
//! `position_m = [1, 0, 0, 5]` would load as `[1, 0, 0]`. The scene as read is serialized
//! back and compared with the text: an array of the text longer than its round trip lost
//! entries. Fields that do not round-trip (defaults, aliases, enums written another way) are
//! not compared; every fixed-length array does.

use super::{Locator, SceneFile};
use crate::error::SpecError;
use toml::Value;

/// Refuses the first array of `text` holding more entries than its key takes.
pub(super) fn check(loc: &Locator, text: &str, file: &SceneFile) -> Result<(), SpecError> {
    let (Ok(written), Ok(read)) = (text.parse::<toml::Table>(), toml::Value::try_from(file)) else {
        return Ok(());
    };
    compare(loc, &Value::Table(written), &read, String::new())
}

fn compare(loc: &Locator, written: &Value, read: &Value, path: String) -> Result<(), SpecError> {
    match (written, read) {
        (Value::Table(w), Value::Table(r)) => {
            for (key, wv) in w {
                if let Some(rv) = r.get(key) {
                    let p = if path.is_empty() {
                        key.clone()
                    } else {
                        format!("{path}.{key}")
                    };
                    compare(loc, wv, rv, p)?;
                }
            }
            Ok(())
        }
        (Value::Array(w), Value::Array(r)) => {
            if w.len() > r.len() && !r.is_empty() {
                return Err(loc.err(
                    &path,
                    format!(
                        "has {} entries, but takes {}: the extra entries would be ignored",
                        w.len(),
                        r.len()
                    ),
                ));
            }
            for (i, (wv, rv)) in w.iter().zip(r).enumerate() {
                compare(loc, wv, rv, format!("{path}[{i}]"))?;
            }
            Ok(())
        }
        _ => Ok(()),
    }
}
