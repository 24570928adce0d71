//! The filter's consistency on recorded data with a truth: the position
//! NEES at every compared epoch against its χ² band.

use kestrel::nalgebra::{Matrix3, Vector3};

/// The two-sided 95 % band of a χ² variable with `dof` degrees of freedom:
/// its 2.5 % and 97.5 % quantiles, from
/// [`chi_square_quantile`](kestrel::adaptive::chi_square_quantile) (`NaN`
/// for `dof == 0`).
///
/// ```
/// let (low, high) = kestrel_app::process::chi_square_band(3);
/// assert!((low - 0.215_795).abs() < 1e-6 && (high - 9.348_404).abs() < 1e-6);
/// ```
pub fn chi_square_band(dof: usize) -> (f64, f64) {
    let q = |p| kestrel::adaptive::chi_square_quantile(p, dof).unwrap_or(f64::NAN);
    (q(0.025), q(0.975))
}

/// The position NEES `δrᵀ P⁻¹ δr` (3 degrees of freedom) over the compared
/// epochs: how often it lies inside its 95 % band ([`chi_square_band`]`(3)`),
/// and its mean.
///
/// For a consistent filter the NEES is χ²(3)-distributed: mean 3 and about
/// 95 % of the epochs inside the band (the epochs of one run are correlated
/// in time, so the fraction varies between runs more than independent
/// draws would).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Consistency {
    /// Epochs with a NEES (a position covariance that could be factored).
    pub epochs: usize,
    /// Of them, inside the 95 % band.
    pub inside: usize,
    /// Above its upper end (the filter claims too much).
    pub above: usize,
    /// The sum of the NEES values.
    sum: f64,
}

impl Consistency {
    /// Adds the epoch with position error `dr` and covariance `p` (NED, m);
    /// returns its NEES, or `None` when `p` is not positive definite.
    pub(crate) fn add(&mut self, dr: &Vector3<f64>, p: &Matrix3<f64>) -> Option<f64> {
        let nees = dr.dot(&p.cholesky()?.solve(dr));
        if !nees.is_finite() {
            return None;
        }
        let (low, high) = chi_square_band(3);
        self.epochs += 1;
        self.inside += usize::from((low..=high).contains(&nees));
        self.above += usize::from(nees > high);
        self.sum += nees;
        Some(nees)
    }

    /// The mean NEES (`None` over no epoch).
    ///
    /// ```
    /// let c = kestrel_app::process::Consistency::default();
    /// assert_eq!(c.mean(), None);
    /// ```
    pub fn mean(&self) -> Option<f64> {
        (self.epochs > 0).then(|| self.sum / self.epochs as f64)
    }

    /// The share of the epochs inside the band (`None` over no epoch).
    pub fn inside_share(&self) -> Option<f64> {
        (self.epochs > 0).then(|| self.inside as f64 / self.epochs as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nees_by_hand() {
        let mut c = Consistency::default();
        // P = diag(4, 1, 9): (2, 1, 3) gives 1 + 1 + 1 = 3.
        let p = Matrix3::from_diagonal(&Vector3::new(4.0, 1.0, 9.0));
        assert!((c.add(&Vector3::new(2.0, 1.0, 3.0), &p).unwrap() - 3.0).abs() < 1e-12);
        // 10 σ on one axis: 100, above the band.
        assert!((c.add(&Vector3::new(20.0, 0.0, 0.0), &p).unwrap() - 100.0).abs() < 1e-9);
        // Zero error: below the band.
        c.add(&Vector3::zeros(), &p);
        assert_eq!((c.epochs, c.inside, c.above), (3, 1, 1));
        assert!((c.mean().unwrap() - 103.0 / 3.0).abs() < 1e-9);
        // A singular covariance is not counted.
        assert_eq!(c.add(&Vector3::new(1.0, 0.0, 0.0), &Matrix3::zeros()), None);
        assert_eq!(c.epochs, 3);
    }
}
