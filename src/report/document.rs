//! The qualification report as data: a title, a preamble and headed sections of blocks
//! (paragraphs, lists, tables, figures). It is built once from the results (`build`) and
//! rendered twice (`render_md`, `render_html`), so both formats always carry the same content.

/// The whole report.
#[derive(Debug, Clone, PartialEq)]
pub struct Document {
    /// The level-1 heading, also the HTML page title.
    pub title: String,
    /// Blocks before the first section (the verdict).
    pub preamble: Vec<Block>,
    pub sections: Vec<Section>,
}

/// A level-2 heading and what stands under it.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    pub heading: String,
    pub blocks: Vec<Block>,
}

impl Section {
    pub fn new(heading: impl Into<String>, blocks: Vec<Block>) -> Self {
        Self {
            heading: heading.into(),
            blocks,
        }
    }
}

/// One piece of content.
#[derive(Debug, Clone, PartialEq)]
pub enum Block {
    /// The overall verdict, shown prominently.
    Verdict(VerdictLine),
    Paragraph(Text),
    /// A bullet list; an empty list renders as nothing but still separates its neighbours.
    List(Vec<ListItem>),
    Table(Table),
    /// Figures one after the other, each with its caption.
    Figures(Vec<Figure>),
    /// A table folded under a one-line summary (`<details>` in both formats), for the rows
    /// an aggregated table stands for.
    Details(String, Table),
}

/// The verdict of the whole qualification.
#[derive(Debug, Clone, PartialEq)]
pub struct VerdictLine {
    pub pass: bool,
    pub gates: usize,
    pub failed: usize,
}

/// A run of inline text with emphasis.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Text(pub Vec<Span>);

/// A piece of inline text.
#[derive(Debug, Clone, PartialEq)]
pub enum Span {
    Plain(String),
    Strong(String),
    Code(String),
}

impl Text {
    /// Text without emphasis.
    pub fn plain(s: impl Into<String>) -> Self {
        Self(vec![Span::Plain(s.into())])
    }

    /// Appends plain text.
    pub fn and(mut self, s: impl Into<String>) -> Self {
        self.0.push(Span::Plain(s.into()));
        self
    }

    /// Appends strong (bold) text.
    pub fn strong(mut self, s: impl Into<String>) -> Self {
        self.0.push(Span::Strong(s.into()));
        self
    }

    /// Appends code (a file name, a hash).
    pub fn code(mut self, s: impl Into<String>) -> Self {
        self.0.push(Span::Code(s.into()));
        self
    }
}

/// A bullet with optional sub-bullets.
#[derive(Debug, Clone, PartialEq)]
pub struct ListItem {
    pub text: Text,
    pub details: Vec<Text>,
}

impl ListItem {
    pub fn new(text: Text) -> Self {
        Self {
            text,
            details: Vec::new(),
        }
    }
}

/// How a column's cells line up: text to the left, numbers to the right.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Align {
    Left,
    Right,
}

/// A column heading and its alignment.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    pub title: String,
    pub align: Align,
}

impl Column {
    pub fn left(title: &str) -> Self {
        Self {
            title: title.into(),
            align: Align::Left,
        }
    }

    pub fn right(title: &str) -> Self {
        Self {
            title: title.into(),
            align: Align::Right,
        }
    }
}

/// A table row; `failed` marks a row that reports a failure, highlighted in HTML.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub cells: Vec<String>,
    pub failed: bool,
}

/// A table of plain-text cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub columns: Vec<Column>,
    pub rows: Vec<Row>,
}

impl Table {
    pub fn new(columns: Vec<Column>) -> Self {
        Self {
            columns,
            rows: Vec::new(),
        }
    }

    /// Appends an ordinary row.
    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(Row {
            cells,
            failed: false,
        });
    }
}

/// A plot: its file stem under `plots/`, its caption and its SVG text.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub stem: String,
    pub caption: String,
    pub svg: String,
}

impl Figure {
    /// Where the SVG file lies relative to the report.
    pub fn file(&self) -> String {
        format!("plots/{}.svg", self.stem)
    }
}
