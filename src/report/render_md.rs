//! Renders a [`Document`] as Markdown, plots referenced as SVG files beside it.
//!
//! Layout: every heading and block renders to whole lines, and consecutive pieces are
//! separated by one blank line. An empty list renders as nothing, so it leaves two blank lines
//! between its neighbours; the figures end each with a blank line. Existing reports have this
//! exact shape, and reviewers diff reports between runs, so it is kept byte for byte.

use super::document::{Align, Block, Document, Figure, ListItem, Span, Table, Text, VerdictLine};

/// The whole document as Markdown.
pub fn render(doc: &Document) -> String {
    let mut pieces = vec![format!("# {}\n", doc.title)];
    pieces.extend(doc.preamble.iter().map(block));
    for section in &doc.sections {
        pieces.push(format!("## {}\n", section.heading));
        pieces.extend(section.blocks.iter().map(block));
    }
    pieces.join("\n")
}

fn block(b: &Block) -> String {
    match b {
        Block::Verdict(v) => verdict(v),
        Block::Paragraph(t) => format!("{}\n", text(t)),
        Block::List(items) => items.iter().map(list_item).collect(),
        Block::Table(t) => table(t),
        Block::Figures(figs) => figs.iter().map(figure).collect(),
        // GitHub and most viewers render Markdown inside <details> after a blank line.
        Block::Details(summary, t) => format!(
            "<details><summary>{}</summary>\n\n{}\n</details>\n",
            summary.replace('<', "&lt;"),
            table(t)
        ),
    }
}

fn verdict(v: &VerdictLine) -> String {
    format!(
        "**Verdict: {}** — {} gates, {} failed.\n",
        if v.pass { "PASS" } else { "FAIL" },
        v.gates,
        v.failed
    )
}

fn text(t: &Text) -> String {
    t.0.iter()
        .map(|s| match s {
            Span::Plain(p) => p.clone(),
            Span::Strong(p) => format!("**{p}**"),
            Span::Code(p) => format!("`{p}`"),
        })
        .collect()
}

fn list_item(item: &ListItem) -> String {
    let mut s = format!("- {}\n", text(&item.text));
    for d in &item.details {
        s.push_str(&format!("  - {}\n", text(d)));
    }
    s
}

/// A pipe inside a cell would end the cell early.
fn cell(s: &str) -> String {
    s.replace('|', "\\|")
}

fn table_line(cells: impl Iterator<Item = String>) -> String {
    format!("| {} |\n", cells.collect::<Vec<_>>().join(" | "))
}

fn table(t: &Table) -> String {
    let mut s = table_line(t.columns.iter().map(|c| cell(&c.title)));
    for c in &t.columns {
        s.push_str(match c.align {
            Align::Left => "|---",
            Align::Right => "|---:",
        });
    }
    s.push_str("|\n");
    for row in &t.rows {
        s.push_str(&table_line(row.cells.iter().map(|c| cell(c))));
    }
    s
}

fn figure(f: &Figure) -> String {
    format!("![{}]({})\n\n*{}*\n\n", f.caption, f.file(), f.caption)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::document::{Column, Section};

    fn small_document() -> Document {
        let mut t = Table::new(vec![Column::left("name"), Column::right("value")]);
        t.row(vec!["a|b".into(), "1.5".into()]);
        Document {
            title: "Report".into(),
            preamble: vec![Block::Verdict(VerdictLine {
                pass: false,
                gates: 2,
                failed: 1,
            })],
            sections: vec![
                Section::new(
                    "Numbers",
                    vec![
                        Block::Table(t),
                        Block::Paragraph(Text::plain("see ").code("x.csv")),
                    ],
                ),
                Section::new(
                    "Notes",
                    vec![Block::List(vec![ListItem {
                        text: Text::plain("skipped ").strong("modal"),
                        details: vec![Text::plain("why")],
                    }])],
                ),
            ],
        }
    }

    #[test]
    fn renders_headings_tables_and_lists_with_one_blank_line_between_blocks() {
        // Expected text written by hand from the layout rules in the module documentation.
        let expected = "# Report\n\n**Verdict: FAIL** — 2 gates, 1 failed.\n\n## Numbers\n\n\
                        | name | value |\n|---|---:|\n| a\\|b | 1.5 |\n\nsee `x.csv`\n\n\
                        ## Notes\n\n- skipped **modal**\n  - why\n";
        assert_eq!(render(&small_document()), expected);
    }

    #[test]
    fn an_empty_list_leaves_two_blank_lines() {
        let doc = Document {
            title: "T".into(),
            preamble: vec![Block::Paragraph(Text::plain("p")), Block::List(vec![])],
            sections: vec![Section::new("S", vec![])],
        };
        assert_eq!(render(&doc), "# T\n\np\n\n\n## S\n");
    }

    #[test]
    fn figures_link_their_svg_file_and_end_with_a_blank_line() {
        let fig = Figure {
            stem: "speed".into(),
            caption: "Speed".into(),
            svg: "<svg/>".into(),
        };
        assert_eq!(
            block(&Block::Figures(vec![fig.clone(), fig])),
            "![Speed](plots/speed.svg)\n\n*Speed*\n\n![Speed](plots/speed.svg)\n\n*Speed*\n\n"
        );
    }
}
