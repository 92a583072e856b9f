//! ISO 8601 date-times in a time column (`2024-04-21T15:54:46.333682Z`, `2024-04-21
//! 15:54:46,5+02:00`), as loggers and phone apps write them.
//!
//! Hand-written (no date crate in the tree for one format): the calendar part is the
//! days-from-civil count of the proleptic Gregorian calendar (H. Hinnant, "chrono-Compatible
//! Low-Level Date Algorithms"). Whole seconds are kept as an integer and the fraction apart, so
//! that microsecond steps survive subtracting an epoch of 1.7e9 s.

/// A date-time as whole seconds since 1970-01-01T00:00:00Z and the fraction of a second.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instant {
    pub seconds: i64,
    pub fraction: f64,
}

impl Instant {
    /// Seconds from `origin` to this instant.
    pub fn since(self, origin: Instant) -> f64 {
        (self.seconds - origin.seconds) as f64 + (self.fraction - origin.fraction)
    }
}

fn digits(s: &[u8]) -> Option<i64> {
    if s.is_empty() || !s.iter().all(u8::is_ascii_digit) {
        return None;
    }
    Some(s.iter().fold(0i64, |a, &d| a * 10 + i64::from(d - b'0')))
}

/// Days from 1970-01-01 to the civil date `y-m-d`.
pub(super) fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

pub(super) fn days_in_month(y: i64, m: i64) -> i64 {
    match m {
        4 | 6 | 9 | 11 => 30,
        2 if (y % 4 == 0 && y % 100 != 0) || y % 400 == 0 => 29,
        2 => 28,
        _ => 31,
    }
}

/// Offset from UTC in seconds: `Z`, `±hh:mm`, `±hhmm`, `±hh`; none means UTC (a log's times
/// only matter relative to each other).
fn offset(s: &[u8]) -> Option<i64> {
    match s {
        [] | [b'Z'] | [b'z'] => Some(0),
        [sign @ (b'+' | b'-'), rest @ ..] => {
            let (h, m) = match rest {
                [a, b] => (digits(&[*a, *b])?, 0),
                [a, b, b':', c, d] | [a, b, c, d] => (digits(&[*a, *b])?, digits(&[*c, *d])?),
                _ => return None,
            };
            if h > 23 || m > 59 {
                return None;
            }
            let o = h * 3600 + m * 60;
            Some(if *sign == b'-' { -o } else { o })
        }
        _ => None,
    }
}

/// Parses `YYYY-MM-DD(T| )hh:mm:ss[(.|,)fraction][offset]`; `None` for anything else.
pub fn parse(text: &str) -> Option<Instant> {
    let s = text.trim().trim_matches('"').as_bytes();
    if s.len() < 19 || s[4] != b'-' || s[7] != b'-' || !matches!(s[10], b'T' | b't' | b' ') {
        return None;
    }
    if s[13] != b':' || s[16] != b':' {
        return None;
    }
    let (y, mo, d) = (digits(&s[0..4])?, digits(&s[5..7])?, digits(&s[8..10])?);
    let (h, mi, sec) = (
        digits(&s[11..13])?,
        digits(&s[14..16])?,
        digits(&s[17..19])?,
    );
    if !(1..=12).contains(&mo) || d < 1 || d > days_in_month(y, mo) || h > 23 || mi > 59 || sec > 60
    {
        return None;
    }
    let mut i = 19;
    let mut fraction = 0.0;
    if matches!(s.get(i), Some(b'.' | b',')) {
        let start = i + 1;
        let end = start + s[start..].iter().take_while(|b| b.is_ascii_digit()).count();
        if end == start {
            return None;
        }
        let frac = std::str::from_utf8(&s[start..end]).ok()?;
        fraction = format!("0.{frac}").parse().ok()?;
        i = end;
    }
    let off = offset(&s[i..])?;
    let seconds = days_from_civil(y, mo, d) * 86_400 + h * 3600 + mi * 60 + sec - off;
    Some(Instant { seconds, fraction })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_epochs() {
        // 2000-01-01T00:00:00Z is 946 684 800 s after the Unix epoch (POSIX time).
        assert_eq!(parse("2000-01-01T00:00:00Z").unwrap().seconds, 946_684_800);
        // 2024-02-29 (leap day) 12:00 at +02:00 is 10:00 UTC: 1 709 200 800 s.
        assert_eq!(
            parse("2024-02-29 12:00:00+02:00").unwrap().seconds,
            1_709_200_800
        );
        let a = parse("2024-04-21T15:54:46.333682").unwrap();
        let b = parse("2024-04-21T15:54:46,334182").unwrap();
        assert!((b.since(a) - 500e-6).abs() < 1e-12);
        for bad in [
            "2023-02-29T00:00:00",
            "2024-04-21",
            "12.5",
            "2024-13-01T00:00:00",
            "2024-04-21T15:54:46.",
            "2024-04-21T15:54:46+2",
        ] {
            assert!(parse(bad).is_none(), "{bad}");
        }
    }
}
