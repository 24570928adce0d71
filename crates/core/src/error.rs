//! Typed failures of predict and update.

use core::fmt;

/// The quantity an error is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// The measurement vector `z` given to `update`.
    Measurement,
    /// The measurement noise covariance `R` (from the model or an adapter).
    MeasurementNoise,
    /// The predicted measurement `h(x)` or its Jacobian.
    PredictedMeasurement,
    /// The process noise covariance `Q`.
    ProcessNoise,
    /// The propagated state `f(x)` or the transition matrix `Φ`.
    Propagation,
    /// The state covariance `P` (or its factor `S`).
    StateCovariance,
    /// The innovation covariance `C = HPHᵀ + R`.
    InnovationCovariance,
    /// The updated state or covariance.
    UpdatedEstimate,
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Quantity::Measurement => "measurement",
            Quantity::MeasurementNoise => "measurement noise covariance",
            Quantity::PredictedMeasurement => "predicted measurement",
            Quantity::ProcessNoise => "process noise covariance",
            Quantity::Propagation => "propagated state",
            Quantity::StateCovariance => "state covariance",
            Quantity::InnovationCovariance => "innovation covariance",
            Quantity::UpdatedEstimate => "updated estimate",
        })
    }
}

/// Why a predict or update was refused. The filter state is unchanged
/// whenever one of these is returned.
///
/// ```
/// use kestrel_core::{FilterError, Quantity};
/// let e = FilterError::NonFinite { what: Quantity::Measurement, index: 2 };
/// assert_eq!(e.to_string(), "measurement has a non-finite value at index 2");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum FilterError {
    /// An input or intermediate value is NaN or infinite.
    NonFinite {
        /// Which quantity.
        what: Quantity,
        /// Index of the first offending element (column-major for matrices).
        index: usize,
    },
    /// A matrix that must be positive (semi-)definite is not: its Cholesky
    /// factorisation met a non-positive pivot.
    NotPositiveDefinite {
        /// Which matrix.
        what: Quantity,
        /// The pivot (row and column) where factorisation failed.
        index: usize,
    },
    /// A rank-one downdate of the square-root covariance would have made it
    /// indefinite (the square-root form's measurement update or a negative
    /// sigma-point weight).
    DowndateFailed {
        /// Which downdate vector (column of `U = K S_z`, or 0 for a weight).
        column: usize,
        /// The pivot where the downdate failed.
        index: usize,
    },
    /// A configuration parameter is out of its valid range.
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
    },
}

impl fmt::Display for FilterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FilterError::NonFinite { what, index } => {
                write!(f, "{what} has a non-finite value at index {index}")
            }
            FilterError::NotPositiveDefinite { what, index } => {
                write!(f, "{what} is not positive definite (pivot {index})")
            }
            FilterError::DowndateFailed { column, index } => write!(
                f,
                "square-root covariance downdate by column {column} lost positive definiteness at pivot {index}"
            ),
            FilterError::InvalidParameter { name } => write!(f, "parameter {name} is out of range"),
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
/// vectorises: `0 · v` is `±0` for a finite `v` and NaN for `±∞` or NaN, and
/// NaN survives any sum. Eight independent lanes keep the adds parallel.
fn all_finite<T: crate::Real>(values: &[T]) -> bool {
    const LANES: usize = 8;
    if values.len() < 2 * LANES {
        // Short vectors: the lanes would cost more than they save.
        return values.iter().all(|v| v.is_finite());
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

/// `Err(NonFinite)` naming `what` if any element of `values` is not finite.
pub(crate) fn ensure_finite<T: crate::Real>(
    values: &[T],
    what: Quantity,
) -> Result<(), FilterError> {
    match first_non_finite(values) {
        Some(index) => Err(FilterError::NonFinite { what, index }),
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
}
