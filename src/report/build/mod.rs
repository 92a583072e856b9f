//! Builds the report [`Document`] from the results of a qualification: one file per section,
//! assembled here in reading order.

mod analyses;
mod calibration;
mod cause;
mod environments;
mod gates;
mod joint_loads;
mod modes;
mod notes;
mod response;
mod separation;
mod test_data;

use super::Qualification;
use super::document::{Block, Document, Figure, Section};
pub(super) use super::format::{number, quantity};

/// The report of `q`, with `figures` (already drawn) in its Plots section.
pub fn document(q: &Qualification, figures: Vec<Figure>) -> Document {
    let mut sections = vec![gates::section(q), analyses::section(q)];
    sections.extend(environments::section(q));
    sections.extend(modes::section(q));
    sections.extend(calibration::section(q));
    sections.extend(response::sections(q));
    sections.extend(notes::assumptions(q));
    sections.extend(separation::section(q));
    sections.extend(test_data::section(q));
    sections.extend(notes::paper_comparison(q));
    if !figures.is_empty() {
        sections.push(Section::new("Plots", vec![Block::Figures(figures)]));
    }
    sections.push(notes::provenance(q));
    Document {
        title: format!(
            "Qualification report: {}",
            q.title.as_deref().unwrap_or(&q.scene)
        ),
        preamble: gates::preamble(q),
        sections,
    }
}

/// An optional value, or a dash when there is none.
fn or_dash(v: Option<String>) -> String {
    v.unwrap_or_else(|| "—".into())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gates::Verdict;
    use crate::report::render_html;
    use crate::report::render_md;
    use crate::results::{PaperComparison, Provenance, Skipped};

    /// A qualification with one passed and one failed gate, no analyses' results, and every
    /// section that needs none of them.
    fn small_qualification() -> Qualification {
        let gate = |name: &str, pass: bool| {
            let margin = if pass { 0.5 } else { -0.5 };
            Verdict::gate(name, 1.0, 2.0, margin, pass, "scene")
        };
        Qualification {
            scene: "small".into(),
            title: None,
            pass: false,
            gates: vec![gate("mass", true), gate("first lateral frequency", false)],
            ran: vec!["gates".into()],
            skipped: vec![Skipped {
                analysis: "modal".into(),
                reason: "no structure".into(),
            }],
            environments: None,
            modal: None,
            response: None,
            separation: None,
            test_data: None,
            paper_comparison: vec![PaperComparison {
                quantity: "mass".into(),
                paper: "1 kg".into(),
                satqual: "1.0 kg".into(),
                source: "table 1".into(),
            }],
            calibration: None,
            assumptions: vec!["rigid platform".into()],
            provenance: Provenance {
                scene_file: "small.toml".into(),
                scene_hash: "0".into(),
                satqual_version: "0".into(),
                modal_solver: None,
                separation_tolerance: None,
            },
        }
    }

    #[test]
    fn markdown_and_html_carry_the_same_sections_in_the_same_order() {
        let figure = Figure {
            stem: "f".into(),
            caption: "a figure".into(),
            svg: "<svg></svg>".into(),
        };
        let doc = document(&small_qualification(), vec![figure]);
        let md = render_md::render(&doc);
        let html = render_html::render(&doc);
        let md_headings: Vec<&str> = md.lines().filter_map(|l| l.strip_prefix("## ")).collect();
        let html_headings: Vec<&str> = html
            .split("<h2>")
            .skip(1)
            .filter_map(|h| h.split("</h2>").next())
            .collect();
        let expected = [
            "Gates",
            "Analyses",
            "Assumptions of the scene",
            "Comparison with the paper",
            "Plots",
            "Provenance",
        ];
        assert_eq!(md_headings, expected);
        assert_eq!(html_headings, expected);
        for shown in [
            "Governing gates",
            "first lateral frequency",
            "rigid platform",
            "table 1",
        ] {
            assert!(md.contains(shown) && html.contains(shown), "{shown}");
        }
        assert!(md.contains("**Verdict: FAIL** — 2 gates, 1 failed."));
        assert!(html.contains("<tr class=\"fail\"><td>first lateral frequency</td>"));
        assert!(
            html.find("Governing gates") < html.find("<h2>"),
            "governing gates come first"
        );
    }
}
