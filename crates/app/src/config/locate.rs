//! Where keys are in the file: a map from key paths to byte spans, built
//! from the spanned TOML document, and byte offsets to line and column.

use std::ops::Range;

use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// One key or array element of the document.
struct Entry {
    /// Dotted key path, arrays as `name[i]` (0-based).
    path: String,
    /// Span of the value.
    value: Range<usize>,
    /// Span of the key, if it has one (array elements do not).
    key: Option<Range<usize>>,
    /// Whether the value is a table.
    table: bool,
}

/// The key paths of a document (`gnss.outlier[2].start_s`) with their
/// spans.
pub(crate) struct Places {
    entries: Vec<Entry>,
}

impl Places {
    /// The places of `text`; empty if it does not parse.
    pub fn new(text: &str) -> Self {
        let mut entries = Vec::new();
        if let Ok(doc) = DeTable::parse(text) {
            table(&mut entries, "", doc.get_ref());
        }
        Self { entries }
    }

    /// Where to point for `path` (or its nearest ancestor in the file): at
    /// a value, or at the key of a table (whose own span may cover its
    /// whole body).
    pub fn span_of(&self, path: &str) -> Option<Range<usize>> {
        let mut p = path;
        loop {
            if let Some(e) = self.entries.iter().find(|e| e.path == p) {
                return Some(match &e.key {
                    Some(k) if e.table => k.clone(),
                    _ => e.value.clone(),
                });
            }
            let cut = p.rfind(['.', '['])?;
            p = &p[..cut];
        }
    }

    /// The path of the innermost key or value containing `offset`.
    pub fn path_at(&self, offset: usize) -> Option<&str> {
        self.entries
            .iter()
            .flat_map(|e| {
                [Some(&e.value), e.key.as_ref()]
                    .into_iter()
                    .flatten()
                    .map(move |s| (e.path.as_str(), s))
            })
            .filter(|(_, s)| s.start <= offset && offset < s.end.max(s.start + 1))
            .min_by_key(|(_, s)| s.end - s.start)
            .map(|(p, _)| p)
    }
}

fn table(out: &mut Vec<Entry>, prefix: &str, t: &DeTable<'_>) {
    for (k, v) in t.iter() {
        let path = if prefix.is_empty() {
            k.get_ref().to_string()
        } else {
            format!("{prefix}.{}", k.get_ref())
        };
        value(out, path, Some(k.span()), v);
    }
}

fn value(out: &mut Vec<Entry>, path: String, key: Option<Range<usize>>, v: &Spanned<DeValue<'_>>) {
    out.push(Entry {
        path: path.clone(),
        value: v.span(),
        key,
        table: v.get_ref().is_table(),
    });
    match v.get_ref() {
        DeValue::Table(t) => table(out, &path, t),
        DeValue::Array(a) => {
            for (i, item) in a.iter().enumerate() {
                value(out, format!("{path}[{i}]"), None, item);
            }
        }
        _ => {}
    }
}

/// 1-based line and column (in characters) of byte `offset` of `text`.
pub(crate) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}
