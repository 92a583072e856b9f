//! An acceleration unit stated once for every channel in the lines above a log's header, as
//! loggers write it when the channel names carry none: `# Units: g`, `Unit = m/s^2`,
//! `Engineering units<TAB>g<TAB>g<TAB>g`; or an electrical unit, a scope's `Vertical Units,V`,
//! which the channels keep.

use super::unit::Unit;

/// Keys that name the unit of the logged values.
const UNIT_KEYS: [&str; 7] = [
    "unit",
    "units",
    "eu",
    "engineering unit",
    "engineering units",
    "y unit",
    // Tektronix oscilloscopes' CSV preamble.
    "vertical units",
];

/// The unit words of a preamble line whose key names the unit of the values, each without
/// the channel prefix Siglent writes (`CH3:V`).
fn unit_words(line: &str) -> Option<Vec<&str>> {
    let (key, value) = super::preamble_rate::key_value(line)?;
    let key = key.split_whitespace().collect::<Vec<_>>().join(" ");
    if !UNIT_KEYS.contains(&key.as_str()) {
        return None;
    }
    let words = value
        .split(['\t', ',', ';', ' '])
        .map(|w| w.trim().trim_matches(['"', '[', ']', '(', ')']))
        .map(|w| w.rsplit(':').next().unwrap_or(w))
        .filter(|w| !w.is_empty())
        .collect();
    Some(words)
}

/// The unit a preamble line states for every channel: one of the keys above followed by one
/// known unit, or by the same unit once per channel. A line listing different units names no
/// channel to give each to, so it states none (the header's units then decide).
pub fn unit_of_line(line: &str) -> Option<Unit> {
    let words = unit_words(line)?;
    let mut units = words.iter().map(|w| Unit::parse(w).ok());
    let first = units.next()??;
    (first != Unit::AsIs && units.all(|u| u == Some(first))).then_some(first)
}

/// The electrical unit (`V`, `mV`, see [`super::unit::is_electrical`]) a preamble line states
/// for every channel, as written: a scope's `Vertical Units,V` above `TIME,CH1`.
pub fn electrical_of_line(line: &str) -> Option<String> {
    let words = unit_words(line)?;
    let first = *words.first()?;
    let same = words.iter().all(|w| w.eq_ignore_ascii_case(first));
    (same && super::unit::is_electrical(first)).then(|| first.to_string())
}

#[cfg(test)]
mod tests {
    use super::unit_of_line;
    use crate::signal::ingest::unit::Unit;

    #[test]
    fn preamble_lines_state_one_unit_for_every_channel() {
        assert_eq!(unit_of_line("# Units: g"), Some(Unit::G));
        assert_eq!(unit_of_line("Unit = m/s^2"), Some(Unit::MPerS2));
        assert_eq!(
            unit_of_line("Engineering units\tmg\tmg\tmg"),
            Some(Unit::MilliG)
        );
        assert_eq!(unit_of_line("\"EU\",\"g\",\"g\""), Some(Unit::G));
        assert_eq!(unit_of_line("Vertical Units,g"), Some(Unit::G));
        // Different units per channel, an unknown unit, another key, no value: none.
        assert_eq!(unit_of_line("Units: g, V"), None);
        assert_eq!(unit_of_line("Units: V"), None);
        assert_eq!(unit_of_line("Units: as-is"), None);
        assert_eq!(unit_of_line("Operator: g"), None);
        assert_eq!(unit_of_line("# Units:"), None);
        // Siglent's channel prefix.
        assert_eq!(unit_of_line("Vertical Units,CH3:g,,"), Some(Unit::G));
    }

    #[test]
    fn preamble_lines_state_one_electrical_unit() {
        use super::electrical_of_line;
        assert_eq!(electrical_of_line("Vertical Units,V"), Some("V".into()));
        assert_eq!(electrical_of_line("Vertical Units,mV,"), Some("mV".into()));
        assert_eq!(
            electrical_of_line("Vertical Units,CH3:V,,"),
            Some("V".into())
        );
        assert_eq!(electrical_of_line("Units: V, mV"), None);
        assert_eq!(electrical_of_line("Vertical Units,g"), None);
        assert_eq!(electrical_of_line("Operator: V"), None);
    }
}
