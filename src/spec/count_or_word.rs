//! A key that takes a whole count or a word (`bar_modes = 3` or `"rigid"`, `runs = 1109` or
//! `"auto"`). Read by hand: serde's untagged enums answer a wrong value (`3.0`, `-5`, `true`)
//! with "did not match any variant of untagged enum", which names neither what the key takes
//! nor what it got.

use serde::Deserializer;
use serde::de::{self, Unexpected, Visitor};
use std::fmt;

/// What the key held: a non-negative whole number or a word (checked by the caller).
#[derive(Debug)]
pub enum CountOrWord {
    Count(usize),
    Word(String),
}

/// Reads a count or a word; anything else is an error saying what the key takes
/// (`expecting`, e.g. "a whole number of runs, or `auto`") and what it got.
pub fn read<'de, D: Deserializer<'de>>(
    d: D,
    expecting: &'static str,
) -> Result<CountOrWord, D::Error> {
    d.deserialize_any(CountOrWordVisitor { expecting })
}

struct CountOrWordVisitor {
    expecting: &'static str,
}

impl<'de> Visitor<'de> for CountOrWordVisitor {
    type Value = CountOrWord;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.expecting)
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<CountOrWord, E> {
        usize::try_from(v)
            .map(CountOrWord::Count)
            .map_err(|_| E::invalid_value(Unexpected::Unsigned(v), &self))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<CountOrWord, E> {
        match u64::try_from(v) {
            Ok(u) => self.visit_u64(u),
            Err(_) => Err(E::invalid_value(Unexpected::Signed(v), &self)),
        }
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<CountOrWord, E> {
        Err(E::invalid_value(Unexpected::Float(v), &self))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<CountOrWord, E> {
        Ok(CountOrWord::Word(v.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    struct Runs(CountOrWord);
    impl<'de> Deserialize<'de> for Runs {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            read(d, "a whole number of runs, or `auto`").map(Runs)
        }
    }
    #[derive(Deserialize)]
    struct Scene {
        runs: Runs,
    }

    fn parse(text: &str) -> Result<CountOrWord, String> {
        toml::from_str::<Scene>(text)
            .map(|s| s.runs.0)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn counts_and_words_are_read_and_anything_else_says_what_the_key_takes() {
        assert!(matches!(parse("runs = 59"), Ok(CountOrWord::Count(59))));
        assert!(matches!(parse("runs = \"auto\""), Ok(CountOrWord::Word(w)) if w == "auto"));
        for (text, got) in [
            ("runs = -5", "integer `-5`"),
            ("runs = 3.0", "floating point `3.0`"),
            ("runs = true", "boolean `true`"),
        ] {
            let e = parse(text).unwrap_err();
            assert!(
                e.contains(got) && e.contains("expected a whole number of runs, or `auto`"),
                "{text}: {e}"
            );
        }
    }
}
