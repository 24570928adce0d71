//! The input contract every form enforces on what the user supplies: the
//! initial state and covariance, the time step, and the noise covariances
//! the models return.
//!
//! - A state or measurement must be finite.
//! - `P`, `Q` and `R` must be finite, symmetric to within
//!   [`symmetry_tolerance`] of their scale, and positive semi-definite
//!   (`Q` and `R` may be singular: a noise-free state, a perfect
//!   measurement). The innovation covariance must be positive definite.
//! - `dt` must be finite and not negative (zero is allowed: an update
//!   without a time step in between).
//!
//! Every form checks the same things in the same order and reports the same
//! [`FilterError`] naming the same [`Quantity`]; on error the filter is
//! unchanged. The semi-definiteness check is the Cholesky factorisation
//! the forms need anyway (the factor of `R` for the Joseph update, of `Q`
//! for the square-root time update), so it costs little; a `Q` equal to the
//! one already checked at the previous predict is not factored again.
//!
//! ```
//! use kestrel_core::{contract, FilterError, Quantity, nalgebra::Matrix2};
//! let r = Matrix2::new(1.0, 0.5, 0.4, 1.0);
//! assert_eq!(
//!     contract::check_covariance(&r, Quantity::MeasurementNoise).unwrap_err(),
//!     FilterError::NotSymmetric { what: Quantity::MeasurementNoise, row: 1, col: 0 }
//! );
//! let r = Matrix2::new(1.0, 0.0, 0.0, -2.0);
//! assert_eq!(
//!     contract::check_covariance(&r, Quantity::MeasurementNoise).unwrap_err(),
//!     FilterError::NotPositiveDefinite { what: Quantity::MeasurementNoise, index: 1 }
//! );
//! ```

use nalgebra::SMatrix;

use crate::error::ensure_finite;
use crate::linalg::cholesky_semidefinite;
use crate::{FilterError, Quantity, Real};

/// The relative asymmetry a covariance may have: `|aᵢⱼ − aⱼᵢ|` must not
/// exceed `√ε · √(|aᵢᵢ| |aⱼⱼ|)` (`√ε` ≈ 1.5·10⁻⁸ in `f64`, 3.5·10⁻⁴ in
/// `f32`). Products such as `G Q Gᵀ` round far below this; a matrix typed
/// with one off-diagonal entry missing is far above it.
///
/// ```
/// assert!(kestrel_core::contract::symmetry_tolerance::<f64>() < 2e-8);
/// ```
pub fn symmetry_tolerance<T: Real>() -> T {
    crate::real::epsilon::<T>().sqrt()
}

/// Checks that `a` is symmetric to within [`symmetry_tolerance`]: the first
/// offending entry (lowest column, then row, in the lower triangle) is
/// reported. `a` must be finite.
pub fn check_symmetric<T: Real, const N: usize>(
    a: &SMatrix<T, N, N>,
    what: Quantity,
) -> Result<(), FilterError> {
    let tol = symmetry_tolerance::<T>();
    for j in 0..N {
        for i in j + 1..N {
            let (lower, upper) = (a[(i, j)], a[(j, i)]);
            if lower == upper {
                continue;
            }
            let scale = (a[(i, i)].abs() * a[(j, j)].abs()).sqrt();
            if (lower - upper).abs() > tol * scale {
                return Err(FilterError::NotSymmetric {
                    what,
                    row: i,
                    col: j,
                });
            }
        }
    }
    Ok(())
}

/// Checks a covariance supplied by the user (`P`, `Q` or `R`): finite,
/// symmetric, positive semi-definite. Returns its lower Cholesky factor
/// (with zero columns where it is singular), which the forms reuse.
pub fn check_covariance<T: Real, const N: usize>(
    a: &SMatrix<T, N, N>,
    what: Quantity,
) -> Result<SMatrix<T, N, N>, FilterError> {
    ensure_finite(a, what)?;
    check_symmetric(a, what)?;
    cholesky_semidefinite(a).map_err(|e| FilterError::NotPositiveDefinite {
        what,
        index: e.index,
    })
}

/// Checks a diagonal covariance cheaply: finite and non-negative diagonal.
pub(crate) fn check_diagonal<T: Real, const N: usize>(
    a: &SMatrix<T, N, N>,
    what: Quantity,
) -> Result<(), FilterError> {
    for i in 0..N {
        let v = a[(i, i)];
        if !v.is_finite() {
            return Err(FilterError::NonFinite {
                what,
                row: i,
                col: i,
            });
        }
        if v < T::zero() {
            return Err(FilterError::NotPositiveDefinite { what, index: i });
        }
    }
    Ok(())
}

/// Checks a time step: finite and not negative.
///
/// ```
/// use kestrel_core::{contract::check_time_step, FilterError, Quantity};
/// assert_eq!(check_time_step(-0.1), Err(FilterError::NegativeTimeStep));
/// assert_eq!(
///     check_time_step(f64::NAN),
///     Err(FilterError::NonFinite { what: Quantity::TimeStep, row: 0, col: 0 })
/// );
/// assert!(check_time_step(0.0_f32).is_ok());
/// ```
pub fn check_time_step<T: Real>(dt: T) -> Result<(), FilterError> {
    if !dt.is_finite() {
        return Err(FilterError::NonFinite {
            what: Quantity::TimeStep,
            row: 0,
            col: 0,
        });
    }
    if dt < T::zero() {
        return Err(FilterError::NegativeTimeStep);
    }
    Ok(())
}

/// Checks `q` unless it equals, element for element, `checked` (a matrix
/// that passed the check before): a model returning the same `Q` every
/// step is factored once. `Ok(true)` when `q` differs from `checked` (and
/// passed), `Ok(false)` when it is the same matrix.
#[inline(always)]
pub(crate) fn check_noise_cached<T: Real, const N: usize>(
    q: &SMatrix<T, N, N>,
    checked: &SMatrix<T, N, N>,
    what: Quantity,
) -> Result<bool, FilterError> {
    // NaN never compares equal, so it is checked.
    if same_values(q.as_slice(), checked.as_slice()) {
        return Ok(false);
    }
    check_noise(q, what).map(|()| true)
}

/// Whether `a` and `b` hold the same values, element for element, by `==`
/// (NaN equals nothing, `−0` equals `0`), as the slice `==` decides.
/// Without its early exit the comparison vectorises, with no branch per
/// element, where the slice `==` tests each element in turn (and the matrix
/// `==` walks a generic iterator).
#[inline(always)]
pub(crate) fn same_values<T: Real>(a: &[T], b: &[T]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(true, |same, (x, y)| same & (x == y))
}

/// The full check of [`check_noise_cached`], out of line.
#[inline(never)]
fn check_noise<T: Real, const N: usize>(
    q: &SMatrix<T, N, N>,
    what: Quantity,
) -> Result<(), FilterError> {
    ensure_finite(q, what)?;
    check_symmetric(q, what)?;
    // A symmetric matrix with a non-negative, dominant diagonal is positive
    // semi-definite (Gershgorin), which settles diagonal and nearly diagonal
    // noise in O(N²); only the others are factored.
    if diagonally_dominant(q) {
        return Ok(());
    }
    cholesky_semidefinite(q)
        .map(|_| ())
        .map_err(|e| FilterError::NotPositiveDefinite {
            what,
            index: e.index,
        })
}

/// Whether every diagonal element is at least the sum of the magnitudes of
/// the other elements in its column (and so `≥ 0`).
fn diagonally_dominant<T: Real, const N: usize>(a: &SMatrix<T, N, N>) -> bool {
    (0..N).all(|j| {
        let column = a.column(j);
        let off: T = column
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != j)
            .fold(T::zero(), |acc, (_, v)| acc + v.abs());
        a[(j, j)] >= off
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    #[test]
    fn same_values_is_the_slice_comparison() {
        let a = [1.0, -0.0, 3.5, f64::MAX, 5.0e-324];
        assert!(same_values(&a, &a));
        // `−0 = 0`, as `==` says.
        assert!(same_values(&a, &[1.0, 0.0, 3.5, f64::MAX, 5.0e-324]));
        for at in 0..a.len() {
            let mut b = a;
            b[at] = 2.0;
            assert!(!same_values(&a, &b), "differs at {at}");
            b[at] = f64::NAN;
            assert!(!same_values(&b, &b), "NaN at {at} equals nothing");
        }
        assert!(!same_values(&a, &a[..4]));
        assert!(same_values::<f32>(&[], &[]));
    }

    /// The three routes of the cached check: equal to the last one,
    /// diagonally dominant, factored; and the refusals they must not hide.
    #[test]
    fn cached_noise_check_routes() {
        let zero = Matrix3::<f64>::zeros();
        let dominant = Matrix3::new(2.0, -1.0, 0.5, -1.0, 3.0, 1.0, 0.5, 1.0, 1.5);
        assert!(diagonally_dominant(&dominant));
        assert_eq!(
            check_noise_cached(&dominant, &zero, Quantity::ProcessNoise),
            Ok(true)
        );
        // PSD but not dominant: factored.
        let a = Matrix3::new(1.0, 2.0, 0.0, 0.5, 1.0, 3.0, 1.0, 0.0, 1.0);
        let psd = a * a.transpose();
        assert!(!diagonally_dominant(&psd));
        assert!(check_noise_cached(&psd, &zero, Quantity::ProcessNoise).is_ok());
        // Indefinite: [[1, 2], [2, 1]] block, not dominant, refused at 1.
        let bad = Matrix3::new(1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0);
        assert_eq!(
            check_noise_cached(&bad, &zero, Quantity::ProcessNoise),
            Err(FilterError::NotPositiveDefinite {
                what: Quantity::ProcessNoise,
                index: 1
            })
        );
        // Equal to the checked one: accepted without a look; NaN never is.
        assert_eq!(
            check_noise_cached(&psd, &psd, Quantity::ProcessNoise),
            Ok(false)
        );
        let mut nan = psd;
        nan[(2, 2)] = f64::NAN;
        assert!(check_noise_cached(&nan, &nan, Quantity::ProcessNoise).is_err());
    }
}
