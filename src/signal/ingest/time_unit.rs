//! Time columns: which names are time, and the unit the name states (s, ms, µs, ns) or the
//! cells show (ISO 8601 date-times).

use crate::error::SignalError;

/// Unit of a time column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum TimeUnit {
    #[serde(rename = "s")]
    S,
    #[serde(rename = "ms")]
    Ms,
    #[serde(rename = "us")]
    Us,
    #[serde(rename = "ns")]
    Ns,
    /// ISO 8601 date-times, read as seconds from the first row's.
    #[serde(rename = "iso8601")]
    Iso8601,
    /// Days, as spreadsheets count date-times (serial days since 1899-12-30).
    #[serde(rename = "d")]
    Days,
}

impl TimeUnit {
    pub fn parse(s: &str) -> Result<TimeUnit, SignalError> {
        Self::from_word(s).ok_or_else(|| SignalError::BadParameter {
            name: "time-unit",
            value: s.to_string(),
            reason: "expected s, ms, us, ns, d (days) or iso8601".into(),
        })
    }

    fn from_word(s: &str) -> Option<TimeUnit> {
        match s.trim().to_lowercase().as_str() {
            "s" | "sec" | "secs" | "second" | "seconds" => Some(TimeUnit::S),
            "ms" | "msec" | "millis" => Some(TimeUnit::Ms),
            "us" | "µs" | "μs" | "usec" | "micros" => Some(TimeUnit::Us),
            "ns" | "nsec" | "nanos" => Some(TimeUnit::Ns),
            "iso8601" | "iso" => Some(TimeUnit::Iso8601),
            "d" | "day" | "days" => Some(TimeUnit::Days),
            _ => None,
        }
    }

    /// Seconds per unit.
    pub fn seconds(self) -> f64 {
        match self {
            TimeUnit::S => 1.0,
            TimeUnit::Ms => 1e-3,
            TimeUnit::Us => 1e-6,
            TimeUnit::Ns => 1e-9,
            TimeUnit::Iso8601 => 1.0,
            TimeUnit::Days => 86_400.0,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            TimeUnit::S => "s",
            TimeUnit::Ms => "ms",
            TimeUnit::Us => "us",
            TimeUnit::Ns => "ns",
            TimeUnit::Iso8601 => "iso8601",
            TimeUnit::Days => "d",
        }
    }
}

/// Words that name a time column (`zeit`: German exports, catman's and Dewesoft's included).
const TIME_WORDS: [&str; 12] = [
    "t",
    "time",
    "times",
    "timestamp",
    "x_value",
    "second",
    "seconds",
    "sec",
    "epoch",
    "elapsed",
    "elapsed_time",
    "zeit",
];

/// `Some(unit)` for a time column: `Some(Some(u))` when the name states the unit (`time_ms`,
/// `time [us]`, `seconds`), `Some(None)` when it does not (`time`, `t`, `timestamp`).
pub fn time_column_unit(name: &str) -> Option<Option<TimeUnit>> {
    let n = name.trim().to_lowercase();
    let (base, bracket) = match n.find(['[', '(']) {
        Some(i) => (
            n[..i].trim(),
            Some(n[i + 1..].trim_end_matches([']', ')']).trim()),
        ),
        None => (n.as_str(), None),
    };
    let base = base.trim();
    if let Some(b) = bracket {
        let unit = TimeUnit::from_word(b)?;
        return (TIME_WORDS.contains(&base) || numbered_time(base)).then_some(Some(unit));
    }
    if TIME_WORDS.contains(&base) {
        let stated = matches!(base, "second" | "seconds" | "sec").then_some(TimeUnit::S);
        return Some(stated);
    }
    if numbered_time(base) {
        return Some(None);
    }
    let (stem, suffix) = base.rsplit_once(['_', ' '])?;
    let unit = TimeUnit::from_word(suffix)?;
    TIME_WORDS.contains(&stem).then_some(Some(unit))
}

/// A numbered time channel, as HBM catman names it: `time  1 - default sample rate`.
fn numbered_time(base: &str) -> bool {
    base.split_once(' ').is_some_and(|(first, rest)| {
        TIME_WORDS.contains(&first) && rest.trim_start().starts_with(|c: char| c.is_ascii_digit())
    })
}

#[cfg(test)]
mod tests {
    use super::{TimeUnit, time_column_unit};

    #[test]
    fn time_columns_are_named_as_exports_name_them() {
        assert_eq!(time_column_unit("Time [s]"), Some(Some(TimeUnit::S)));
        assert_eq!(time_column_unit("time_ms"), Some(Some(TimeUnit::Ms)));
        assert_eq!(time_column_unit("Zeit [ms]"), Some(Some(TimeUnit::Ms)));
        assert_eq!(
            time_column_unit("Time  1 - default sample rate"),
            Some(None)
        );
        assert_eq!(time_column_unit("Time 2"), Some(None));
        assert_eq!(
            time_column_unit("Time  1 - default sample rate [s]"),
            Some(Some(TimeUnit::S))
        );
        assert_eq!(time_column_unit("timestamp"), Some(None));
        assert_eq!(time_column_unit("Time of flight"), None);
        assert_eq!(time_column_unit("Acc X"), None);
    }
}
