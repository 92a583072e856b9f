//! What the report records about its input: the scene's fingerprint and its labelled
//! assumptions.

/// FNV-1a, 64 bit: a stable fingerprint of the scene text for the report's provenance.
pub fn fnv1a(text: &str) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in text.as_bytes() {
        h ^= *b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    format!("{h:016x}")
}

/// The scene's labelled assumptions (comment lines that say ASSUMPTION or CALIBRATED, with
/// the comment lines that continue them), for the report's model summary: the engineer signs
/// off on them.
pub fn assumption_lines(text: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut current: Option<String> = None;
    for line in text.lines() {
        let t = line.trim();
        let comment = t.find('#').map(|i| t[i + 1..].trim());
        match comment {
            Some(c) if c.contains("ASSUMPTION") || c.contains("CALIBRATED") => {
                out.extend(current.replace(c.to_string()));
            }
            Some(c) if t.starts_with('#') && !c.is_empty() && current.is_some() => {
                if let Some(cur) = current.as_mut() {
                    cur.push(' ');
                    cur.push_str(c);
                }
            }
            _ => out.extend(current.take()),
        }
    }
    out.extend(current);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference values of the FNV-1a 64-bit test vectors (Fowler, Noll, Vo): "" and "a".
    #[test]
    fn fnv1a_matches_the_published_test_vectors() {
        assert_eq!(fnv1a(""), "cbf29ce484222325");
        assert_eq!(fnv1a("a"), "af63dc4c8601ec8c");
    }

    #[test]
    fn an_assumption_runs_on_over_its_comment_lines_only() {
        let text =
            "# ASSUMPTION: rigid platform\n# under the columns\nx = 1 # CALIBRATED: Q\n\n# note";
        assert_eq!(
            assumption_lines(text),
            [
                "ASSUMPTION: rigid platform under the columns",
                "CALIBRATED: Q"
            ]
        );
    }
}
