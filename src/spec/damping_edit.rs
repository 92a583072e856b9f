//! Writes identified damping into a scene's `[damping]` as a frequency table, editing the
//! text with `toml_edit` so that every comment and every other key stays as written. Each
//! table point carries a comment naming where it came from; a `q` or `zeta` the table replaces
//! is kept as a comment above it.

use toml_edit::{Array, DocumentMut, Item, Value};

/// One identified mode: frequency (Hz), damping ratio and a one-line note of its source.
pub struct IdentifiedDamping {
    pub frequency_hz: f64,
    pub zeta: f64,
    pub source: String,
}

/// `text` with `[damping]` holding `table = [[f, ζ], …]` from `points` (ascending in f,
/// distinct), `q`, `zeta` and `table` replaced; `interpolation` and `modes` are left alone.
pub fn with_identified_damping(text: &str, points: &[IdentifiedDamping]) -> Result<String, String> {
    if points.is_empty() {
        return Err("no identified mode to write".into());
    }
    if let Some(w) = points
        .windows(2)
        .find(|w| w[1].frequency_hz <= w[0].frequency_hz)
    {
        return Err(format!(
            "identified frequencies must increase: {} Hz follows {} Hz",
            w[1].frequency_hz, w[0].frequency_hz
        ));
    }
    let mut doc: DocumentMut = text.parse().map_err(|e| format!("{e}"))?;
    let damping = damping_table(&mut doc)?;
    let mut replaced = String::new();
    for key in ["q", "zeta", "table"] {
        if let Some(old) = damping.remove(key) {
            let old = old.to_string();
            let old = old.trim().replace('\n', " ");
            replaced.push_str(&format!(
                "# replaced by `satqual ema --write-damping`: {key} = {old}\n"
            ));
        }
    }
    let mut table = Array::new();
    for p in points {
        let mut pair = Array::new();
        pair.push(round(p.frequency_hz, 4));
        pair.push(round(p.zeta, 6));
        push_annotated(&mut table, Value::Array(pair), &p.source);
    }
    damping.insert("table", Item::Value(Value::Array(table)));
    if !replaced.is_empty()
        && let Some(mut key) = damping.key_mut("table")
    {
        key.leaf_decor_mut().set_prefix(replaced);
    }
    Ok(doc.to_string())
}

/// The scene's `[damping]` table, created when it has none.
fn damping_table(doc: &mut DocumentMut) -> Result<&mut toml_edit::Table, String> {
    doc.entry("damping")
        .or_insert(Item::Table(toml_edit::Table::new()))
        .as_table_mut()
        .ok_or_else(|| "`damping` is not a table".into())
}

/// One mode's identified ratio: its 1-based number, ζ, the direction of its largest
/// effective-mass fraction on the model it was identified on (so that a later model that
/// renumbers its modes is refused rather than damping another mode), and a one-line note of
/// its source.
pub struct IdentifiedModeDamping {
    pub mode: usize,
    pub zeta: f64,
    pub direction: Option<String>,
    pub source: String,
}

/// `text` with `[damping] modes = [{ mode, zeta, direction }, …]` holding `entries` (each annotated)
/// in place of any entry of theirs; other entries, the base damping and every comment stay.
pub fn with_mode_damping(text: &str, entries: &[IdentifiedModeDamping]) -> Result<String, String> {
    let mut doc: DocumentMut = text.parse().map_err(|e| format!("{e}"))?;
    let damping = damping_table(&mut doc)?;
    let mut modes = match damping.remove("modes") {
        None => Array::new(),
        Some(Item::Value(Value::Array(a))) => a,
        Some(_) => return Err("`damping.modes` is an array of tables; write it inline (`modes = [...]`) for update to edit it".into()),
    };
    modes.retain(|v| {
        let mode = v
            .as_inline_table()
            .and_then(|t| t.get("mode"))
            .and_then(|m| m.as_integer());
        !entries.iter().any(|e| Some(e.mode as i64) == mode)
    });
    for e in entries {
        let mut t = toml_edit::InlineTable::new();
        t.insert("mode", Value::from(e.mode as i64));
        t.insert("zeta", Value::from(round(e.zeta, 6)));
        if let Some(d) = &e.direction {
            t.insert("direction", Value::from(d.as_str()));
        }
        push_annotated(&mut modes, Value::InlineTable(t), &e.source);
    }
    damping.insert("modes", Item::Value(Value::Array(modes)));
    Ok(doc.to_string())
}

/// Appends `v` to a multi-line array on its own line, under a comment naming its source.
fn push_annotated(array: &mut Array, mut v: Value, source: &str) {
    v.decor_mut().set_prefix(format!("\n    # {source}\n    "));
    array.push_formatted(v);
    array.set_trailing("\n");
    array.set_trailing_comma(true);
}

/// `v` to `digits` significant decimals after the point: the table reads as written.
fn round(v: f64, digits: i32) -> f64 {
    let s = 10f64.powi(digits);
    (v * s).round() / s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_survive_and_points_are_annotated() {
        let text = "# the scene\ntitle = \"x\"\n\n# damping from the last test\n[damping]\nq = 15.0 # a guess\n\n[sine]\naxes = [\"x\"] # only x\n";
        let pts = [
            IdentifiedDamping {
                frequency_hz: 10.0,
                zeta: 0.012,
                source: "ema a.csv mode 1".into(),
            },
            IdentifiedDamping {
                frequency_hz: 30.0,
                zeta: 0.02,
                source: "ema a.csv mode 2".into(),
            },
        ];
        let out = with_identified_damping(text, &pts).unwrap();
        for kept in [
            "# the scene",
            "# damping from the last test",
            "axes = [\"x\"] # only x",
        ] {
            assert!(out.contains(kept), "{out}");
        }
        assert!(
            out.contains("# replaced by `satqual ema --write-damping`: q = 15.0"),
            "{out}"
        );
        assert!(
            out.contains("# ema a.csv mode 1\n    [10.0, 0.012]"),
            "{out}"
        );
        let v: toml::Table = toml::from_str(&out).unwrap();
        let t = v["damping"]["table"].as_array().unwrap();
        assert_eq!(t.len(), 2);
        assert!(v["damping"].get("q").is_none());
    }
}
