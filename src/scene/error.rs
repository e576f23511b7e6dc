//! What is wrong with a scene, and where: the origin (file path or lesson),
//! the line and column when the problem sits at a place in the file, the
//! field, and what the field must be.

use std::fmt;

#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The file's path, or `lesson NAME`.
    pub origin: String,
    /// 1-based line and column, when known.
    pub at: Option<(usize, usize)>,
    /// Dotted field name (`world.dt`, `body[2].radius`), when one is at fault.
    pub field: Option<String>,
    pub message: String,
    /// The offending source line, shown under the message.
    pub source_line: Option<String>,
}

impl SceneError {
    pub(crate) fn new(origin: &str, message: impl Into<String>) -> Self {
        Self {
            origin: origin.to_string(),
            at: None,
            field: None,
            message: message.into(),
            source_line: None,
        }
    }

    pub(crate) fn field(mut self, field: impl Into<String>) -> Self {
        self.field = Some(field.into());
        self
    }

    /// Place the error at byte `offset` of `source`.
    pub(crate) fn at_offset(mut self, source: &str, offset: usize) -> Self {
        let (line, column) = line_column(source, offset);
        let line_start = source[..offset.min(source.len())]
            .rfind('\n')
            .map_or(0, |i| i + 1);
        self.at = Some((line, column));
        self.source_line = source[line_start..]
            .lines()
            .next()
            .map(|l| match line_start {
                0 => l.strip_prefix(BYTE_ORDER_MARK).unwrap_or(l).to_string(),
                _ => l.to_string(),
            });
        self
    }
}

/// The dotted name of the field a deserialisation error is in
/// (`world.dt`, `body[1].mass`), from the path serde followed to it;
/// `None` at the top of the file. The keys [`toml::Spanned`] uses inside
/// to carry a value's place are no field names and are left out.
pub(crate) fn field_path(path: &serde_path_to_error::Path) -> Option<String> {
    use serde_path_to_error::Segment;
    let mut name = String::new();
    for segment in path {
        match segment {
            Segment::Seq { index } => name += &format!("[{index}]"),
            Segment::Map { key } | Segment::Enum { variant: key } => {
                if key.starts_with("$__serde_spanned_private") {
                    continue;
                }
                if !name.is_empty() {
                    name.push('.');
                }
                name += key;
            }
            Segment::Unknown => break,
        }
    }
    (!name.is_empty()).then_some(name)
}

/// Where each line of a source starts, so that many offsets find their
/// line in one pass over the text (a scene of 40,000 `[[spawn]]` entries
/// notes the line of each).
pub(crate) struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    pub(crate) fn new(source: &str) -> Self {
        let starts = std::iter::once(0)
            .chain(source.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Self { starts }
    }

    /// 1-based line of byte `offset`.
    pub(crate) fn line(&self, offset: usize) -> usize {
        self.starts.partition_point(|&start| start <= offset)
    }
}

/// 1-based line and column of byte `offset` in `source`. A byte-order
/// mark that begins the file is no column of its first line.
pub(crate) fn line_column(source: &str, offset: usize) -> (usize, usize) {
    let before = &source[..offset.min(source.len())];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let in_line = &before[line_start..];
    let in_line = match line_start {
        0 => in_line.strip_prefix(BYTE_ORDER_MARK).unwrap_or(in_line),
        _ => in_line,
    };
    (line, in_line.chars().count() + 1)
}

/// What some editors begin a UTF-8 file with; TOML readers skip it.
const BYTE_ORDER_MARK: char = '\u{feff}';

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.origin)?;
        if let Some((line, column)) = self.at {
            write!(f, ":{line}:{column}")?;
        }
        write!(f, ": ")?;
        if let Some(field) = &self.field {
            write!(f, "{field}: ")?;
        }
        write!(f, "{}", self.message)?;
        if let (Some((line, _)), Some(text)) = (self.at, &self.source_line) {
            write!(f, "\n{line:>5} | {text}")?;
        }
        Ok(())
    }
}

impl std::error::Error for SceneError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_index_agrees_with_line_column() {
        let source = "a = 1\n\n[[spawn]]\ncount = 2\nlast";
        let index = LineIndex::new(source);
        for offset in 0..=source.len() {
            assert_eq!(
                index.line(offset),
                line_column(source, offset).0,
                "{offset}"
            );
        }
    }

    #[test]
    fn a_byte_order_mark_that_begins_the_file_is_no_column() {
        let source = "\u{feff}x = 1\ny = 2\n";
        assert_eq!(line_column(source, 3), (1, 1), "x");
        assert_eq!(line_column(source, 7), (1, 5), "1");
        assert_eq!(line_column(source, 9), (2, 1), "y");
        let e = SceneError::new("b.toml", "unknown field").at_offset(source, 3);
        assert_eq!(e.to_string(), "b.toml:1:1: unknown field\n    1 | x = 1");
    }
}
