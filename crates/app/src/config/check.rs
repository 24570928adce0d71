//! Value checks while converting: each failure names the key path and the
//! allowed range.

use std::fmt::Display;

use kestrel::nav::nalgebra::Vector3;

use super::units::Unit;
use super::vec3::V3;

/// A value the scenario cannot use: where (dotted key path, arrays as
/// `name[i]`, 0-based) and why.
#[derive(Debug)]
pub(crate) struct Bad {
    pub key: String,
    pub message: String,
}

/// Result of a conversion step.
pub(crate) type Res<T> = Result<T, Bad>;

/// A failure at `key`.
pub(crate) fn bad(key: impl Into<String>, message: impl Into<String>) -> Bad {
    Bad {
        key: key.into(),
        message: message.into(),
    }
}

/// `prefix.name` (or `name` at the top).
pub(crate) fn join(prefix: &str, name: impl Display) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}.{name}")
    }
}

/// The allowed values of a number.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Range {
    /// Finite.
    Any,
    /// Finite and ≥ 0 (standard deviations, amplitudes).
    NonNegative,
    /// Finite and > 0 (rates, durations).
    Positive,
    /// At least [`CORRELATION_TIME_MIN`](kestrel_io::gins::physical::CORRELATION_TIME_MIN),
    /// infinity allowed (correlation times: ∞ means a constant).
    Tau,
    /// In `[lo, hi]` with open ends where the flags say so.
    Interval(f64, f64, bool, bool),
}

impl Range {
    fn holds(self, x: f64) -> bool {
        match self {
            Self::Any => x.is_finite(),
            Self::NonNegative => x.is_finite() && x >= 0.0,
            Self::Positive => x.is_finite() && x > 0.0,
            Self::Tau => x >= kestrel_io::gins::physical::CORRELATION_TIME_MIN,
            Self::Interval(lo, hi, lo_open, hi_open) => {
                (if lo_open { x > lo } else { x >= lo }) && (if hi_open { x < hi } else { x <= hi })
            }
        }
    }

    fn describe(self) -> String {
        match self {
            Self::Any => "a finite number".into(),
            Self::NonNegative => "a finite number ≥ 0".into(),
            Self::Positive => "a finite number > 0".into(),
            Self::Tau => format!(
                "a time ≥ {} s (or inf; a shorter correlation is white noise)",
                kestrel_io::gins::physical::CORRELATION_TIME_MIN
            ),
            Self::Interval(lo, hi, lo_open, hi_open) => format!(
                "a number in {}{lo}, {hi}{}",
                if lo_open { '(' } else { '[' },
                if hi_open { ')' } else { ']' }
            ),
        }
    }
}

/// `x` if it lies in `range`.
pub(crate) fn num(key: &str, x: f64, range: Range) -> Res<f64> {
    if range.holds(x) {
        Ok(x)
    } else {
        Err(bad(
            key,
            format!(
                "expected {}, found {}",
                range.describe(),
                kestrel_io::gins::physical::show(x)
            ),
        ))
    }
}

/// A required optional value.
pub(crate) fn need<T>(key: &str, x: Option<T>, why: &str) -> Res<T> {
    x.ok_or_else(|| bad(key, format!("missing; {why}")))
}

/// Three values, each in `range`.
pub(crate) fn vec3(key: &str, v: V3, range: Range) -> Res<Vector3<f64>> {
    for (i, &x) in v.0.iter().enumerate() {
        num(&component(key, &v, i), x, range)?;
    }
    Ok(Vector3::from(v.0))
}

/// A lever arm, m: each component within
/// ±[`LEVER_ARM`](kestrel_io::gins::physical::LEVER_ARM).
pub(crate) fn lever_arm(key: &str, v: V3) -> Res<Vector3<f64>> {
    use kestrel_io::gins::physical::{outside, LEVER_ARM};
    for (i, &x) in v.0.iter().enumerate() {
        if let Some(m) = outside("a lever arm", "m", x, (-LEVER_ARM, LEVER_ARM)) {
            return Err(bad(component(key, &v, i), m));
        }
    }
    Ok(Vector3::from(v.0))
}

/// An Earth constant within
/// [`EARTH_CONSTANT_TOLERANCE`](kestrel_io::gins::physical::EARTH_CONSTANT_TOLERANCE)
/// of WGS-84's value `wgs84`.
pub(crate) fn earth_constant(key: &str, x: f64, wgs84: f64, unit: &str) -> Res<f64> {
    use kestrel_io::gins::physical::{show, EARTH_CONSTANT_TOLERANCE};
    if (x / wgs84 - 1.0).abs() <= EARTH_CONSTANT_TOLERANCE {
        Ok(x)
    } else {
        Err(bad(
            key,
            format!(
                "expected a value within {} % of WGS-84's {wgs84:e} {unit}, found {}",
                EARTH_CONSTANT_TOLERANCE * 100.0,
                show(x)
            ),
        ))
    }
}

/// The key of component `i` of `v`: `key[i]`, or `key` when the three are
/// one number (as a file gives a value for every axis).
pub(crate) fn component(key: &str, v: &V3, i: usize) -> String {
    let [x, y, z] = v.0;
    if x.to_bits() == y.to_bits() && y.to_bits() == z.to_bits() {
        key.to_string()
    } else {
        format!("{key}[{i}]")
    }
}

/// A quantity given in at most one of several units (`stem_unit` keys):
/// checked in the file's unit, returned in SI.
pub(crate) fn quantity(
    prefix: &str,
    stem: &str,
    given: &[(&Unit, Option<V3>)],
    range: Range,
) -> Res<Option<Vector3<f64>>> {
    let name = |u: &Unit| u.key(stem);
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

/// A standard deviation given in one of `given`'s units (or absent:
/// `None`): `> 0` (or 0 when `zero_is_none`) with a variance in SI units
/// that is a normal double, so it neither underflows to 0 nor overflows.
pub(crate) fn sigma(
    prefix: &str,
    stem: &str,
    given: &[(&Unit, Option<V3>)],
    zero_is_none: bool,
) -> Res<Option<Vector3<f64>>> {
    let Some(si) = quantity(prefix, stem, given, Range::Any)? else {
        return Ok(None);
    };
    let Some(&(unit, Some(raw))) = given.iter().find(|(_, v)| v.is_some()) else {
        return Ok(Some(si));
    };
    for i in 0..3 {
        let (x, s) = (raw.0[i], si[i]);
        if !((zero_is_none && x == 0.0) || (x > 0.0 && (s * s).is_normal())) {
            let what = if zero_is_none {
                "0 (none) or a standard deviation"
            } else {
                "a standard deviation"
            };
            return Err(bad(
                component(&join(prefix, unit.key(stem)), &raw, i),
                format!(
                    "expected {what} > 0 whose square in SI units is a normal double \
                     (neither 0 nor infinite), found {}",
                    kestrel_io::gins::physical::show(x)
                ),
            ));
        }
    }
    Ok(Some(si))
}

/// A plausibility bound: the largest magnitude a quantity can have, in
/// SI, and what is beyond it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bound {
    pub max_si: f64,
    pub beyond: &'static str,
}

/// The quantity `stem` of `given` (if given) within `bound` in magnitude;
/// the message states the bound in the unit of the key that was given.
pub(crate) fn bounded(
    prefix: &str,
    stem: &str,
    given: &[(&Unit, Option<V3>)],
    bound: Bound,
) -> Res<()> {
    let Some(&(unit, Some(raw))) = given.iter().find(|(_, v)| v.is_some()) else {
        return Ok(());
    };
    for (i, &x) in raw.0.iter().enumerate() {
        let si = unit.si(x).abs();
        if si.is_nan() || si > bound.max_si {
            let max = unit.exact(bound.max_si);
            return Err(bad(
                component(&join(prefix, unit.key(stem)), &raw, i),
                format!(
                    "expected at most {} in magnitude ({}), found {}",
                    kestrel_io::gins::physical::show(max),
                    bound.beyond,
                    kestrel_io::gins::physical::show(x)
                ),
            ));
        }
    }
    Ok(())
}

/// [`quantity`] for a single number.
pub(crate) fn scalar_quantity(
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

/// Fails if any of the `(name, present)` keys is set: they do not apply to
/// `what`, which takes `takes`.
pub(crate) fn reject(prefix: &str, keys: &[(&str, bool)], what: &str, takes: &str) -> Res<()> {
    match keys.iter().find(|(_, present)| *present) {
        Some((name, _)) => Err(bad(
            join(prefix, name),
            format!("does not apply to {what}, which takes {takes}"),
        )),
        None => Ok(()),
    }
}
