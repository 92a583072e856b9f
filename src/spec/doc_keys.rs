//! Keeps `docs/scene-format.md` in step with the loader. The accepted keys are not listed by
//! hand: a recording deserializer walks [`SceneFile`] and collects the field names serde-derive
//! hands to `deserialize_struct` for every struct reachable from it. Every such key must be
//! documented, and every key the reference documents must be one the loader accepts, so a
//! field added, renamed or removed in `src/spec/` fails this test until the reference follows.

use super::SceneFile;
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::rc::Rc;

/// Dotted key path -> whether its value is a table (a struct) rather than a plain value.
type Keys = Rc<RefCell<BTreeMap<String, bool>>>;

#[derive(Debug)]
struct WalkError(String);

impl std::fmt::Display for WalkError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for WalkError {}

impl de::Error for WalkError {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        WalkError(msg.to_string())
    }
}

/// Produces a minimal value of whatever type asks, recording struct fields under `path`.
/// Sequences yield one element (so `Vec<Struct>` is walked once) and tuples (fixed arrays)
/// exactly their length; enums take their first variant.
struct Recorder {
    path: String,
    keys: Keys,
}

impl Recorder {
    fn child(&self, name: &str) -> Recorder {
        let path = if self.path.is_empty() {
            name.to_string()
        } else {
            format!("{}.{name}", self.path)
        };
        Recorder {
            path,
            keys: self.keys.clone(),
        }
    }
}

impl<'de> Deserializer<'de> for Recorder {
    type Error = WalkError;

    // Only the count-or-word keys (`bar_modes`, `runs`; spec::count_or_word) ask for "any";
    // both accept a number.
    fn deserialize_any<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_u64(0)
    }
    fn deserialize_bool<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_bool(false)
    }
    fn deserialize_i8<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_i64(0)
    }
    fn deserialize_i16<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_i64(0)
    }
    fn deserialize_i32<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_i64(0)
    }
    fn deserialize_i64<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_i64(0)
    }
    fn deserialize_u8<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_u64(0)
    }
    fn deserialize_u16<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_u64(0)
    }
    fn deserialize_u32<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_u64(0)
    }
    fn deserialize_u64<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_u64(0)
    }
    fn deserialize_f32<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_f64(0.0)
    }
    fn deserialize_f64<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_f64(0.0)
    }
    fn deserialize_char<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_char('x')
    }
    fn deserialize_str<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_str("")
    }
    fn deserialize_string<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_str("")
    }
    fn deserialize_bytes<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_bytes(&[])
    }
    fn deserialize_byte_buf<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_bytes(&[])
    }
    fn deserialize_option<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_some(self)
    }
    fn deserialize_unit<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_unit()
    }
    fn deserialize_unit_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        v: V,
    ) -> Result<V::Value, WalkError> {
        v.visit_unit()
    }
    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        v: V,
    ) -> Result<V::Value, WalkError> {
        v.visit_newtype_struct(self)
    }
    fn deserialize_seq<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_seq(Elements {
            left: 1,
            recorder: self,
        })
    }
    fn deserialize_tuple<V: Visitor<'de>>(self, len: usize, v: V) -> Result<V::Value, WalkError> {
        v.visit_seq(Elements {
            left: len,
            recorder: self,
        })
    }
    fn deserialize_tuple_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        len: usize,
        v: V,
    ) -> Result<V::Value, WalkError> {
        self.deserialize_tuple(len, v)
    }
    // No scene type is a free-form map; an empty one keeps the walk going if one appears.
    fn deserialize_map<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_map(Fields {
            fields: &[],
            next: 0,
            recorder: self,
        })
    }
    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        fields: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, WalkError> {
        {
            let mut keys = self.keys.borrow_mut();
            for f in fields {
                keys.insert(self.child(f).path, false);
            }
            if !self.path.is_empty() {
                keys.insert(self.path.clone(), true);
            }
        }
        v.visit_map(Fields {
            fields,
            next: 0,
            recorder: self,
        })
    }
    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _: &'static str,
        variants: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, WalkError> {
        let first = variants.first().copied().unwrap_or_default();
        v.visit_enum(de::value::StrDeserializer::<WalkError>::new(first))
    }
    fn deserialize_identifier<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_str("")
    }
    fn deserialize_ignored_any<V: Visitor<'de>>(self, v: V) -> Result<V::Value, WalkError> {
        v.visit_unit()
    }
}

struct Elements {
    left: usize,
    recorder: Recorder,
}

impl<'de> SeqAccess<'de> for Elements {
    type Error = WalkError;
    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, WalkError> {
        if self.left == 0 {
            return Ok(None);
        }
        self.left -= 1;
        // Elements of an array of tables share their table's path.
        seed.deserialize(Recorder {
            path: self.recorder.path.clone(),
            keys: self.recorder.keys.clone(),
        })
        .map(Some)
    }
}

struct Fields {
    fields: &'static [&'static str],
    next: usize,
    recorder: Recorder,
}

impl<'de> MapAccess<'de> for Fields {
    type Error = WalkError;
    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, WalkError> {
        let Some(name) = self.fields.get(self.next) else {
            return Ok(None);
        };
        seed.deserialize(de::value::StrDeserializer::<WalkError>::new(name))
            .map(Some)
    }
    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, WalkError> {
        let name = self.fields[self.next];
        self.next += 1;
        seed.deserialize(self.recorder.child(name))
    }
}

/// Every key the loader accepts, with whether it names a table.
fn accepted_keys() -> BTreeMap<String, bool> {
    let keys: Keys = Rc::default();
    let recorder = Recorder {
        path: String::new(),
        keys: keys.clone(),
    };
    <SceneFile as serde::Deserialize>::deserialize(recorder)
        .expect("the recording deserializer builds every scene type");
    keys.take()
}

fn reference() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/scene-format.md");
    std::fs::read_to_string(path).expect("docs/scene-format.md exists")
}

/// The keys the reference documents: the first code span of every table row.
fn documented_keys(doc: &str) -> Vec<String> {
    doc.lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|rest| rest.split('`').next())
        .map(str::to_string)
        .collect()
}

#[test]
fn the_walk_reaches_nested_sections() {
    // Guards the recorder itself: a walk that stopped at the top level would make the
    // completeness test below vacuous.
    let keys = accepted_keys();
    for key in [
        "title",
        "static_load.moment_n_m",
        "stack.interface.torsional_stiffness_n_m_rad",
        "separation.dispersion.seed",
        "sine.segment.acceleration_g",
        "margins.include_face_moment",
    ] {
        assert!(keys.contains_key(key), "`{key}` not found by the walk");
    }
    assert_eq!(keys.get("separation.spring"), Some(&true));
    assert_eq!(keys.get("gates.alarm_db"), Some(&false));
    assert!(keys.len() > 120, "only {} keys found", keys.len());
}

#[test]
fn every_accepted_key_is_documented_and_no_other() {
    let keys = accepted_keys();
    let doc = reference();
    let rows = documented_keys(&doc);
    let missing: Vec<&String> = keys
        .iter()
        .filter(|(key, table)| {
            if **table {
                // A table is documented by its header, `[a.b]` or `[[a.b]]`.
                !doc.contains(&format!("`[{key}]`")) && !doc.contains(&format!("`[[{key}]]`"))
            } else {
                !rows.contains(key)
            }
        })
        .map(|(key, _)| key)
        .collect();
    assert!(
        missing.is_empty(),
        "keys the loader accepts but docs/scene-format.md does not document: {missing:?}"
    );
    let unknown: Vec<&String> = rows
        .iter()
        .filter(|k| keys.get(*k) != Some(&false))
        .collect();
    assert!(
        unknown.is_empty(),
        "keys docs/scene-format.md documents but the loader rejects: {unknown:?}"
    );
}
