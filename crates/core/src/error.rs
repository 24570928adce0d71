//! Typed failures of predict and update, in the user's terms: which
//! quantity (the one the user supplied, or the step that produced it) and
//! where in that object (row and column).

use core::fmt;

use nalgebra::SMatrix;

use crate::real::finite;

/// The quantity an error is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Quantity {
    /// The state given to the constructor or [`Filter::set_state`](crate::Filter::set_state).
    State,
    /// The state covariance `P` given to the constructor or
    /// [`Filter::set_covariance`](crate::Filter::set_covariance), or the
    /// filter's own covariance when the form must factor it.
    StateCovariance,
    /// The time step `dt` given to `predict`.
    TimeStep,
    /// The process noise covariance `Q` returned by
    /// [`ProcessModel::noise`](crate::ProcessModel::noise).
    ProcessNoise,
    /// The state-transition matrix `Φ` returned by
    /// [`LinearizedProcess::transition`](crate::LinearizedProcess::transition).
    Transition,
    /// The propagated state `f(x, dt)` returned by
    /// [`ProcessModel::propagate`](crate::ProcessModel::propagate) (for a
    /// sigma point in the unscented forms).
    PropagatedState,
    /// The propagated covariance `Φ P Φᵀ` (overflow), or the recorded prior
    /// covariance `P⁻` the RTS smoother must factor.
    PropagatedCovariance,
    /// The measurement vector `z` given to `update` (or the innovation
    /// computed from it).
    Measurement,
    /// The measurement noise covariance `R` returned by
    /// [`MeasurementModel::noise`](crate::MeasurementModel::noise) or set by
    /// an adapter.
    MeasurementNoise,
    /// The predicted measurement `h(x)` returned by
    /// [`MeasurementModel::predict`](crate::MeasurementModel::predict).
    PredictedMeasurement,
    /// The Jacobian `H` returned by
    /// [`LinearizedMeasurement::jacobian`](crate::LinearizedMeasurement::jacobian).
    MeasurementJacobian,
    /// The innovation covariance `C = H P Hᵀ + R`.
    InnovationCovariance,
    /// The updated state.
    UpdatedState,
    /// The updated covariance.
    UpdatedCovariance,
    /// A covariance given to a utility (e.g. a Gaussian to sample from).
    Covariance,
    /// A state computed by the RTS smoother's backward pass.
    SmoothedState,
    /// A covariance computed by the RTS smoother's backward pass.
    SmoothedCovariance,
}

impl Quantity {
    /// Whether the quantity is a vector (its errors give an index, not a row
    /// and column).
    pub fn is_vector(self) -> bool {
        matches!(
            self,
            Quantity::State
                | Quantity::TimeStep
                | Quantity::PropagatedState
                | Quantity::Measurement
                | Quantity::PredictedMeasurement
                | Quantity::UpdatedState
                | Quantity::SmoothedState
        )
    }

    /// Whether the quantity must be positive definite (the innovation
    /// covariance) rather than positive semi-definite (`P`, `Q`, `R`).
    pub fn must_be_definite(self) -> bool {
        matches!(self, Quantity::InnovationCovariance)
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Quantity::State => "state",
            Quantity::StateCovariance => "state covariance P",
            Quantity::TimeStep => "time step dt",
            Quantity::ProcessNoise => "process noise covariance Q",
            Quantity::Transition => "state-transition matrix",
            Quantity::PropagatedState => "propagated state f(x, dt)",
            Quantity::PropagatedCovariance => "propagated covariance",
            Quantity::Measurement => "measurement z",
            Quantity::MeasurementNoise => "measurement noise covariance R",
            Quantity::PredictedMeasurement => "predicted measurement h(x)",
            Quantity::MeasurementJacobian => "measurement Jacobian H",
            Quantity::InnovationCovariance => "innovation covariance",
            Quantity::UpdatedState => "updated state",
            Quantity::UpdatedCovariance => "updated covariance",
            Quantity::Covariance => "covariance",
            Quantity::SmoothedState => "smoothed state",
            Quantity::SmoothedCovariance => "smoothed covariance",
        })
    }
}

/// Why a predict or update (or a constructor) was refused. The filter is
/// unchanged, bit for bit, whenever one of these is returned.
///
/// Indices are into the object the quantity names: `row` and `col` of the
/// matrix the user's model returned (for a vector, `row` is the index and
/// `col` is 0), never into an internal matrix.
///
/// ```
/// use kestrel_core::{FilterError, Quantity};
/// let e = FilterError::NonFinite { what: Quantity::Measurement, row: 2, col: 0 };
/// assert_eq!(e.to_string(), "measurement z has a non-finite value at index 2");
/// let e = FilterError::NotSymmetric { what: Quantity::MeasurementNoise, row: 1, col: 0 };
/// assert_eq!(
///     e.to_string(),
///     "measurement noise covariance R is not symmetric: entries (1, 0) and (0, 1) differ"
/// );
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum FilterError {
    /// An input or computed value is NaN or infinite.
    NonFinite {
        /// Which quantity.
        what: Quantity,
        /// Row (vector index) of the first offending element, column-major.
        row: usize,
        /// Column of the first offending element (0 for a vector).
        col: usize,
    },
    /// A covariance differs from its transpose by more than
    /// [`symmetry_tolerance`](crate::contract::symmetry_tolerance) relative
    /// to its scale.
    NotSymmetric {
        /// Which matrix.
        what: Quantity,
        /// Row of the first offending entry (in the lower triangle).
        row: usize,
        /// Its column.
        col: usize,
    },
    /// A matrix that must be positive semi-definite (`P`, `Q`, `R`) or
    /// positive definite (the innovation covariance) is not: its leading
    /// block up to row and column `index` is indefinite (a negative variance
    /// at `index` is the common case).
    NotPositiveDefinite {
        /// Which matrix.
        what: Quantity,
        /// Row and column where the leading block stops being positive
        /// (semi-)definite.
        index: usize,
    },
    /// `predict` was given a negative time step.
    NegativeTimeStep,
    /// A rank-one downdate of the square-root covariance would have made it
    /// indefinite (the square-root form's measurement update or a negative
    /// sigma-point weight).
    DowndateFailed {
        /// Which downdate vector (column of `U = K S_z`, or 0 for a weight).
        column: usize,
        /// The state index where the downdate failed.
        index: usize,
    },
    /// A configuration parameter is out of its valid range.
    InvalidParameter {
        /// The parameter's name, as in the constructor's signature.
        name: &'static str,
        /// Its valid range, in words (e.g. `"0 < b < 1"`).
        valid: &'static str,
    },
}

impl fmt::Display for FilterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FilterError::NonFinite { what, row, .. } if what.is_vector() => {
                write!(f, "{what} has a non-finite value at index {row}")
            }
            FilterError::NonFinite { what, row, col } => {
                write!(f, "{what} has a non-finite value at row {row}, column {col}")
            }
            FilterError::NotSymmetric { what, row, col } => write!(
                f,
                "{what} is not symmetric: entries ({row}, {col}) and ({col}, {row}) differ"
            ),
            FilterError::NotPositiveDefinite { what, index } => {
                let semi = if what.must_be_definite() { "" } else { "semi-" };
                write!(
                    f,
                    "{what} is not positive {semi}definite (first failing row and column: {index})"
                )
            }
            FilterError::NegativeTimeStep => f.write_str("time step dt is negative"),
            FilterError::DowndateFailed { column, index } => write!(
                f,
                "square-root covariance downdate by column {column} lost positive definiteness at state {index}"
            ),
            FilterError::InvalidParameter { name, valid } => {
                write!(f, "parameter {name} is out of range: it must be {valid}")
            }
        }
    }
}

impl core::error::Error for FilterError {}

/// Returns the index of the first non-finite element of `values`.
pub(crate) fn first_non_finite<T: crate::Real>(values: &[T]) -> Option<usize> {
    if all_finite(values) {
        return None;
    }
    values.iter().position(|v| !v.is_finite())
}

/// Whether every element is finite, without an early exit so the check
/// vectorises (inlined into [`ensure_finite`]): `0 · v` is `±0` for a
/// finite `v` and NaN for `±∞` or NaN, and NaN survives any sum. Eight
/// independent lanes keep the adds parallel.
#[inline(always)]
fn all_finite<T: crate::Real>(values: &[T]) -> bool {
    const LANES: usize = 8;
    if values.len() < 2 * LANES {
        // Short vectors: the lanes would cost more than they save. No early
        // exit either: the compiler tests the values two or four at a time.
        return values.iter().fold(true, |ok, &v| ok & finite(v));
    }
    let mut lanes = [T::zero(); LANES];
    let mut chunks = values.chunks_exact(LANES);
    for chunk in &mut chunks {
        for (lane, &v) in lanes.iter_mut().zip(chunk) {
            *lane += v * T::zero();
        }
    }
    let mut total = T::zero();
    for &v in chunks.remainder() {
        total += v * T::zero();
    }
    for lane in lanes {
        total += lane;
    }
    total == T::zero()
}

/// `Err(NonFinite)` naming `what` and the row and column of the first
/// non-finite element of `m` (a vector is a one-column matrix).
///
/// The passing check is inlined (it runs a dozen times a step, and at small
/// sizes the call costs as much as the check); the error is built out of
/// line.
#[inline(always)]
pub(crate) fn ensure_finite<T: crate::Real, const R: usize, const C: usize>(
    m: &SMatrix<T, R, C>,
    what: Quantity,
) -> Result<(), FilterError> {
    if all_finite(m.as_slice()) {
        Ok(())
    } else {
        non_finite_error(m, what)
    }
}

/// Whether every element of `m` is finite: the inlined test of
/// [`ensure_finite`], for a form that checks only its outputs and, when one
/// is not finite, runs its full sequence of checks out of line to name the
/// first quantity that is not (see [`diagnose`]).
#[inline(always)]
pub(crate) fn is_finite<T: crate::Real, const R: usize, const C: usize>(
    m: &SMatrix<T, R, C>,
) -> bool {
    all_finite(m.as_slice())
}

/// Runs `checks` out of line: the diagnosis of a failed output check, off
/// the path of a passing step.
#[cold]
#[inline(never)]
pub(crate) fn diagnose<R>(checks: impl FnOnce() -> R) -> R {
    checks()
}

/// The error of [`ensure_finite`] for an `m` that has a non-finite element.
#[cold]
#[inline(never)]
fn non_finite_error<T: crate::Real, const R: usize, const C: usize>(
    m: &SMatrix<T, R, C>,
    what: Quantity,
) -> Result<(), FilterError> {
    match first_non_finite(m.as_slice()) {
        Some(i) => Err(FilterError::NonFinite {
            what,
            row: i % R,
            col: i / R,
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::first_non_finite;

    #[test]
    fn finds_the_first_non_finite_element_in_lanes_and_tail() {
        // 19 elements: two rounds of eight lanes and a tail of three.
        let mut v = [1.0e308_f64; 19];
        v[3] = -1.0e-310;
        assert_eq!(first_non_finite(&v), None);
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for at in [0, 9, 17, 18] {
                let mut w = v;
                w[at] = bad;
                w[18] = if at == 18 { bad } else { f64::MAX };
                assert_eq!(first_non_finite(&w), Some(at));
            }
        }
        assert_eq!(first_non_finite::<f32>(&[]), None);
        assert_eq!(first_non_finite(&[0.0_f32, f32::INFINITY]), Some(1));
    }

    /// The short path (fewer than 16 values): every length, every position.
    #[test]
    fn finds_the_first_non_finite_element_of_short_vectors() {
        assert_eq!(first_non_finite(&[f64::MAX, f64::MIN, 5.0e-324]), None);
        for len in 1..16 {
            let mut v = [0.0_f64; 15];
            // Finite in `f32` too, for the narrowed copy below.
            v[0] = 1.0e30;
            v[len - 1] = -5.0e-324;
            assert_eq!(first_non_finite(&v[..len]), None, "length {len}");
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                for at in 0..len {
                    let mut w = v;
                    w[at] = bad;
                    assert_eq!(
                        first_non_finite(&w[..len]),
                        Some(at),
                        "{bad} at {at} of {len}"
                    );
                    let mut narrow = [0.0_f32; 15];
                    for (n, &x) in narrow.iter_mut().zip(&w) {
                        *n = x as f32;
                    }
                    assert_eq!(
                        first_non_finite(&narrow[..len]),
                        Some(at),
                        "f32: {bad} at {at}"
                    );
                }
            }
        }
    }
}
