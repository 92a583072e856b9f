//! Lock-integrity gates: the governing (smallest over every load case) gapping, slip and
//! guide-bar strength margins of the sine and random analyses. The margins themselves are
//! defined where the loads are recovered, in `response::margins`.

use super::verdict::Verdict;

/// One gate per checked item: the margin as computed, renamed `kind: item (load case)` so that
/// the name alone says what it is; kind and load case stay, for the report to aggregate the
/// items of one kind and load case.
pub fn governing(margins: &[Verdict]) -> Vec<Verdict> {
    margins
        .iter()
        .map(|m| Verdict {
            name: format!("{}: {} ({})", m.kind, m.name, m.load_case),
            ..m.clone()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_margin_becomes_a_gate_named_by_kind_item_and_case() {
        let m = Verdict {
            kind: "slip".into(),
            load_case: "sine x".into(),
            ..Verdict::gate("slip joint 1", 100.0, 150.0, 0.5, true, "NASA-STD-5020B")
        };
        let g = governing(&[m]);
        assert_eq!(g[0].name, "slip: slip joint 1 (sine x)");
        assert_eq!(
            (g[0].kind.as_str(), g[0].load_case.as_str()),
            ("slip", "sine x")
        );
        assert_eq!((g[0].value, g[0].limit, g[0].margin), (100.0, 150.0, 0.5));
    }
}
