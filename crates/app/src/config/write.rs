//! Writing a configuration as a commented TOML file: every value in the
//! unit that reads best and converts back to exactly the same number.

use std::fmt::Write;

use kestrel::nav::nalgebra::Vector3;

use super::units::Unit;

/// Accumulates the file text.
#[derive(Default)]
pub(crate) struct Writer {
    pub out: String,
}

/// Column where trailing comments start.
const COMMENT_COLUMN: usize = 44;

impl Writer {
    /// A blank line, comment lines, then `[name]` (or `[[name]]`).
    pub fn table(&mut self, name: &str, array: bool, comment: &str) {
        self.out.push('\n');
        self.out.push_str(&comment_lines(comment));
        if array {
            let _ = writeln!(self.out, "[[{name}]]");
        } else {
            let _ = writeln!(self.out, "[{name}]");
        }
    }

    /// `key = value  # comment` with `value` already in TOML syntax.
    pub fn raw(&mut self, key: &str, value: &str, comment: &str) {
        let line = format!("{key} = {value}");
        if comment.is_empty() {
            let _ = writeln!(self.out, "{line}");
        } else {
            let pad = COMMENT_COLUMN.saturating_sub(line.chars().count()).max(1);
            let comment = one_line(comment);
            let _ = writeln!(self.out, "{line}{:pad$}# {comment}", "");
        }
    }

    /// A quoted string.
    pub fn string(&mut self, key: &str, value: &str, comment: &str) {
        let quoted = toml::Value::String(value.to_string()).to_string();
        self.raw(key, &quoted, comment);
    }

    /// A number already in the key's unit.
    pub fn num(&mut self, key: &str, x: f64, comment: &str) {
        self.raw(key, &number(x), comment);
    }

    /// A per-axis SI quantity in the best of `units` (`stem_unit = …`).
    pub fn quantity(&mut self, stem: &str, units: &[&Unit], v: Vector3<f64>, comment: &str) {
        let (unit, values) = best(units, &[v.x, v.y, v.z]);
        let text = if values.iter().all(|x| x.to_bits() == values[0].to_bits()) {
            number(values[0])
        } else {
            format!(
                "[{}, {}, {}]",
                number(values[0]),
                number(values[1]),
                number(values[2])
            )
        };
        self.raw(&unit.key(stem), &text, comment);
    }

    /// A scalar SI quantity in the best of `units`.
    pub fn scalar(&mut self, stem: &str, units: &[&Unit], x: f64, comment: &str) {
        let (unit, values) = best(units, &[x]);
        self.raw(&unit.key(stem), &number(values[0]), comment);
    }
}

/// A float in TOML syntax.
pub(crate) fn number(x: f64) -> String {
    if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else if x.is_nan() {
        "nan".into()
    } else {
        format!("{x:?}")
    }
}

/// The shortest decimal in `unit` that converts to exactly `si`.
fn decimal(unit: &Unit, si: f64) -> Option<f64> {
    if si == 0.0 || !si.is_finite() {
        return ((unit.to_si)(si) == si).then_some(si);
    }
    let guess = (unit.from_si)(si);
    (1..=17).find_map(|digits| {
        let x: f64 = format!("{guess:.*e}", digits - 1).parse().ok()?;
        ((unit.to_si)(x).to_bits() == si.to_bits()).then_some(x)
    })
}

/// Whether `x` reads well: at most 4 significant digits and, unless zero,
/// a magnitude in [0.001, 10 000).
fn reads_well(x: f64) -> bool {
    let digits = format!("{:e}", x.abs());
    let mantissa = digits.split('e').next().unwrap_or("");
    let significant = mantissa.chars().filter(char::is_ascii_digit).count();
    x == 0.0 || x.is_infinite() || (significant <= 4 && (1e-3..1e4).contains(&x.abs()))
}

/// The unit to write `si` in, with the values: the first of `units` (they
/// are in order of preference) whose exact values all read well, else the
/// exact one with the fewest characters, else the first unit's nearest.
fn best<'a>(units: &[&'a Unit], si: &[f64]) -> (&'a Unit, Vec<f64>) {
    let exact: Vec<(&Unit, Vec<f64>)> = units
        .iter()
        .filter_map(|u| {
            let values: Option<Vec<f64>> = si.iter().map(|&x| decimal(u, x)).collect();
            values.map(|v| (*u, v))
        })
        .collect();
    if let Some((u, v)) = exact.iter().find(|(_, v)| v.iter().all(|&x| reads_well(x))) {
        return (u, v.clone());
    }
    let length = |v: &Vec<f64>| v.iter().map(|&x| number(x).len()).sum::<usize>();
    match exact.into_iter().min_by_key(|(_, v)| length(v)) {
        Some(choice) => choice,
        None => (
            units[0],
            si.iter().map(|&x| (units[0].from_si)(x)).collect(),
        ),
    }
}

/// `value` (a configuration file's tables) as TOML with `header` as the
/// file's leading comment lines and `comments` beside the keys they name
/// (dotted key paths, e.g. `imu.gyro_arw`). The text is the TOML library's
/// serialization, so every string is escaped and every number reads back
/// to the same bits.
///
/// # Errors
/// A message if `value` has no TOML form.
pub(crate) fn commented_toml<T: serde::Serialize>(
    value: &T,
    header: &[String],
    comments: &[(String, String)],
) -> Result<String, String> {
    let mut doc = toml_edit::ser::to_document(value).map_err(|e| e.to_string())?;
    as_tables(doc.as_table_mut());
    for (path, comment) in comments {
        let mut parts: Vec<&str> = path.split('.').collect();
        let Some(leaf) = parts.pop() else { continue };
        let table = parts.iter().try_fold(doc.as_table_mut(), |t, p| {
            t.get_mut(p).and_then(|i| i.as_table_mut())
        });
        match table.and_then(|t| t.get_mut(leaf)) {
            Some(toml_edit::Item::Value(v)) => {
                v.decor_mut()
                    .set_suffix(format!(" # {}", one_line(comment)));
            }
            Some(toml_edit::Item::Table(t)) => {
                t.decor_mut()
                    .set_prefix(format!("\n{}", comment_lines(comment)));
            }
            _ => {}
        }
    }
    let head: String = header.iter().map(|l| comment_lines(l)).collect();
    Ok(format!("{head}{doc}"))
}

/// `text` as comment lines, one `# ` line per line of it: a line break in
/// a path or a message cannot end the comment and start live TOML.
fn comment_lines(text: &str) -> String {
    text.lines()
        .map(|l| format!("# {}\n", one_line(l)))
        .collect()
}

/// `text` with every control character (line breaks included; TOML
/// allows none in a comment but the tab) written as its Rust escape, so it
/// stays on one comment line.
fn one_line(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_control() && c != '\t' {
                c.escape_default().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// Every inline table under `table` as a `[table]` of its own (the
/// serializer writes inline tables; a file a person reads has headers).
fn as_tables(table: &mut toml_edit::Table) {
    for (_, item) in table.iter_mut() {
        if let Some(inline) = item.as_inline_table() {
            *item = toml_edit::Item::Table(inline.clone().into_table());
        }
        if let Some(t) = item.as_table_mut() {
            as_tables(t);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_break_in_a_comment_stays_inside_the_comment() {
        assert_eq!(comment_lines("a\n[output]"), "# a\n# [output]\n");
        assert_eq!(one_line("out\n[output]\rx"), "out\\n[output]\\rx");
        let header = vec!["Run with: --out o\n[output]\ninterval = 1e308".to_owned()];
        let comments = vec![("a".to_owned(), "x\ny = 2".to_owned())];
        #[derive(serde::Serialize)]
        struct T {
            a: f64,
        }
        let text = commented_toml(&T { a: 1.0 }, &header, &comments).unwrap();
        let parsed: toml::Table = toml::from_str(&text).unwrap();
        assert_eq!(parsed.len(), 1, "{text}");
        assert_eq!(parsed["a"].as_float(), Some(1.0));
    }
}
