//! Date-times and clock times in a time column, in the forms lab software writes them: ISO 8601
//! ([`super::iso8601`]); a locale's date and time, `28.11.2026 10:15:30,125` (German),
//! `11/28/2026 10:15:30.125 AM` (US, Excel), `2026/11/28 10:15:30`; and a time of day or an
//! elapsed clock alone, `10:15:30.125`, `0:00:01.5`. Only differences between rows are used,
//! so a clock without a date counts from midnight and a zone never matters within one column.
//!
//! A slashed date is month/day/year (the US and Excel form) unless its first number exceeds 12;
//! read the other way it would still give the same differences within one day.

use super::iso8601::{self, Instant, days_from_civil, days_in_month};

/// Parses any of the module's forms; `None` for anything else (a plain number among them).
pub fn parse(text: &str) -> Option<Instant> {
    iso8601::parse(text).or_else(|| local(text.trim().trim_matches('"')))
}

/// True for a clock time with no date (`23:59:58.5`, `11:59:58 PM`): such a column starts
/// again from zero when the log runs past midnight.
pub fn is_time_of_day(text: &str) -> bool {
    let t = text.trim().trim_matches('"');
    iso8601::parse(t).is_none()
        && local(t).is_some()
        && parts(t).is_some_and(|(date, _, _)| date.is_none())
}

/// A cell's date, clock and AM/PM tokens.
fn parts(t: &str) -> Option<(Option<&str>, &str, Option<bool>)> {
    let tokens: Vec<&str> = t.split_whitespace().collect();
    Some(match tokens.as_slice() {
        [c] => (None, *c, None),
        [c, m] if meridiem_of(m).is_some() => (None, *c, meridiem_of(m)),
        [d, c] => (Some(*d), *c, None),
        [d, c, m] => (Some(*d), *c, Some(meridiem_of(m)?)),
        _ => return None,
    })
}

fn local(t: &str) -> Option<Instant> {
    let (date, clock, meridiem) = parts(t)?;
    let days = match date {
        Some(d) => civil_days(d)?,
        None => 0,
    };
    let (h, m, s, fraction) = clock_of(clock)?;
    let h = match meridiem {
        None if date.is_some() && h > 23 => return None,
        None => h,
        Some(_) if !(1..=12).contains(&h) => return None,
        Some(pm) => h % 12 + if pm { 12 } else { 0 },
    };
    Some(Instant {
        seconds: days * 86_400 + h * 3600 + m * 60 + s,
        fraction,
    })
}

/// `AM` → false, `PM` → true.
fn meridiem_of(m: &str) -> Option<bool> {
    match m.to_ascii_uppercase().as_str() {
        "AM" | "A.M." => Some(false),
        "PM" | "P.M." => Some(true),
        _ => None,
    }
}

fn number(s: &str) -> Option<i64> {
    (!s.is_empty() && s.len() <= 4 && s.bytes().all(|b| b.is_ascii_digit()))
        .then(|| s.parse().ok())
        .flatten()
}

/// Days since 1970-01-01 of `DD.MM.YYYY`, `DD-MM-YYYY`, `MM/DD/YYYY` (or `DD/MM/YYYY` when the
/// first number exceeds 12) and `YYYY/MM/DD`.
fn civil_days(d: &str) -> Option<i64> {
    let sep = ['.', '/', '-'].into_iter().find(|&c| d.contains(c))?;
    let parts: Vec<&str> = d.split(sep).collect();
    let [a, b, c] = parts.as_slice() else {
        return None;
    };
    let (x, y, z) = (number(a)?, number(b)?, number(c)?);
    let (year, month, day) = match sep {
        '/' if a.len() == 4 => (x, y, z),
        '/' if x > 12 => (z, y, x),
        '/' => (z, x, y),
        _ if c.len() == 4 => (z, y, x),
        _ => return None,
    };
    if c.len() != 4 && a.len() != 4 {
        return None;
    }
    if !(1..=12).contains(&month) || day < 1 || day > days_in_month(year, month) {
        return None;
    }
    Some(days_from_civil(year, month, day))
}

/// `h:mm:ss` with an optional fraction after `.` or `,`: (hours, minutes, seconds, fraction).
/// Hours may exceed 23 in an elapsed clock.
fn clock_of(c: &str) -> Option<(i64, i64, i64, f64)> {
    let mut parts = c.split(':');
    let (h, m, s) = (parts.next()?, parts.next()?, parts.next()?);
    if parts.next().is_some() || m.len() != 2 {
        return None;
    }
    let (whole, frac) = match s.find(['.', ',']) {
        Some(i) => (&s[..i], Some(&s[i + 1..])),
        None => (s, None),
    };
    if whole.len() != 2 {
        return None;
    }
    let (h, m, sec) = (number(h)?, number(m)?, number(whole)?);
    if m > 59 || sec > 60 {
        return None;
    }
    let fraction = match frac {
        Some(f) if !f.is_empty() && f.bytes().all(|b| b.is_ascii_digit()) => {
            format!("0.{f}").parse().ok()?
        }
        Some(_) => return None,
        None => 0.0,
    };
    Some((h, m, sec, fraction))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every locale form of 2026-11-28 10:15:30.125 gives the same instant as its ISO 8601
    /// text (days-from-civil, the reference of `iso8601`'s own tests).
    #[test]
    fn locale_forms_are_the_same_instant_as_iso_8601() {
        let want = iso8601::parse("2026-11-28T10:15:30.125").unwrap();
        for text in [
            "28.11.2026 10:15:30,125",
            "28-11-2026 10:15:30.125",
            "11/28/2026 10:15:30.125 AM",
            "28/11/2026 10:15:30.125",
            "2026/11/28 10:15:30.125",
            "\"11/28/2026 10:15:30.125\"",
        ] {
            assert_eq!(parse(text), Some(want), "{text}");
        }
        let pm = parse("11/28/2026 12:00:00 PM").unwrap();
        let am = parse("11/28/2026 12:00:00 AM").unwrap();
        assert_eq!(pm.seconds - am.seconds, 12 * 3600);
    }

    #[test]
    fn only_a_clock_without_a_date_is_a_time_of_day() {
        for t in ["23:59:58.5", "11:59:58 PM", "\"0:00:01\""] {
            assert!(is_time_of_day(t), "{t}");
        }
        for t in ["28.11.2026 23:59:58", "2026-11-28T23:59:58", "1.5", "noon"] {
            assert!(!is_time_of_day(t), "{t}");
        }
    }

    #[test]
    fn clocks_without_a_date_count_from_midnight() {
        let a = parse("0:00:01.5").unwrap();
        assert_eq!((a.seconds, a.fraction), (1, 0.5));
        let b = parse("10:15:30,25").unwrap();
        assert_eq!((b.seconds, b.fraction), (36_930, 0.25));
        assert_eq!(parse("01:00:00 PM").unwrap().seconds, 13 * 3600);
        assert_eq!(parse("100:00:00").unwrap().seconds, 360_000);
        for bad in [
            "12.5",
            "10:15",
            "10:5:30",
            "10:15:30.",
            "31.02.2026 10:00:00",
            "13:00:00 PM",
            "28.11.26 10:00:00",
            "2026-11-28",
            "24:00:00 x",
        ] {
            assert!(parse(bad).is_none(), "{bad}");
        }
    }
}
