//! Where a table or key of the model file is written: line numbers for error messages.
//!
//! The text is parsed a second time with `toml_edit`, which keeps the byte span of every
//! table header and key (the `toml::Table` that validation reads has none). A location is
//! `(top-level key, index in an array of tables, key)`; `[[material]]` #3's `young` is
//! `("material", Some(2), Some("young"))`. Errors then end with `(FILE, line N)`. A place
//! the locator cannot resolve (inline tables written in unusual ways, a key that is
//! missing) simply gets no line.

use std::ops::Deref;
use toml::Table;
use toml_edit::{ImDocument, Item};

/// The parsed model tree together with the source's name and spans.
pub(crate) struct Doc<'a> {
    root: &'a Table,
    source: &'a str,
    text: &'a str,
    spans: Option<ImDocument<&'a str>>,
}

impl<'a> Deref for Doc<'a> {
    type Target = Table;
    fn deref(&self) -> &Table {
        self.root
    }
}

impl<'a> Doc<'a> {
    pub fn new(root: &'a Table, source: &'a str, text: &'a str) -> Self {
        Doc {
            root,
            source,
            text,
            spans: ImDocument::parse(text).ok(),
        }
    }

    /// 1-based line of `top[index].key` (or of the table's header when `key` is `None`).
    pub fn line(&self, top: &str, index: Option<usize>, key: Option<&str>) -> Option<usize> {
        let doc = self.spans.as_ref()?;
        let item = doc.as_table().get(top)?;
        let span = match (item, index) {
            (Item::Table(t), None) => match key {
                Some(k) => t.key(k)?.span(),
                None => t.span(),
            },
            (Item::ArrayOfTables(a), Some(i)) => {
                let t = a.get(i)?;
                match key {
                    Some(k) => t.key(k)?.span(),
                    None => t.span(),
                }
            }
            (Item::Value(v), _) => {
                let inline = match (v, index) {
                    (toml_edit::Value::InlineTable(t), None) => t,
                    (toml_edit::Value::Array(a), Some(i)) => a.get(i)?.as_inline_table()?,
                    _ => return None,
                };
                match key {
                    Some(k) => inline.key(k)?.span(),
                    None => inline.span(),
                }
            }
            _ => None,
        }?;
        self.line_at(span.start)
    }

    /// 1-based line of `top.sub.key` (a table inside a single top-level table, such as
    /// `[base_motion.x]` or `x = { … }` in `[base_motion]`), or of `sub` itself when
    /// `key` is `None`.
    pub fn line_sub(&self, top: &str, sub: &str, key: Option<&str>) -> Option<usize> {
        let doc = self.spans.as_ref()?;
        let parent = doc.as_table().get(top)?.as_table_like()?;
        let span = match key {
            Some(k) => parent.get(sub)?.as_table_like()?.key(k)?.span(),
            None => parent.key(sub)?.span(),
        }?;
        self.line_at(span.start)
    }

    /// ` (FILE, line N)` of `top.sub.key` (see [`Doc::line_sub`]), falling back to the
    /// line of `sub`, then of `top`; or nothing.
    pub fn at_sub(&self, top: &str, sub: &str, key: Option<&str>) -> String {
        let line = self
            .line_sub(top, sub, key)
            .or_else(|| self.line_sub(top, sub, None))
            .or_else(|| self.top_line(top));
        self.suffix(line)
    }

    /// 1-based line of a byte offset into the text.
    fn line_at(&self, offset: usize) -> Option<usize> {
        Some(self.text.get(..offset)?.matches('\n').count() + 1)
    }

    /// 1-based line of a top-level key (a table header, or `key = value` at the top).
    pub fn top_line(&self, top: &str) -> Option<usize> {
        let span = self.spans.as_ref()?.as_table().key(top)?.span()?;
        self.line_at(span.start)
    }

    /// ` (FILE, line N)` of a top-level key, or nothing.
    pub fn at_top(&self, top: &str) -> String {
        self.suffix(self.top_line(top))
    }

    /// ` (FILE, line N)` for a place, or nothing when it cannot be located.
    pub fn at(&self, top: &str, index: Option<usize>, key: Option<&str>) -> String {
        self.suffix(self.line(top, index, key))
    }

    fn suffix(&self, line: Option<usize>) -> String {
        match line {
            Some(l) => format!(" ({}, line {l})", self.source),
            None => String::new(),
        }
    }

    /// Typed access to one table, whose errors carry its line numbers.
    pub fn fields(
        &'a self,
        place: impl Into<String>,
        table: &'a Table,
        top: &'static str,
        index: Option<usize>,
    ) -> super::reader::Fields<'a> {
        super::reader::Fields::new(place, table).located(self, top, index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "# a model\nblock = [{ name = \"x\" },\n  { vertices = 1 }]\n[analysis]\ndt = 0.1\n\nsteps = 3\n\n[[material]]\nname = \"a\"\n\n[[material]]\nname = \"b\"\nyoung = 1.0\n";

    #[test]
    fn lines_of_tables_and_keys() {
        let root: Table = toml::from_str(TEXT).unwrap();
        let d = Doc::new(&root, "m.toml", TEXT);
        assert_eq!(d.line("analysis", None, None), Some(4));
        assert_eq!(d.line("analysis", None, Some("steps")), Some(7));
        assert_eq!(d.line("material", Some(1), None), Some(12));
        assert_eq!(d.line("material", Some(1), Some("young")), Some(14));
        assert_eq!(d.line("material", Some(0), Some("young")), None);
        assert_eq!(d.line("material", Some(2), None), None);
        assert_eq!(d.line("block", Some(0), Some("name")), Some(2));
        assert_eq!(d.line("block", Some(1), Some("vertices")), Some(3));
        assert_eq!(d.line("block", Some(0), Some("vertices")), None);
        assert_eq!(d.at("analysis", None, Some("dt")), " (m.toml, line 5)");
        assert_eq!(d.at("cover", None, None), "");
        assert_eq!(d.top_line("block"), Some(2));
        assert_eq!(d.top_line("analysis"), Some(4));
    }

    #[test]
    fn lines_of_sub_tables() {
        let text = "[base_motion]\nstart = 1.0\nx = { file = \"a.AT2\", pga = 0.3 }\n\n[base_motion.y]\nfile = \"b.AT2\"\nscale = 2.0\n";
        let root: Table = toml::from_str(text).unwrap();
        let d = Doc::new(&root, "m.toml", text);
        assert_eq!(d.line_sub("base_motion", "x", Some("pga")), Some(3));
        assert_eq!(d.line_sub("base_motion", "x", None), Some(3));
        assert_eq!(d.line_sub("base_motion", "y", Some("scale")), Some(7));
        assert_eq!(d.line_sub("base_motion", "y", None), Some(5));
        assert_eq!(
            d.at_sub("base_motion", "y", Some("nope")),
            " (m.toml, line 5)"
        );
    }
}
