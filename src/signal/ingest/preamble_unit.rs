//! An acceleration unit stated once for every channel in the lines above a log's header, as
//! loggers write it when the channel names carry none: `# Units: g`, `Unit = m/s^2`,
//! `Engineering units<TAB>g<TAB>g<TAB>g`.

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

/// The unit a preamble line states for every channel: one of the keys above followed by one
/// known unit, or by the same unit once per channel. A line listing different units names no
/// channel to give each to, so it states none (the header's units then decide).
pub fn unit_of_line(line: &str) -> Option<Unit> {
    let (key, value) = super::preamble_rate::key_value(line)?;
    let key = key.split_whitespace().collect::<Vec<_>>().join(" ");
    if !UNIT_KEYS.contains(&key.as_str()) {
        return None;
    }
    let mut units = value
        .split(['\t', ',', ';', ' '])
        .map(|w| w.trim().trim_matches(['"', '[', ']', '(', ')']))
        .filter(|w| !w.is_empty())
        .map(|w| Unit::parse(w).ok());
    let first = units.next()??;
    (first != Unit::AsIs && units.all(|u| u == Some(first))).then_some(first)
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
    }
}
