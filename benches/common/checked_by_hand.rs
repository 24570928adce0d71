//! The step at 2 states written out by hand, element by element, with every
//! check the library's KF step makes: what a checked Joseph step costs at
//! least, to tell the checks' cost from the generic step's.
//!
//! Like the library's step it refuses a negative or non-finite `dt`, checks
//! `Q` and `R` unless they equal the ones checked last (and keeps `R`'s
//! Cholesky factor), checks `z`, `ẑ`, `ν`, `x⁻`, `Φ P Φᵀ`, `x⁺` and `P⁺`
//! for finiteness (`Φ` and `H` through their outputs, as the library does),
//! factors `C = H P Hᵀ + R` as `L D Lᵀ` with the library's pivot test,
//! updates `P` in the Joseph form with `R` through its factor, commits
//! nothing unless every check passed, and returns a report with the same
//! content (`ν` twice, NIS twice, the fade, two flags). It has none of the
//! library's generality: no models behind traits, no adapters, no fading,
//! no sequential path, no state space, and it knows `N = M = 2`.

use kestrel::nalgebra::{Matrix2, Vector2};

/// `x − x`: exactly 0 for every finite `x`, NaN for `±∞` and NaN (the
/// library's test).
#[inline(always)]
// `x − x` is the test, not a slip.
#[allow(clippy::eq_op)]
fn finite(x: f64) -> bool {
    x - x == 0.0
}

/// Whether `a` and `b` hold the same values, compared without an early
/// exit, as the library compares a noise matrix with the one checked last.
#[inline(always)]
fn same(a: &Matrix2<f64>, b: &Matrix2<f64>) -> bool {
    a.iter()
        .zip(b.iter())
        .fold(true, |same, (x, y)| same & (x == y))
}

/// The library's test of a factorisation's pivot `d` of a matrix whose
/// diagonal element was `original`: finite, positive, and above `2 ε` times
/// `|original|`.
#[inline(always)]
fn regular_pivot(d: f64, original: f64) -> bool {
    finite(d) & (d > 2.0 * f64::EPSILON * original.abs()) & (d > 0.0)
}

/// What the update reports: as the library's report without adapters.
#[derive(Clone, Copy, Debug)]
pub struct Report {
    /// `ν = z − ẑ`.
    pub innovation: Vector2<f64>,
    /// The innovation the gain took (no adapter: `ν`).
    pub innovation_used: Vector2<f64>,
    /// `νᵀ C⁻¹ ν`.
    pub nis: f64,
    /// The NIS after adapters (none: the NIS).
    pub adapted_nis: f64,
    /// The fade applied (none: 1).
    pub fade: f64,
    /// Whether an adapter rejected the measurement (never here).
    pub rejected: bool,
    /// Whether the update ran as sequential scalar updates (never here).
    pub sequential: bool,
}

/// The checked filter at 2 states: `x`, the lower triangle of `P`, and the
/// noise covariances checked last with `R`'s lower Cholesky factor.
pub struct CheckedByHand {
    /// State.
    pub x: Vector2<f64>,
    /// `P₀₀`, `P₁₀`, `P₁₁`.
    p: [f64; 3],
    q: Matrix2<f64>,
    r: Matrix2<f64>,
    r_factor: [f64; 3],
}

/// `Some` if `a` is a finite, symmetric (exactly: the library allows
/// rounding), positive semi-definite 2 × 2 matrix, with its lower Cholesky
/// factor `[L₀₀, L₁₀, L₁₁]` (zeros where a pivot is zero).
fn factor(a: &Matrix2<f64>) -> Option<[f64; 3]> {
    let d0 = a[(0, 0)];
    if !(a.iter().all(|v| v.is_finite()) && a[(1, 0)] == a[(0, 1)] && d0 >= 0.0) {
        return None;
    }
    let l0 = d0.sqrt();
    let l1 = if d0 > 0.0 { a[(1, 0)] / l0 } else { 0.0 };
    let d1 = a[(1, 1)] - l1 * l1;
    (d1 >= 0.0 && (d0 > 0.0 || a[(1, 0)] == 0.0)).then(|| [l0, l1, d1.sqrt()])
}

impl CheckedByHand {
    /// The filter at `x0`, `p0`; `None` if `p0` is not a covariance.
    pub fn new(x0: Vector2<f64>, p0: &Matrix2<f64>) -> Option<Self> {
        factor(p0)?;
        Some(Self {
            x: x0,
            p: [p0[(0, 0)], p0[(1, 0)], p0[(1, 1)]],
            // NaN equals nothing: the first `Q` and `R` are checked.
            q: Matrix2::from_element(f64::NAN),
            r: Matrix2::from_element(f64::NAN),
            r_factor: [0.0; 3],
        })
    }

    /// The covariance.
    pub fn p(&self) -> Matrix2<f64> {
        let [p00, p10, p11] = self.p;
        Matrix2::new(p00, p10, p10, p11)
    }

    /// `x ← Φ x`, `P ← Φ P Φᵀ + Q`, after `dt`, with the library's checks.
    #[inline(never)]
    pub fn predict(
        &mut self,
        phi: &Matrix2<f64>,
        q: &Matrix2<f64>,
        dt: f64,
    ) -> Result<(), &'static str> {
        if !(finite(dt) & (dt >= 0.0)) {
            return Err("time step");
        }
        if !same(q, &self.q) {
            factor(q).ok_or("process noise")?;
            self.q = *q;
        }
        let [p00, p10, p11] = self.p;
        let x = phi * self.x;
        // T = Φ P, then the lower triangle of T Φᵀ + Q.
        let t00 = phi[(0, 0)] * p00 + phi[(0, 1)] * p10;
        let t01 = phi[(0, 0)] * p10 + phi[(0, 1)] * p11;
        let t10 = phi[(1, 0)] * p00 + phi[(1, 1)] * p10;
        let t11 = phi[(1, 0)] * p10 + phi[(1, 1)] * p11;
        let n00 = t00 * phi[(0, 0)] + t01 * phi[(0, 1)] + q[(0, 0)];
        let n10 = t10 * phi[(0, 0)] + t11 * phi[(0, 1)] + q[(1, 0)];
        let n11 = t10 * phi[(1, 0)] + t11 * phi[(1, 1)] + q[(1, 1)];
        if !(finite(x[0]) & finite(x[1]) & finite(n00) & finite(n10) & finite(n11)) {
            return Err("propagated state or covariance");
        }
        self.x = x;
        self.p = [n00, n10, n11];
        Ok(())
    }

    /// The Joseph update with `z`, `H` and `R`, with the library's checks;
    /// nothing is committed unless every check passed.
    #[inline(never)]
    pub fn update(
        &mut self,
        h: &Matrix2<f64>,
        r: &Matrix2<f64>,
        z: &Vector2<f64>,
    ) -> Result<Report, &'static str> {
        if !(finite(z[0]) & finite(z[1])) {
            return Err("measurement");
        }
        if !same(r, &self.r) {
            self.r_factor = factor(r).ok_or("measurement noise")?;
            self.r = *r;
        }
        let z_hat = h * self.x;
        let nu = z - z_hat;
        if !(finite(z_hat[0]) & finite(z_hat[1]) & finite(nu[0]) & finite(nu[1])) {
            return Err("predicted measurement or innovation");
        }
        let [p00, p10, p11] = self.p;
        // B = P Hᵀ, C = H B + R (lower triangle).
        let b00 = p00 * h[(0, 0)] + p10 * h[(0, 1)];
        let b01 = p00 * h[(1, 0)] + p10 * h[(1, 1)];
        let b10 = p10 * h[(0, 0)] + p11 * h[(0, 1)];
        let b11 = p10 * h[(1, 0)] + p11 * h[(1, 1)];
        let c00 = h[(0, 0)] * b00 + h[(0, 1)] * b10 + r[(0, 0)];
        let c10 = h[(1, 0)] * b00 + h[(1, 1)] * b10 + r[(1, 0)];
        let c11 = h[(1, 0)] * b01 + h[(1, 1)] * b11 + r[(1, 1)];
        // C = L D Lᵀ.
        let d0 = c00;
        let l10 = c10 / d0;
        let d1 = c11 - l10 * c10;
        if !(regular_pivot(d0, c00) & regular_pivot(d1, c11)) {
            return Err("innovation covariance");
        }
        let w1 = nu[1] - l10 * nu[0];
        let nis = nu[0] * nu[0] / d0 + w1 * w1 / d1;
        // Row i of K solves C kᵢᵀ = bᵢᵀ.
        let solve = |c0: f64, c1: f64| {
            let u1 = (c1 - l10 * c0) / d1;
            (c0 / d0 - l10 * u1, u1)
        };
        let (k00, k01) = solve(b00, b01);
        let (k10, k11) = solve(b10, b11);
        // A = I − K H; P⁺ = A P Aᵀ + (K L_R)(K L_R)ᵀ, lower triangle.
        let a00 = 1.0 - (k00 * h[(0, 0)] + k01 * h[(1, 0)]);
        let a01 = -(k00 * h[(0, 1)] + k01 * h[(1, 1)]);
        let a10 = -(k10 * h[(0, 0)] + k11 * h[(1, 0)]);
        let a11 = 1.0 - (k10 * h[(0, 1)] + k11 * h[(1, 1)]);
        let t00 = a00 * p00 + a01 * p10;
        let t01 = a00 * p10 + a01 * p11;
        let t10 = a10 * p00 + a11 * p10;
        let t11 = a10 * p10 + a11 * p11;
        let [l0, l1, l2] = self.r_factor;
        let g00 = k00 * l0 + k01 * l1;
        let g01 = k01 * l2;
        let g10 = k10 * l0 + k11 * l1;
        let g11 = k11 * l2;
        let n00 = t00 * a00 + t01 * a01 + (g00 * g00 + g01 * g01);
        let n10 = t10 * a00 + t11 * a01 + (g10 * g00 + g11 * g01);
        let n11 = t10 * a10 + t11 * a11 + (g10 * g10 + g11 * g11);
        let x0 = self.x[0] + (k00 * nu[0] + k01 * nu[1]);
        let x1 = self.x[1] + (k10 * nu[0] + k11 * nu[1]);
        if !(finite(x0) & finite(x1) & finite(n00) & finite(n10) & finite(n11)) {
            return Err("updated state or covariance");
        }
        self.x = Vector2::new(x0, x1);
        self.p = [n00, n10, n11];
        Ok(Report {
            innovation: nu,
            innovation_used: nu,
            nis,
            adapted_nis: nis,
            fade: 1.0,
            rejected: false,
            sequential: false,
        })
    }
}
