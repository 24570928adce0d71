//! Quantiles of the χ² distribution, for innovation tests whose threshold is
//! `χ²_p(m)` with `m` the measurement dimension.

use kestrel_core::real::{lit, to_f64};
use kestrel_core::{FilterError, Real};
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The `probability` quantile of the χ² distribution with `dof` degrees of
/// freedom: the `c` with `P(χ²_dof ≤ c) = probability`.
///
/// An innovation test at significance `α` uses
/// `chi_square_quantile(1.0 - α, m)`. Adapters call this once, in their
/// constructor, never per update.
///
/// # Errors
/// [`FilterError::InvalidParameter`] with name `"probability"` unless
/// `0 < probability < 1`, or `"dof"` if `dof == 0`.
///
/// ```
/// use kestrel_adaptive::chi_square_quantile;
/// // One degree of freedom: the square of the normal 97.5 % quantile.
/// let c = chi_square_quantile(0.95, 1).unwrap();
/// assert!((c - 1.959_964_f64.powi(2)).abs() < 1e-5);
/// // Two degrees of freedom: −2 ln(1 − p).
/// let c = chi_square_quantile(0.95, 2).unwrap();
/// assert!((c + 2.0 * (0.05_f64).ln()).abs() < 1e-9);
/// assert!(chi_square_quantile(1.0, 2).is_err());
/// assert!(chi_square_quantile(0.5, 0).is_err());
/// ```
pub fn chi_square_quantile(probability: f64, dof: usize) -> Result<f64, FilterError> {
    // `probability > 0 && < 1` also refuses NaN.
    if !(probability > 0.0 && probability < 1.0) {
        return Err(FilterError::InvalidParameter {
            name: "probability",
            valid: "0 < probability < 1",
        });
    }
    if dof == 0 {
        return Err(FilterError::InvalidParameter {
            name: "dof",
            valid: "at least 1 (the measurement dimension M)",
        });
    }
    let dist = ChiSquared::new(dof as f64).map_err(|_| FilterError::InvalidParameter {
        name: "dof",
        valid: "at least 1 (the measurement dimension M)",
    })?;
    let c = dist.inverse_cdf(probability);
    if c.is_finite() && c > 0.0 {
        Ok(c)
    } else {
        Err(FilterError::InvalidParameter {
            name: "probability",
            valid: "0 < probability < 1",
        })
    }
}

/// The threshold `χ²_{1−significance}(dof)` of an innovation test at
/// `significance` (the probability that a consistent innovation fails it),
/// in the filter's scalar.
///
/// # Errors
/// [`FilterError::InvalidParameter`] `"significance"` unless
/// `0 < significance < 1`, `"dof"` if `dof == 0`.
///
/// ```
/// use kestrel_adaptive::significance_threshold;
/// let c: f32 = significance_threshold(0.05_f32, 2).unwrap();
/// assert!((c - 5.991).abs() < 1e-3);
/// let e = significance_threshold(1.5_f64, 2).unwrap_err();
/// assert_eq!(e.to_string(), "parameter significance is out of range: it must be 0 < significance < 1");
/// ```
pub fn significance_threshold<T: Real>(significance: T, dof: usize) -> Result<T, FilterError> {
    let s = to_f64(significance);
    if !(s > 0.0 && s < 1.0) {
        return Err(FilterError::InvalidParameter {
            name: "significance",
            valid: "0 < significance < 1",
        });
    }
    Ok(lit(chi_square_quantile(1.0 - s, dof)?))
}
