//! The physical unit of a log channel: read from a unit label, a channel name or `--units`,
//! and converted to the unit the analysis reports (g for accelerations).

use crate::error::SignalError;

/// Physical unit of a channel, as found in its name or given by the caller.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Unit {
    #[serde(rename = "g")]
    G,
    #[serde(rename = "m/s2")]
    MPerS2,
    /// Thousandths of g, as low-level accelerometer logs state it.
    #[serde(rename = "mg")]
    MilliG,
    /// Millionths of g, as seismic and microgravity accelerometers state it.
    #[serde(rename = "ug")]
    MicroG,
    #[serde(rename = "mm/s2")]
    MmPerS2,
    /// Inches and feet per second squared, as US laboratories log accelerations.
    #[serde(rename = "in/s2")]
    InPerS2,
    #[serde(rename = "ft/s2")]
    FtPerS2,
    /// Anything else (force, voltage, ...): values are kept as they are.
    #[serde(rename = "as-is")]
    AsIs,
}

/// Spellings of each acceleration unit after [`normalise_unit`].
const UNIT_SPELLINGS: [(Unit, &[&str]); 8] = [
    (Unit::G, &["g", "gn", "g0", "g's"]),
    (Unit::MPerS2, &["m/s2", "ms-2", "ms2", "m_s2", "mps2"]),
    (Unit::MilliG, &["mg"]),
    (Unit::MicroG, &["ug", "µg", "μg"]),
    (Unit::MmPerS2, &["mm/s2", "mms-2"]),
    (Unit::InPerS2, &["in/s2", "ins-2"]),
    (Unit::FtPerS2, &["ft/s2", "fts-2"]),
    (Unit::AsIs, &["as-is", "raw", "none"]),
];

/// A unit as written by acquisition software, reduced to one spelling: lower case, no blanks,
/// products or powers (`m s^-2`, `m/s**2`, `m·s⁻²`, `m/sec²`, `m/s/s` all become `m/s2` or
/// `ms-2`).
fn normalise_unit(s: &str) -> String {
    let mut n: String = s
        .trim()
        .to_lowercase()
        .replace("⁻²", "-2")
        .replace('²', "2")
        .replace("sec", "s")
        .chars()
        .filter(|c| !matches!(c, ' ' | '*' | '·' | '^' | '.'))
        .collect();
    if let Some(stem) = n.strip_suffix("/s/s") {
        n = format!("{stem}/s2");
    }
    n
}

/// The text in a name's closing brackets: `Kraft [N]` → `N`, `F (lbf)` → `lbf`.
pub fn bracketed(name: &str) -> Option<&str> {
    let t = name.trim_end();
    [('[', ']'), ('(', ')')].iter().find_map(|&(open, close)| {
        let inner = t.strip_suffix(close)?;
        let unit = inner[inner.rfind(open)? + 1..].trim();
        (!unit.is_empty()).then_some(unit)
    })
}

/// A file's unit text as a label for values kept as they are: trimmed, at most 24 characters
/// of printable text, empty when it is blank or one of the as-is spellings.
pub fn kept_label(text: &str) -> String {
    let t = text.trim();
    let printable = !t.is_empty() && t.chars().count() <= 24 && !t.chars().any(char::is_control);
    if printable && Unit::parse(t).is_err() {
        t.to_string()
    } else {
        String::new()
    }
}

/// Whether a unit label is an electrical one (`V`, `mV`, `µV`, `Volt`, `Volts`), as
/// oscilloscopes and DAQs label a raw reading: it becomes an acceleration only through the
/// sensor's sensitivity, which the file does not give, so `--units g` for all channels does
/// not make it g (only `--units NAME=g` for the channel does).
pub fn is_electrical(label: &str) -> bool {
    let n = label.trim().to_lowercase();
    let volts = [
        "v",
        "mv",
        "uv",
        "µv",
        "μv",
        "kv",
        "volt",
        "volts",
        "millivolt",
        "millivolts",
        "microvolt",
        "microvolts",
    ];
    volts.contains(&n.as_str())
}

/// The note, if any, for a channel its file states in `label`: when that is an electrical
/// unit, either kept in it (`read_as` as-is) while `--units` gives one unit (`default`) for
/// every channel, or read as the acceleration `--units NAME=UNIT` `named` it.
pub fn volts_note(
    channel: &str,
    label: &str,
    read_as: Unit,
    named: bool,
    default: Option<Unit>,
) -> Option<String> {
    if !is_electrical(label) {
        return None;
    }
    match (read_as, named, default) {
        (Unit::AsIs, false, Some(d)) => Some(electrical_note(channel, label, d)),
        (u, true, _) if u != Unit::AsIs => Some(volts_read_as_note(channel, label, u)),
        _ => None,
    }
}

/// The note for a channel kept in the electrical unit its file states while `--units` gives
/// one unit for every channel.
fn electrical_note(channel: &str, label: &str, default: Unit) -> String {
    let unit = default.label();
    format!(
        "channel `{channel}` is in {label} as the file states, an electrical unit: kept in \
         {label}, not taken as {unit} by --units {unit}; pass --units \"{channel}={unit}\" if \
         its values are accelerations"
    )
}

/// The note for a channel the file states in volts that `--units NAME=UNIT` reads as an
/// acceleration: its values are taken unchanged, i.e. at a sensitivity of one volt-unit per
/// UNIT, which only the user can vouch for.
fn volts_read_as_note(channel: &str, label: &str, unit: Unit) -> String {
    let u = unit.label();
    format!(
        "channel `{channel}` is in {label} as the file states; --units \"{channel}={u}\" reads \
         its values as {u} unchanged, i.e. at a sensitivity of 1 {label}/{u}: divide them by \
         the sensor's sensitivity first if it is not"
    )
}

impl Unit {
    pub fn parse(s: &str) -> Result<Unit, SignalError> {
        let n = normalise_unit(s);
        UNIT_SPELLINGS
            .iter()
            .find(|(_, spellings)| spellings.contains(&n.as_str()))
            .map(|(u, _)| *u)
            .ok_or_else(|| SignalError::BadParameter {
                name: "units",
                value: s.to_string(),
                reason: "expected g, mg, ug (µg), m/s2, mm/s2, in/s2, ft/s2 or as-is".into(),
            })
    }

    /// The unit a channel name states, e.g. `accel_g`, `acc_m_s2`, `a [m/s²]`, `z (in/s^2)`.
    pub fn from_name(name: &str) -> Option<Unit> {
        let n = name.trim().to_ascii_lowercase();
        let bracketed = [('[', ']'), ('(', ')')].iter().find_map(|&(open, close)| {
            let inner = n.strip_suffix(close)?;
            let start = inner.rfind(open)?;
            Unit::parse(&inner[start + 1..]).ok()
        });
        if let Some(u) = bracketed.filter(|u| *u != Unit::AsIs) {
            Some(u)
        } else if n.ends_with("_g") || n == "g" {
            Some(Unit::G)
        } else if ["m/s2", "m/s^2", "m/s²", "_m_s2", "_ms2", "mps2"]
            .iter()
            .any(|s| n.ends_with(s))
        {
            Some(Unit::MPerS2)
        } else {
            None
        }
    }

    /// The unit as the JSON and a re-read label write it.
    pub fn label(self) -> &'static str {
        match self {
            Unit::G => "g",
            Unit::MPerS2 => "m/s2",
            Unit::MilliG => "mg",
            Unit::MicroG => "ug",
            Unit::MmPerS2 => "mm/s2",
            Unit::InPerS2 => "in/s2",
            Unit::FtPerS2 => "ft/s2",
            Unit::AsIs => "as-is",
        }
    }

    /// Factor from this unit to the unit the analysis reports (g for accelerations; the inch
    /// and foot are exactly 0.0254 m and 0.3048 m).
    pub fn to_report_factor(self) -> f64 {
        let g = crate::units::G;
        match self {
            Unit::MPerS2 => 1.0 / g,
            Unit::MilliG => 1e-3,
            Unit::MicroG => 1e-6,
            Unit::MmPerS2 => 1e-3 / g,
            Unit::InPerS2 => 0.0254 / g,
            Unit::FtPerS2 => 0.3048 / g,
            Unit::G | Unit::AsIs => 1.0,
        }
    }

    /// Unit of the values after conversion.
    /// As [`Unit::reported`], but values kept as they are take the file's unit text for them
    /// (`label`, see [`kept_label`]) where it states one.
    pub fn reported_with(self, label: &str) -> String {
        match (self, kept_label(label)) {
            (Unit::AsIs, l) if !l.is_empty() => l,
            _ => self.reported().to_string(),
        }
    }

    pub fn reported(self) -> &'static str {
        match self {
            Unit::AsIs => "as-is",
            _ => "g",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Unit;

    /// The unit text of a channel kept as it is: brackets of a name, the file's own spelling,
    /// nothing for blanks, as-is spellings and text too long to be a unit.
    #[test]
    fn a_kept_channel_takes_the_files_unit_text() {
        use super::{bracketed, kept_label};
        assert_eq!(bracketed("Kraft [N]"), Some("N"));
        assert_eq!(bracketed("F (lbf) "), Some("lbf"));
        assert_eq!(bracketed("force"), None);
        assert_eq!(bracketed("x []"), None);
        assert_eq!(kept_label(" Pa "), "Pa");
        assert_eq!(kept_label("Deg C"), "Deg C");
        assert_eq!(kept_label(""), "");
        assert_eq!(kept_label("raw"), "");
        assert_eq!(kept_label(&"x".repeat(25)), "");
        assert_eq!(Unit::AsIs.reported_with("V"), "V");
        assert_eq!(Unit::MPerS2.reported_with("m/s^2"), "g");
    }

    /// Spellings seen in LabVIEW, UFF, catman and spreadsheet exports, each to its unit.
    #[test]
    fn acceleration_units_are_read_as_labs_write_them() {
        let cases = [
            ("g", Unit::G),
            ("gn", Unit::G),
            ("G's", Unit::G),
            ("µg", Unit::MicroG),
            ("μg", Unit::MicroG),
            ("ug", Unit::MicroG),
            ("m/s^2", Unit::MPerS2),
            ("m/s²", Unit::MPerS2),
            ("m s^-2", Unit::MPerS2),
            ("m·s⁻²", Unit::MPerS2),
            ("m/s**2", Unit::MPerS2),
            ("m/sec^2", Unit::MPerS2),
            ("m/s/s", Unit::MPerS2),
            ("mg", Unit::MilliG),
            ("mm/s²", Unit::MmPerS2),
            ("in/s^2", Unit::InPerS2),
            ("ft/sec²", Unit::FtPerS2),
            ("none", Unit::AsIs),
        ];
        for (text, unit) in cases {
            assert_eq!(Unit::parse(text).ok(), Some(unit), "{text}");
        }
        assert!(Unit::parse("N").is_err());
        assert!(Unit::parse("Deg C").is_err());
    }

    /// The electrical units oscilloscopes write (`Vertical Units,V`, Rigol's `Volt`); an
    /// acceleration, a force or a blank is none.
    #[test]
    fn volts_are_electrical_units() {
        use super::is_electrical;
        for v in ["V", "mV", " mv ", "µV", "uV", "Volt", "Volts", "millivolts"] {
            assert!(is_electrical(v), "{v}");
        }
        for other in ["g", "m/s2", "N", "", "VV", "dB"] {
            assert!(!is_electrical(other), "{other}");
        }
    }

    /// A unit in brackets at the end of a name states the channel's unit; a bare `_g` too.
    #[test]
    fn a_name_states_its_unit_in_brackets_or_a_suffix() {
        assert_eq!(Unit::from_name("z (in/s^2)"), Some(Unit::InPerS2));
        assert_eq!(Unit::from_name("Acc 3 [mg]"), Some(Unit::MilliG));
        assert_eq!(Unit::from_name("accel_g"), Some(Unit::G));
        assert_eq!(Unit::from_name("acc_m_s2"), Some(Unit::MPerS2));
        assert_eq!(Unit::from_name("Force (N)"), None);
        assert_eq!(Unit::from_name("weight_mg"), None);
    }

    /// To g: 1 g = 9.80665 m/s² (standard gravity, ISO 80000-3), 1 in = 0.0254 m and
    /// 1 ft = 0.3048 m exactly (international yard and pound, 1959).
    #[test]
    fn every_acceleration_unit_converts_to_g() {
        let g = 9.80665;
        let cases = [
            (Unit::G, 1.0),
            (Unit::MilliG, 1e-3),
            (Unit::MPerS2, 1.0 / g),
            (Unit::MmPerS2, 1e-3 / g),
            (Unit::InPerS2, 0.0254 / g),
            (Unit::FtPerS2, 0.3048 / g),
        ];
        for (unit, factor) in cases {
            assert!(
                (unit.to_report_factor() - factor).abs() <= 1e-15 * factor,
                "{unit:?}"
            );
            assert_eq!(unit.reported(), "g");
            assert_eq!(Unit::parse(unit.label()).ok(), Some(unit));
        }
        assert_eq!(Unit::AsIs.reported(), "as-is");
    }
}
