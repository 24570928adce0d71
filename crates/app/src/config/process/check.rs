//! The checks of single values: finite, positive, a standard deviation
//! whose variance is a normal double, a correlation time, a physical range,
//! each failing with the key and the value.

use super::schema::V3;
use super::*;

/// Whether a σ of 0 means "none" or is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Zero {
    Absent,
    Refused,
}

pub(super) fn id(x: f64) -> f64 {
    x
}

pub(super) struct Check<'a> {
    pub(super) source: &'a Source<'a>,
}

impl Check<'_> {
    /// The error `msg` about `key`, at its line and column.
    pub(super) fn err(&self, key: &str, msg: impl Into<String>) -> InputError {
        self.source.error(key, msg)
    }

    pub(super) fn non_negative(&self, key: &str, x: f64) -> Result<f64, InputError> {
        if x.is_finite() && x >= 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, format!("expected a finite value ≥ 0, found {x}")))
        }
    }

    pub(super) fn positive(&self, key: &str, x: f64) -> Result<f64, InputError> {
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, format!("expected a finite value > 0, found {x}")))
        }
    }

    /// A correlation time: at least
    /// [`CORRELATION_TIME_MIN`](physical::CORRELATION_TIME_MIN), `inf` (or
    /// absent) for none.
    pub(super) fn tau(&self, key: &str, x: Option<f64>) -> Result<f64, InputError> {
        match x {
            None => Ok(f64::INFINITY),
            Some(t) if t >= physical::CORRELATION_TIME_MIN => Ok(t),
            Some(t) => Err(self.err(
                key,
                format!(
                    "expected a time ≥ {} s (or inf; a shorter correlation is white noise), found {}",
                    physical::CORRELATION_TIME_MIN,
                    physical::show(t)
                ),
            )),
        }
    }

    pub(super) fn vec(
        &self,
        key: &str,
        v: V3,
        each: impl Fn(&Self, &str, f64) -> Result<f64, InputError>,
        unit: impl Fn(f64) -> f64,
    ) -> Result<Vector3<f64>, InputError> {
        let mut out = Vector3::zeros();
        for (i, x) in v.0.iter().enumerate() {
            out[i] = unit(each(self, &format!("{key}[{i}]"), *x)?);
        }
        Ok(out)
    }

    /// A lever arm, m: each component within ±[`LEVER_ARM`](physical::LEVER_ARM).
    pub(super) fn lever_arm(&self, key: &str, v: V3) -> Result<Vector3<f64>, InputError> {
        let limit = physical::LEVER_ARM;
        self.vec(
            key,
            v,
            |c: &Self, k: &str, x: f64| c.within(k, "a lever arm", "m", x, (-limit, limit)),
            id,
        )
    }

    /// `initial.week`: a full GPS week number, at most
    /// [`GPS_WEEK_MAX`](physical::GPS_WEEK_MAX) (its seconds must not wrap).
    pub(super) fn week(&self, w: u32) -> Result<u32, InputError> {
        if w <= physical::GPS_WEEK_MAX {
            Ok(w)
        } else {
            Err(self.err(
                "initial.week",
                format!(
                    "expected a GPS week in [0, {}] (the full week number, not modulo 1024), found {w}",
                    physical::GPS_WEEK_MAX
                ),
            ))
        }
    }

    /// `x` > 0 and at most `max` (a detector threshold whose larger values
    /// would accept anything).
    pub(super) fn positive_at_most(
        &self,
        key: &str,
        what: &str,
        unit: &str,
        x: f64,
        max: f64,
    ) -> Result<f64, InputError> {
        let x = self.positive(key, x)?;
        self.within(key, what, unit, x, (0.0, max))
    }

    /// A standard deviation in the unit `unit` converts to SI: positive
    /// (or 0 when `zero` is `Absent`) with a variance in SI units that is
    /// a normal double, so it neither underflows to 0 nor overflows.
    pub(super) fn sigma(
        &self,
        key: &str,
        x: f64,
        unit: fn(f64) -> f64,
        zero: Zero,
    ) -> Result<f64, InputError> {
        let si = unit(x);
        if (zero == Zero::Absent && x == 0.0) || (x > 0.0 && (si * si).is_normal()) {
            return Ok(si);
        }
        let what = match zero {
            Zero::Absent => "0 (none) or a standard deviation",
            Zero::Refused => "a standard deviation",
        };
        Err(self.err(
            key,
            format!(
                "expected {what} > 0 whose square in SI units is a normal double \
                 (neither 0 nor infinite), found {}",
                physical::show(x)
            ),
        ))
    }

    /// [`sigma`](Self::sigma) for each element of `v`.
    pub(super) fn sigmas(
        &self,
        key: &str,
        v: V3,
        unit: fn(f64) -> f64,
        zero: Zero,
    ) -> Result<Vector3<f64>, InputError> {
        let mut out = Vector3::zeros();
        for (i, x) in v.0.iter().enumerate() {
            out[i] = self.sigma(&format!("{key}[{i}]"), *x, unit, zero)?;
        }
        Ok(out)
    }

    /// `x` within the physical range `range` ([`physical`]).
    pub(super) fn within(
        &self,
        key: &str,
        what: &str,
        unit: &str,
        x: f64,
        range: (f64, f64),
    ) -> Result<f64, InputError> {
        match physical::outside(what, unit, x, range) {
            None => Ok(x),
            Some(m) => Err(self.err(key, m)),
        }
    }
}
