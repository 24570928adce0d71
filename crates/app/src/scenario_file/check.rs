//! Value checks while converting: each failure names the key path and the
//! allowed range.

use std::fmt::Display;

use kestrel::nav::nalgebra::Vector3;

use super::units::Unit;
use super::vec3::V3;

/// A value the scenario cannot use: where (dotted key path, arrays as
/// `name[i]`, 0-based) and why.
#[derive(Debug)]
pub(super) struct Bad {
    pub key: String,
    pub message: String,
}

/// Result of a conversion step.
pub(super) type Res<T> = Result<T, Bad>;

/// A failure at `key`.
pub(super) fn bad(key: impl Into<String>, message: impl Into<String>) -> Bad {
    Bad {
        key: key.into(),
        message: message.into(),
    }
}

/// `prefix.name` (or `name` at the top).
pub(super) fn join(prefix: &str, name: impl Display) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}.{name}")
    }
}

/// The allowed values of a number.
#[derive(Clone, Copy, Debug)]
pub(super) enum Range {
    /// Finite.
    Any,
    /// Finite and ≥ 0 (standard deviations, amplitudes).
    NonNegative,
    /// Finite and > 0 (rates, durations).
    Positive,
    /// > 0, infinity allowed (correlation times: ∞ means a constant).
    Tau,
    /// In `[lo, hi]` with open ends where the flags say so.
    Interval(f64, f64, bool, bool),
    /// ≥ the value.
    AtLeast(f64),
}

impl Range {
    fn holds(self, x: f64) -> bool {
        match self {
            Self::Any => x.is_finite(),
            Self::NonNegative => x.is_finite() && x >= 0.0,
            Self::Positive => x.is_finite() && x > 0.0,
            Self::Tau => x > 0.0,
            Self::Interval(lo, hi, lo_open, hi_open) => {
                (if lo_open { x > lo } else { x >= lo }) && (if hi_open { x < hi } else { x <= hi })
            }
            Self::AtLeast(lo) => x.is_finite() && x >= lo,
        }
    }

    fn describe(self) -> String {
        match self {
            Self::Any => "a finite number".into(),
            Self::NonNegative => "a finite number ≥ 0".into(),
            Self::Positive => "a finite number > 0".into(),
            Self::Tau => "a number > 0 (inf for none)".into(),
            Self::Interval(lo, hi, lo_open, hi_open) => format!(
                "in {}{lo}, {hi}{}",
                if lo_open { '(' } else { '[' },
                if hi_open { ')' } else { ']' }
            ),
            Self::AtLeast(lo) => format!("a finite number ≥ {lo}"),
        }
    }
}

/// `x` if it lies in `range`.
pub(super) fn num(key: &str, x: f64, range: Range) -> Res<f64> {
    if range.holds(x) {
        Ok(x)
    } else {
        Err(bad(key, format!("must be {}, found {x}", range.describe())))
    }
}

/// A required optional value.
pub(super) fn need<T>(key: &str, x: Option<T>, why: &str) -> Res<T> {
    x.ok_or_else(|| bad(key, format!("missing; {why}")))
}

/// Three values, each in `range`.
pub(super) fn vec3(key: &str, v: V3, range: Range) -> Res<Vector3<f64>> {
    for (i, &x) in v.0.iter().enumerate() {
        num(&format!("{key}[{i}]"), x, range)?;
    }
    Ok(Vector3::from(v.0))
}

/// A quantity given in at most one of several units (`stem_unit` keys):
/// checked in the file's unit, returned in SI.
pub(super) fn quantity(
    prefix: &str,
    stem: &str,
    given: &[(&Unit, Option<V3>)],
    range: Range,
) -> Res<Option<Vector3<f64>>> {
    let name = |u: &Unit| key_name(stem, u);
    let mut present = given.iter().filter(|(_, v)| v.is_some());
    let Some(&(unit, Some(v))) = present.next() else {
        return Ok(None);
    };
    if let Some((other, _)) = present.next() {
        return Err(bad(
            join(prefix, name(other)),
            format!("give `{}` or `{}`, not both", name(unit), name(other)),
        ));
    }
    let v = vec3(&join(prefix, name(unit)), v, range)?;
    Ok(Some(v.map(unit.to_si)))
}

/// [`quantity`] for a single number.
pub(super) fn scalar_quantity(
    prefix: &str,
    stem: &str,
    given: &[(&Unit, Option<f64>)],
    range: Range,
) -> Res<Option<f64>> {
    let as_v3: Vec<(&Unit, Option<V3>)> = given
        .iter()
        .map(|&(u, v)| (u, v.map(|x| V3([x; 3]))))
        .collect();
    match quantity(prefix, stem, &as_v3, range) {
        Ok(v) => Ok(v.map(|v| v.x)),
        // A scalar has no components: report the key itself.
        Err(mut e) => {
            if let Some(i) = e.key.rfind('[') {
                e.key.truncate(i);
            }
            Err(e)
        }
    }
}

/// The key of `stem` in `unit`.
pub(super) fn key_name(stem: &str, unit: &Unit) -> String {
    if unit.suffix.is_empty() {
        stem.to_string()
    } else {
        format!("{stem}_{}", unit.suffix)
    }
}

/// Fails if any of the `(name, present)` keys is set: they do not apply to
/// `what`, which takes `takes`.
pub(super) fn reject(prefix: &str, keys: &[(&str, bool)], what: &str, takes: &str) -> Res<()> {
    match keys.iter().find(|(_, present)| *present) {
        Some((name, _)) => Err(bad(
            join(prefix, name),
            format!("does not apply to {what}, which takes {takes}"),
        )),
        None => Ok(()),
    }
}
