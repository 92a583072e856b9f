//! Renders a [`Document`] as one self-contained HTML page: inline SVG figures, inline style,
//! no network access, printable.

use super::document::{Align, Block, Document, Figure, ListItem, Span, Table, Text, VerdictLine};

const STYLE: &str = "body{font-family:sans-serif;max-width:1300px;margin:1em auto;color:#222}
details{margin:.5em 0} summary{cursor:pointer;color:#036}
table{border-collapse:collapse;margin:1em 0;font-size:90%}
td,th{border:1px solid #bbb;padding:3px 8px}
th{background:#eee}
td.num{text-align:right;white-space:nowrap}
tr.fail td{color:#b00;font-weight:bold;background:#fee}
.verdict{font-size:150%;padding:.5em;border:2px solid}
.pass{color:#060;border-color:#060}
.failv{color:#b00;border-color:#b00}
figure{margin:1em 0;page-break-inside:avoid} figure svg{max-width:100%;height:auto}
@media print{body{max-width:none}}
";

/// Escapes the characters HTML text must not contain literally.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The whole document as an HTML page.
pub fn render(doc: &Document) -> String {
    let title = esc(&doc.title);
    let mut s = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{title}</title>\n\
         <style>\n{STYLE}</style></head><body>\n<h1>{title}</h1>\n"
    );
    for b in &doc.preamble {
        s.push_str(&block(b));
    }
    for section in &doc.sections {
        s.push_str(&format!("<h2>{}</h2>\n", esc(&section.heading)));
        for b in &section.blocks {
            s.push_str(&block(b));
        }
    }
    s.push_str("</body></html>\n");
    s
}

fn block(b: &Block) -> String {
    match b {
        Block::Verdict(v) => verdict(v),
        Block::Paragraph(t) => format!("<p>{}</p>\n", text(t)),
        Block::List(items) if items.is_empty() => String::new(),
        Block::List(items) => format!("<ul>\n{}</ul>\n", list_items(items)),
        Block::Table(t) => table(t),
        Block::Figures(figs) => figs.iter().map(figure).collect(),
        Block::Details(summary, t) => format!(
            "<details><summary>{}</summary>\n{}</details>\n",
            esc(summary),
            table(t)
        ),
    }
}

fn verdict(v: &VerdictLine) -> String {
    format!(
        "<p class=\"verdict {}\">Verdict: <b>{}</b> — {} gates, {} failed.</p>\n",
        if v.pass { "pass" } else { "failv" },
        if v.pass { "PASS" } else { "FAIL" },
        v.gates,
        v.failed
    )
}

fn text(t: &Text) -> String {
    t.0.iter()
        .map(|s| match s {
            Span::Plain(p) => esc(p),
            Span::Strong(p) => format!("<b>{}</b>", esc(p)),
            Span::Code(p) => format!("<code>{}</code>", esc(p)),
        })
        .collect()
}

fn list_items(items: &[ListItem]) -> String {
    let mut s = String::new();
    for item in items {
        s.push_str(&format!("<li>{}", text(&item.text)));
        if !item.details.is_empty() {
            s.push_str("<ul>");
            for d in &item.details {
                s.push_str(&format!("<li>{}</li>", text(d)));
            }
            s.push_str("</ul>");
        }
        s.push_str("</li>\n");
    }
    s
}

fn table(t: &Table) -> String {
    let mut s = String::from("<table><tr>");
    for c in &t.columns {
        s.push_str(&format!("<th>{}</th>", esc(&c.title)));
    }
    s.push_str("</tr>\n");
    for row in &t.rows {
        s.push_str(if row.failed {
            "<tr class=\"fail\">"
        } else {
            "<tr>"
        });
        for (cell, col) in row.cells.iter().zip(&t.columns) {
            let class = match col.align {
                Align::Left => "",
                Align::Right => " class=\"num\"",
            };
            s.push_str(&format!("<td{class}>{}</td>", esc(cell)));
        }
        s.push_str("</tr>\n");
    }
    s.push_str("</table>\n");
    s
}

/// The SVG goes inline, without its XML declaration: a declaration is only valid at the start
/// of a document.
fn figure(f: &Figure) -> String {
    let svg = f.svg.trim_start_matches(|c| c != '<');
    let svg = svg
        .strip_prefix("<?xml version=\"1.0\" encoding=\"UTF-8\"?>")
        .unwrap_or(svg);
    format!(
        "<figure>{svg}<figcaption>{}</figcaption></figure>\n",
        esc(&f.caption)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::document::{Column, Row, Section};

    #[test]
    fn table_cells_are_escaped_and_failed_rows_marked() {
        let mut t = Table::new(vec![Column::left("gate"), Column::right("margin")]);
        t.row(vec!["a < b & c".into(), "+1.0%".into()]);
        t.rows.push(Row {
            cells: vec!["<script>".into(), "-3.0%".into()],
            failed: true,
        });
        // Expected text written by hand: HTML escapes `&`, `<`, `>` (HTML Living Standard,
        // "escapingString"); numbers align right through the `num` class of the style.
        assert_eq!(
            table(&t),
            "<table><tr><th>gate</th><th>margin</th></tr>\n\
             <tr><td>a &lt; b &amp; c</td><td class=\"num\">+1.0%</td></tr>\n\
             <tr class=\"fail\"><td>&lt;script&gt;</td><td class=\"num\">-3.0%</td></tr>\n\
             </table>\n"
        );
    }

    #[test]
    fn headings_lists_and_inline_emphasis() {
        let doc = Document {
            title: "R & D".into(),
            preamble: vec![],
            sections: vec![Section::new(
                "Analyses",
                vec![Block::List(vec![ListItem {
                    text: Text::plain("skipped ")
                        .strong("modal")
                        .and(": ")
                        .code("a.toml"),
                    details: vec![Text::plain("x<y")],
                }])],
            )],
        };
        let html = render(&doc);
        assert!(html.contains("<title>R &amp; D</title>"));
        assert!(html.contains("<h1>R &amp; D</h1>\n<h2>Analyses</h2>\n"));
        assert!(html.contains(
            "<ul>\n<li>skipped <b>modal</b>: <code>a.toml</code><ul><li>x&lt;y</li></ul></li>\n</ul>\n"
        ));
        assert!(html.ends_with("</body></html>\n"));
    }

    #[test]
    fn inline_svg_loses_its_xml_declaration() {
        let f = Figure {
            stem: "s".into(),
            caption: "a & b".into(),
            svg: "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg></svg>".into(),
        };
        assert_eq!(
            figure(&f),
            "<figure>\n<svg></svg><figcaption>a &amp; b</figcaption></figure>\n"
        );
    }
}
