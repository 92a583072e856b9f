//! A sampling rate stated in the lines above a log's header, as acquisition software writes
//! it when the log has no time column: `Sample rate: 2048 Hz`, `# Fs = 25.6 kHz`,
//! `Sampling frequency [Hz]<TAB>1000`, `Sample interval: 0.5 ms`.

/// Keys that name a rate (Hz unless a unit follows) or an interval (s unless a unit follows).
const RATE_KEYS: [&str; 16] = [
    "sample rate",
    "sampling rate",
    "sample frequency",
    "sampling frequency",
    "samplerate",
    "fs",
    "scan rate",
    "acquisition rate",
    "samples per second",
    "sample rate hz",
    "data rate",
    "output data rate",
    "odr",
    // German exports (HBM catman, imc): sampling rate, sampling frequency, measuring rate.
    "abtastrate",
    "abtastfrequenz",
    "messrate",
];
const INTERVAL_KEYS: [&str; 7] = [
    "dt",
    "delta t",
    "sample interval",
    "sampling interval",
    "sample period",
    "sampling period",
    "time step",
];

/// The rate a preamble line states, in Hz, if it is one of the keys above with a positive
/// number and a known unit. A line may hold several settings (`# Config: data_rate = 2000.0
/// Hz, filter = 488 Hz`): each clause after `, ` or `; ` is tried, and within a clause a
/// `section:` prefix before the key.
pub fn rate_of_line(line: &str, decimal_comma: bool) -> Option<f64> {
    std::iter::once(line)
        .chain(line.split(", ").flat_map(|c| c.split("; ")))
        .find_map(|clause| {
            let (key, value) = key_value(clause)?;
            rate_of_pair(&key, value, decimal_comma)
                .or_else(|| key_value(value).and_then(|(k, v)| rate_of_pair(&k, v, decimal_comma)))
        })
}

fn rate_of_pair(key: &str, value: &str, decimal_comma: bool) -> Option<f64> {
    let value = value.trim_matches('"');
    let (key, key_unit) = split_unit(key);
    let key = key.split_whitespace().collect::<Vec<_>>().join(" ");
    let (number, value_unit) = split_number(value, decimal_comma)?;
    let unit = value_unit.or(key_unit).unwrap_or_default();
    if RATE_KEYS.contains(&key.as_str()) {
        rate_unit(&unit).map(|k| number * k)
    } else if INTERVAL_KEYS.contains(&key.as_str()) {
        interval_unit(&unit).map(|k| 1.0 / (number * k))
    } else {
        None
    }
    .filter(|hz| hz.is_finite() && *hz > 0.0)
}

/// A preamble line as `key: value` (or `=`, tab, `;`, `,`): the key lower-cased, quotes
/// trimmed, `_` and `-` read as spaces; the value trimmed. Comment marks before it are skipped.
pub(super) fn key_value(line: &str) -> Option<(String, &str)> {
    let t = line
        .trim()
        .trim_start_matches(['#', '%', '/', ';', '"'])
        .trim();
    let cut = t.find([':', '=', '\t', ';', ','])?;
    let key = t[..cut]
        .trim_matches('"')
        .to_lowercase()
        .replace(['_', '-'], " ");
    Some((key, t[cut + 1..].trim()))
}

/// `sampling frequency [hz]` → (`sampling frequency`, Some(`hz`)).
fn split_unit(key: &str) -> (String, Option<String>) {
    match key.find(['[', '(']) {
        Some(i) => (
            key[..i].trim().to_string(),
            Some(key[i + 1..].trim_end_matches([']', ')']).trim().to_string()),
        ),
        None => (key.trim().to_string(), None),
    }
}

/// `2048 Hz` → (2048, Some(`hz`)).
fn split_number(value: &str, decimal_comma: bool) -> Option<(f64, Option<String>)> {
    let mut words = value.split_whitespace();
    let first = words.next()?;
    let end = first
        .find(|c: char| c.is_ascii_alphabetic() && c != 'e' && c != 'E')
        .unwrap_or(first.len());
    let number = super::sniff::number(&first[..end], decimal_comma)?;
    let attached = &first[end..];
    let unit = if attached.is_empty() {
        words.next().map(str::to_lowercase)
    } else {
        Some(attached.to_lowercase())
    };
    Some((number, unit))
}

fn rate_unit(unit: &str) -> Option<f64> {
    match unit {
        "" | "hz" | "s/s" | "sps" | "samples/s" | "1/s" => Some(1.0),
        "khz" | "ks/s" | "ksps" => Some(1e3),
        _ => None,
    }
}

fn interval_unit(unit: &str) -> Option<f64> {
    match unit {
        "" | "s" | "sec" => Some(1.0),
        "ms" => Some(1e-3),
        "us" | "µs" | "μs" => Some(1e-6),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::rate_of_line;

    #[test]
    fn preamble_lines_state_rates_as_loggers_write_them() {
        let cases = [
            ("Sample rate: 2048 Hz", 2048.0),
            ("# Fs = 25.6 kHz", 25600.0),
            ("Sampling frequency [Hz]\t1000", 1000.0),
            ("sample_rate=512", 512.0),
            ("Sample interval: 0.5 ms", 2000.0),
            ("dt = 1e-3", 1000.0),
            ("Scan rate: 10kS/s", 10000.0),
        ];
        for (line, hz) in cases {
            let got = rate_of_line(line, false).unwrap_or(f64::NAN);
            assert!((got - hz).abs() <= 1e-9 * hz, "{line}: {got}");
        }
        assert_eq!(rate_of_line("Messdauer; 1000", false), None);
        // Several settings on one line (PicoQuake's CSV), and a German catman preamble.
        let config = "# Config: data_rate = 2000.0 Hz, filter = 488 Hz, acc_range = 4 g";
        assert_eq!(rate_of_line(config, false), Some(2000.0));
        assert_eq!(rate_of_line("# Filter = 488 Hz, Range = 4 g", false), None);
        assert_eq!(rate_of_line("Abtastrate; 1200 Hz", false), Some(1200.0));
        assert_eq!(rate_of_line("Sample rate: fast", false), None);
        assert_eq!(rate_of_line("Sample rate: 100 rpm", false), None);
        assert_eq!(rate_of_line("Sample rate: -5", false), None);
        assert_eq!(rate_of_line("Operator: J. Smith", false), None);
        let got = rate_of_line("Sampling rate;2,5 kHz", true).unwrap();
        assert!((got - 2500.0).abs() < 1e-9, "{got}");
    }
}
