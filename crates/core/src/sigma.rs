//! Merwe scaled sigma points and the unscented transforms the unscented
//! forms share.
//!
//! For an `N`-state with covariance `P = S Sᵀ` the `2N + 1` points are
//! `χ₀ = x`, `χ±ᵢ = x ⊞ ±η Sᵢ` (`Sᵢ` the i-th column of `S`), stored as a
//! centre plus `N` (plus, minus) pairs so no `2N + 1` size is ever written.

use nalgebra::{ArrayStorage, SMatrix, SVector};

use crate::error::{diagnose, ensure_finite, is_finite};
use crate::linalg::{add_products, add_weighted_outer_lower, mirror_lower};
use crate::real::lit;
use crate::{FilterError, MeasurementModel, ProcessModel, Quantity, Real, StateSpace};

/// The Merwe scaled sigma-point parameters `α` (spread), `β` (prior
/// knowledge of the distribution, 2 for Gaussian) and `κ` (secondary
/// scaling).
///
/// The default is `α = 1, β = 2, κ = 0`: spread `η = √N`, centre mean
/// weight 0 and centre covariance weight 2, so no weight is negative and the
/// square-root form never needs a downdate in its time update. The common
/// textbook choice `α = 10⁻³` makes the centre covariance weight about
/// `−10⁶`, which is exact in theory but costs accuracy in `f32`.
///
/// ```
/// use kestrel_core::sigma::MerweParams;
/// let w = MerweParams::<f64>::default().weights(4).unwrap();
/// assert_eq!(w.spread, 2.0);
/// assert_eq!(w.mean0, 0.0);
/// assert_eq!(w.cov0, 2.0);
/// assert_eq!(w.other, 0.125);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MerweParams<T: Real> {
    /// Spread of the points around the mean, `0 < α ≤ 1`.
    pub alpha: T,
    /// Distribution parameter, `β = 2` is optimal for Gaussians.
    pub beta: T,
    /// Secondary scaling; `N + κ > 0` is required.
    pub kappa: T,
}

impl<T: Real> Default for MerweParams<T> {
    fn default() -> Self {
        Self {
            alpha: T::one(),
            beta: lit(2.0),
            kappa: T::zero(),
        }
    }
}

impl<T: Real> MerweParams<T> {
    /// The error for parameters [`weights`](Self::weights) refuses.
    pub const INVALID: FilterError = FilterError::InvalidParameter {
        name: "MerweParams",
        valid: "finite with α > 0 and α²(N + κ) > 0",
    };

    /// The parameters `(α, β, κ)`.
    pub fn new(alpha: T, beta: T, kappa: T) -> Self {
        Self { alpha, beta, kappa }
    }

    /// The weights for an `n`-dimensional state, or `None` if the
    /// parameters are not finite, `α ≤ 0`, or `α²(n + κ) ≤ 0`.
    pub fn weights(&self, n: usize) -> Option<SigmaWeights<T>> {
        let n_t: T = lit(n as f64);
        let a2 = self.alpha * self.alpha;
        let scale = a2 * (n_t + self.kappa); // n + λ
        let valid = self.alpha > T::zero()
            && scale > T::zero()
            && scale.is_finite()
            && self.beta.is_finite();
        if !valid {
            return None;
        }
        let lambda = scale - n_t;
        let mean0 = lambda / scale;
        Some(SigmaWeights {
            spread: scale.sqrt(),
            mean0,
            cov0: mean0 + T::one() - a2 + self.beta,
            other: T::one() / (scale + scale),
        })
    }
}

/// The weights of a sigma-point set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SigmaWeights<T: Real> {
    /// `η = √(N + λ)`: the points sit at `x ± η Sᵢ`.
    pub spread: T,
    /// Mean weight of the centre point, `λ / (N + λ)`.
    pub mean0: T,
    /// Covariance weight of the centre point, `λ / (N + λ) + 1 − α² + β`.
    pub cov0: T,
    /// Mean and covariance weight of each other point, `1 / (2(N + λ))`.
    pub other: T,
}

/// `N` pairs of `(plus, minus)` vectors of dimension `D`.
pub(crate) type Pairs<T, const D: usize, const N: usize> = [[SVector<T, D>; 2]; N];

/// A sigma set of zeros, to be overwritten. Built from an array of zeros
/// the compiler sees, so it is one `memset`: an array of
/// `SVector::zeros()` (made through an iterator) is filled by a `memcpy`
/// call per pair, fifteen calls for the 15-state set. The smallest sets
/// (at most four elements a vector times pairs) keep that form: the
/// compiler writes their zeros with a few stores, which cost less than a
/// call to `memset`.
#[inline(always)]
fn zero_pairs<T: Real, const D: usize, const N: usize>() -> Pairs<T, D, N> {
    if const { D * N <= 4 } {
        return [[SVector::zeros(); 2]; N];
    }
    let zero = SVector::from_array_storage(ArrayStorage([[T::zero(); D]]));
    [[zero; 2]; N]
}

/// Sigma points `x ⊞ ±η Sᵢ`.
#[inline]
pub(crate) fn points<T: Real, const N: usize, S: StateSpace<T, N>>(
    x: &SVector<T, N>,
    s: &SMatrix<T, N, N>,
    spread: T,
    space: &S,
) -> Pairs<T, N, N> {
    let mut chi = zero_pairs();
    for (i, pair) in chi.iter_mut().enumerate() {
        // Element by element: a view times a scalar, or a view made owned,
        // goes through nalgebra's generic allocation and a `memcpy` call.
        let d = SVector::<T, N>::from_fn(|r, _| s[(r, i)] * spread);
        pair[0] = space.add(x, &d);
        pair[1] = space.add(x, &-d);
    }
    chi
}

/// `Wc₀ d₀ d₀ᵀ + W Σᵢ (d₊ᵢ d₊ᵢᵀ + d₋ᵢ d₋ᵢᵀ)`, one triangle, mirrored. The
/// `2N` deviations are read in place as the columns of one product for the
/// register-tiled kernel, `Σ dⱼ dⱼᵀ`, scaled by `W` after, rather than `2N`
/// rank-one passes, each of which loads and stores the whole triangle.
fn weighted_covariance<T: Real, const D: usize, const N: usize>(
    center: &SVector<T, D>,
    pairs: &Pairs<T, D, N>,
    w: &SigmaWeights<T>,
) -> SMatrix<T, D, D> {
    let mut p = SMatrix::zeros();
    weighted_covariance_into(&mut p, center, pairs, w);
    p
}

/// [`weighted_covariance`] written into `p`.
fn weighted_covariance_into<T: Real, const D: usize, const N: usize>(
    p: &mut SMatrix<T, D, D>,
    center: &SVector<T, D>,
    pairs: &Pairs<T, D, N>,
    w: &SigmaWeights<T>,
) {
    // The pairs are `2N` contiguous columns with one weight: their Gram
    // product read in place, then scaled (a weighted copy of the pairs
    // to multiply against is a few KB to write and read back).
    add_products(p, None, [pairs], [pairs], true);
    for v in p.as_mut_slice() {
        *v *= w.other;
    }
    add_weighted_outer_lower(p, w.cov0, center);
    mirror_lower(p);
}

/// The unscented transform of the state through a process model.
pub(crate) struct PropagatedSigma<T: Real, const N: usize> {
    pub mean: SVector<T, N>,
    /// Deviation of the propagated centre from the mean.
    pub center: SVector<T, N>,
    /// Deviations of the propagated pairs from the mean.
    pub pairs: Pairs<T, N, N>,
}

impl<T: Real, const N: usize> PropagatedSigma<T, N> {
    /// `Σ Wc dⱼ dⱼᵀ`, written into `p`.
    pub fn covariance_into(&self, p: &mut SMatrix<T, N, N>, w: &SigmaWeights<T>) {
        weighted_covariance_into(p, &self.center, &self.pairs, w);
    }
}

pub(crate) fn propagate<T, const N: usize, P, S>(
    x: &SVector<T, N>,
    s: &SMatrix<T, N, N>,
    w: &SigmaWeights<T>,
    model: &P,
    dt: T,
    space: &S,
) -> Result<PropagatedSigma<T, N>, FilterError>
where
    T: Real,
    P: ProcessModel<T, N>,
    S: StateSpace<T, N>,
{
    let y0 = model.propagate(x, dt);
    ensure_finite(&y0, Quantity::PropagatedState)?;
    // Propagated in place: the points are not needed after.
    let mut ys = points(x, s, w.spread, space);
    for pair in ys.iter_mut() {
        for v in pair.iter_mut() {
            *v = model.propagate(v, dt);
        }
    }
    let mut acc = SVector::<T, N>::zeros();
    for pair in &ys {
        acc += space.difference(&pair[0], &y0) + space.difference(&pair[1], &y0);
    }
    check_sum(&acc, &ys, Quantity::PropagatedState)?;
    let mean = space.add(&y0, &(acc * w.other));
    let center = space.difference(&y0, &mean);
    for pair in ys.iter_mut() {
        for v in pair.iter_mut() {
            *v = space.difference(v, &mean);
        }
    }
    Ok(PropagatedSigma {
        mean,
        center,
        pairs: ys,
    })
}

/// One finiteness check of the sum of a sigma set's deviations instead of
/// one per point: a non-finite point makes the sum non-finite (so does a
/// sum that overflows, whose mean is not finite either). Only then are the
/// points checked, to name the first that is not finite as `what`. This
/// relies on a state space's `difference` and a model's `residual` carrying
/// a non-finite input through to their result, as subtraction and the
/// angle wraps of the project's models do.
#[inline(always)]
fn check_sum<T: Real, const D: usize, const N: usize>(
    sum: &SVector<T, D>,
    points: &Pairs<T, D, N>,
    what: Quantity,
) -> Result<(), FilterError> {
    if is_finite(sum) {
        return Ok(());
    }
    diagnose(|| {
        for v in points.as_flattened() {
            ensure_finite(v, what)?;
        }
        ensure_finite(sum, what)
    })
}

/// The unscented transform of the state through a measurement model.
pub(crate) struct MeasuredSigma<T: Real, const N: usize, const M: usize> {
    pub z_hat: SVector<T, M>,
    pub center: SVector<T, M>,
    pub pairs: Pairs<T, M, N>,
    /// `P_xz = Σ Wc (χⱼ ⊟ x)(Zⱼ ⊟ ẑ)ᵀ`, with `χ±ᵢ ⊟ x = ±η Sᵢ`.
    pub cross: SMatrix<T, N, M>,
}

impl<T: Real, const N: usize, const M: usize> MeasuredSigma<T, N, M> {
    /// `P_zz = Σ Wc dzⱼ dzⱼᵀ` (without `R`).
    pub fn covariance(&self, w: &SigmaWeights<T>) -> SMatrix<T, M, M> {
        weighted_covariance(&self.center, &self.pairs, w)
    }
}

pub(crate) fn measure<T, const N: usize, const M: usize, H, S>(
    x: &SVector<T, N>,
    s: &SMatrix<T, N, N>,
    w: &SigmaWeights<T>,
    model: &H,
    space: &S,
) -> Result<MeasuredSigma<T, N, M>, FilterError>
where
    T: Real,
    H: MeasurementModel<T, N, M>,
    S: StateSpace<T, N>,
{
    let chi = points(x, s, w.spread, space);
    let z0 = model.predict(x);
    ensure_finite(&z0, Quantity::PredictedMeasurement)?;
    let mut zs: Pairs<T, M, N> = zero_pairs();
    let mut acc = SVector::<T, M>::zeros();
    for (zp, cp) in zs.iter_mut().zip(&chi) {
        for (zv, cv) in zp.iter_mut().zip(cp) {
            *zv = model.predict(cv);
            acc += model.residual(zv, &z0);
        }
    }
    check_sum(&acc, &zs, Quantity::PredictedMeasurement)?;
    let z_hat = z0 + acc * w.other;
    let center = model.residual(&z0, &z_hat);
    // The state deviations of a pair are `±η Sᵢ` by construction (`⊟`
    // undoes `⊞`), so `P_xz = W Σᵢ η Sᵢ (dz₊ᵢ − dz₋ᵢ)ᵀ = S (W η Δ)ᵀ`: one
    // product of `S` with the pairs' residual differences instead of `2N`
    // outer products, and no deviation `(x ⊞ d) ⊟ x` rounded back from
    // the points. The centre's state deviation is zero: it adds nothing.
    let scale = w.other * w.spread;
    let mut delta = SMatrix::<T, M, N>::zeros();
    for (zp, column) in zs.iter_mut().zip(delta.data.0.iter_mut()) {
        for zv in zp.iter_mut() {
            *zv = model.residual(zv, &z_hat);
        }
        for ((d, &plus), &minus) in column.iter_mut().zip(zp[0].iter()).zip(zp[1].iter()) {
            *d = (plus - minus) * scale;
        }
    }
    let mut cross = SMatrix::<T, N, M>::zeros();
    add_products(&mut cross, None, [s], [&delta], false);
    Ok(MeasuredSigma {
        z_hat,
        center,
        pairs: zs,
        cross,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn zero_pairs_are_zero_in_both_forms() {
        // At most four elements: the `SVector::zeros()` form; above: the
        // array of zeros.
        let small: Pairs<f64, 2, 2> = zero_pairs();
        let large: Pairs<f32, 6, 15> = zero_pairs();
        assert!(small
            .as_flattened()
            .iter()
            .all(|v| v.iter().all(|&x| x == 0.0)));
        assert!(large
            .as_flattened()
            .iter()
            .all(|v| v.iter().all(|&x| x == 0.0)));
        assert_eq!(large.as_flattened().len(), 30);
    }

    #[test]
    fn weighted_covariance_equals_the_sum_of_weighted_outer_products() {
        // 5-dimensional deviations of 7 pairs: tiles and edges of the
        // product kernel.
        let pairs: Pairs<f64, 5, 7> = core::array::from_fn(|i| {
            [0, 1].map(|s| SVector::from_fn(|r, _| ((r * 7 + i * 3 + s * 11) as f64 * 0.37).sin()))
        });
        let center = SVector::<f64, 5>::from_fn(|r, _| r as f64 * 0.1 - 0.2);
        let w = MerweParams::new(0.5, 2.0, 1.0).weights(7).unwrap();
        let mut naive = center * center.transpose() * w.cov0;
        for d in pairs.as_flattened() {
            naive += d * d.transpose() * w.other;
        }
        let p = weighted_covariance(&center, &pairs, &w);
        assert_relative_eq!(p, naive, epsilon = 1e-14);
        assert_eq!(p, p.transpose());
    }

    /// A heading (state 0, wrapped to (−π, π]) and two plain states.
    struct Wrapped;
    impl StateSpace<f64, 3> for Wrapped {
        fn add(&self, x: &SVector<f64, 3>, dx: &SVector<f64, 3>) -> SVector<f64, 3> {
            let mut y = x + dx;
            y[0] = wrap(y[0]);
            y
        }
        fn difference(&self, a: &SVector<f64, 3>, b: &SVector<f64, 3>) -> SVector<f64, 3> {
            let mut d = a - b;
            d[0] = wrap(d[0]);
            d
        }
    }
    fn wrap(a: f64) -> f64 {
        use core::f64::consts::PI;
        (a + PI).rem_euclid(2.0 * PI) - PI
    }

    /// A nonlinear measurement of the three states.
    struct Nonlinear;
    impl MeasurementModel<f64, 3, 2> for Nonlinear {
        fn predict(&self, x: &SVector<f64, 3>) -> SVector<f64, 2> {
            SVector::<f64, 2>::new(x[0].sin() * x[1] + x[2] * x[2], x[1].exp() - x[0] * x[2])
        }
        fn noise(&self) -> SMatrix<f64, 2, 2> {
            SMatrix::identity()
        }
    }

    #[test]
    fn the_cross_covariance_equals_the_sum_over_the_points() {
        // Near the wrap (heading 3.1 rad, spread across ±π) and with a
        // factor that is not triangular: `P_xz` from `S` and the residual
        // differences equals `Σ W (χ ⊟ x)(Z ⊟ ẑ)ᵀ` over the points.
        let x = SVector::<f64, 3>::new(3.1, 0.4, -0.7);
        let s = SMatrix::<f64, 3, 3>::new(0.05, 0.01, -0.02, 0.03, 0.2, 0.0, -0.01, 0.04, 0.3);
        let w = MerweParams::new(0.5, 2.0, 1.0).weights(3).unwrap();
        let measured = measure(&x, &s, &w, &Nonlinear, &Wrapped).unwrap();
        let chi = points(&x, &s, w.spread, &Wrapped);
        let mut naive = SMatrix::<f64, 3, 2>::zeros();
        for (cp, zp) in chi.iter().zip(&measured.pairs) {
            for (cv, dz) in cp.iter().zip(zp) {
                naive += Wrapped.difference(cv, &x) * dz.transpose() * w.other;
            }
        }
        // The points do cross the wrap: the test is not of a plain vector.
        assert!(chi.as_flattened().iter().any(|c| c[0] < 0.0));
        assert_relative_eq!(measured.cross, naive, epsilon = 1e-15, max_relative = 1e-12);
        assert!(measured.cross.iter().all(|v| v.abs() > 1e-6));
    }
}
