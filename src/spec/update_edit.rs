//! Writes updated parameter values into scene text with `toml_edit`, so that comments, layout
//! and line numbers stay as written. A value may carry a note, appended as a trailing comment
//! of its key's line (for an element of an inline array, of the array's line: a comment inside
//! the brackets would end the line early).

use super::split_path;
use toml_edit::{DocumentMut, Item, Value};

/// One value to write: the key in `a[0].b[4]` form, the number, and an optional note.
pub struct Written {
    pub key: String,
    pub value: f64,
    pub note: Option<String>,
}

/// `text` with every value of `edits` written in (as floats), notes appended.
pub fn with_values(text: &str, edits: &[Written]) -> Result<String, String> {
    let mut doc: DocumentMut = text.parse().map_err(|e| format!("{e}"))?;
    for e in edits {
        let slot = value_mut(doc.as_item_mut(), &e.key, false)?;
        let decor = slot.decor().clone();
        *slot = Value::from(e.value);
        *slot.decor_mut() = decor;
    }
    for e in edits {
        if let Some(note) = &e.note {
            annotate(value_mut(doc.as_item_mut(), &e.key, true)?, note);
        }
    }
    Ok(doc.to_string())
}

/// Appends `note` to the value's trailing comment, or starts one.
fn annotate(v: &mut Value, note: &str) {
    let old = v
        .decor()
        .suffix()
        .and_then(|s| s.as_str())
        .unwrap_or("")
        .trim_end()
        .to_string();
    let new = if old.contains('#') {
        format!("{old}; {note}")
    } else {
        format!("{old} # {note}")
    };
    v.decor_mut().set_suffix(new);
}

/// The value at `key`; with `owner`, the value of the key's line (the array holding an
/// indexed element rather than the element).
fn value_mut<'a>(root: &'a mut Item, key: &str, owner: bool) -> Result<&'a mut Value, String> {
    let parts = split_path(key);
    let last = parts.len().saturating_sub(1);
    let mut item = root;
    for (n, (name, index)) in parts.iter().enumerate() {
        item = item
            .get_mut(name.as_str())
            .ok_or_else(|| format!("`{key}`: no key `{name}` in the scene"))?;
        if let Some(i) = index
            && !(owner && n == last)
        {
            item = item
                .get_mut(*i)
                .ok_or_else(|| format!("`{key}`: `{name}` has no element {i}"))?;
        }
    }
    item.as_value_mut()
        .ok_or_else(|| format!("`{key}` is not a value"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_written_and_comments_kept() {
        let text = "# scene\n[[spring]]\nnodes = [1, 2] # the clamp\nstiffness = [1.0, 2.0, 3.0] # guess\n\n[[mass]]\nmass_kg = 5\n";
        let edits = [
            Written {
                key: "spring[0].stiffness[1]".into(),
                value: 2.5,
                note: Some("updated".into()),
            },
            Written {
                key: "mass[0].mass_kg".into(),
                value: 4.25,
                note: Some("updated too".into()),
            },
        ];
        let out = with_values(text, &edits).unwrap();
        assert!(out.contains("# scene\n"), "{out}");
        assert!(out.contains("nodes = [1, 2] # the clamp\n"), "{out}");
        assert!(
            out.contains("stiffness = [1.0, 2.5, 3.0] # guess; updated\n"),
            "{out}"
        );
        assert!(out.contains("mass_kg = 4.25 # updated too\n"), "{out}");
    }
}
