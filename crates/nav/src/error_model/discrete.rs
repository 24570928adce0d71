//! A linear error-state model discretised from its continuous form.

use kestrel_core::real::to_f64;
use kestrel_core::{real::lit, LinearizedProcess, ProcessModel, Real};
use nalgebra::{SMatrix, SVector};

/// Second-order transition matrix `Φ = I + F Δt + (F Δt)² / 2` and
/// trapezoidal process noise `Q_d = (Φ Q Φᵀ + Q) Δt / 2` of the continuous
/// system `ẋ = F x + w`, `E[w wᵀ] = diag(q) δ(t − s)`.
///
/// The second-order term keeps the Schuler and Earth-rate couplings exact to
/// `O((|F| Δt)³)`, which for navigation errors (`|F| ≲ 10⁻²` 1/s outside the
/// attitude–velocity block) leaves relative errors below 10⁻⁶ at
/// `Δt = 1 s`; the trapezoidal `Q_d` is the matching two-point quadrature
/// of `∫ Φ(s) Q Φ(s)ᵀ ds`.
///
/// ```
/// use kestrel_nav::error_model::discretise;
/// use kestrel_nav::nalgebra::{Matrix2, Vector2};
/// // Position driven by velocity, white acceleration of density 2.
/// let f = Matrix2::new(0.0, 1.0, 0.0, 0.0);
/// let (phi, qd) = discretise(&f, &Vector2::new(0.0, 2.0), 0.5);
/// assert_eq!(phi, Matrix2::new(1.0, 0.5, 0.0, 1.0));
/// // ((Φ diag(q) Φᵀ) + diag(q)) Δt / 2
/// assert_eq!(qd, Matrix2::new(0.125, 0.25, 0.25, 1.0));
/// ```
pub fn discretise<const N: usize>(
    f: &SMatrix<f64, N, N>,
    q: &SVector<f64, N>,
    dt: f64,
) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>) {
    let fdt = f * dt;
    // (F Δt)² column by column, skipping the many structural zeros of an
    // INS error model (about a third of the entries are non-zero).
    let mut phi = fdt;
    for j in 0..N {
        for k in 0..N {
            let a = 0.5 * fdt[(k, j)];
            if a != 0.0 {
                for i in 0..N {
                    phi[(i, j)] += a * fdt[(i, k)];
                }
            }
        }
    }
    for i in 0..N {
        phi[(i, i)] += 1.0;
    }
    // Φ diag(q) Φᵀ = Σ_k q_k φ_k φ_kᵀ over the driven states only, lower
    // triangle, then mirrored (exact symmetry for the filter's factorisations).
    let mut qd = SMatrix::<f64, N, N>::zeros();
    for k in 0..N {
        let w = q[k];
        if w != 0.0 {
            for j in 0..N {
                let b = w * phi[(j, k)];
                if b != 0.0 {
                    for i in j..N {
                        qd[(i, j)] += b * phi[(i, k)];
                    }
                }
            }
        }
    }
    let half = 0.5 * dt;
    for j in 0..N {
        qd[(j, j)] = (qd[(j, j)] + q[j]) * half;
        for i in j + 1..N {
            let v = qd[(i, j)] * half;
            qd[(i, j)] = v;
            qd[(j, i)] = v;
        }
    }
    (phi, qd)
}

/// A linear error-state process model `x⁺ = Φ x`, `Q_d`, built for one
/// propagation interval from the continuous `F` and the diagonal white
/// noise densities `q` (see [`discretise`]).
///
/// It implements [`ProcessModel`] and [`LinearizedProcess`] for any filter
/// scalar `T` (the matrices are kept in `f64` and converted). `Φ` and `Q_d`
/// are computed once for the interval given at construction; a filter call
/// with a different `dt` recomputes them from `F`.
///
/// ```
/// use kestrel_core::{Ekf, nalgebra::{Matrix2, Vector2}};
/// use kestrel_nav::error_model::ErrorStateModel;
/// let model = ErrorStateModel::from_continuous(
///     Matrix2::new(0.0, 1.0, 0.0, 0.0), Vector2::new(0.0, 1e-2), 0.1);
/// let mut kf = Ekf::<f32, 2>::new(Vector2::zeros(), Matrix2::identity()).unwrap();
/// kf.predict(&model, 0.1).unwrap();
/// assert!((kf.covariance()[(0, 1)] - 0.1).abs() < 1e-4);
/// ```
#[derive(Clone, Debug)]
pub struct ErrorStateModel<const N: usize> {
    f: SMatrix<f64, N, N>,
    q: SVector<f64, N>,
    dt: f64,
    phi: SMatrix<f64, N, N>,
    qd: SMatrix<f64, N, N>,
}

impl<const N: usize> ErrorStateModel<N> {
    /// The model of `ẋ = F x + w`, `E[w wᵀ] = diag(q) δ`, over `dt` seconds.
    ///
    /// ```
    /// use kestrel_nav::error_model::ErrorStateModel;
    /// use kestrel_nav::nalgebra::{Matrix1, Vector1};
    /// let m = ErrorStateModel::from_continuous(Matrix1::new(-0.5), Vector1::new(1.0), 0.2);
    /// assert!((m.phi()[0] - (1.0 - 0.1 + 0.005)).abs() < 1e-15);
    /// ```
    pub fn from_continuous(f: SMatrix<f64, N, N>, q: SVector<f64, N>, dt: f64) -> Self {
        let (phi, qd) = discretise(&f, &q, dt);
        Self { f, q, dt, phi, qd }
    }

    /// The continuous dynamics matrix `F`.
    ///
    /// ```
    /// use kestrel_nav::error_model::ErrorStateModel;
    /// use kestrel_nav::nalgebra::{Matrix1, Vector1};
    /// let m = ErrorStateModel::from_continuous(Matrix1::new(-0.5), Vector1::new(1.0), 0.2);
    /// assert_eq!(m.f()[0], -0.5);
    /// ```
    pub fn f(&self) -> &SMatrix<f64, N, N> {
        &self.f
    }

    /// The continuous white-noise densities (diagonal of `Q`).
    ///
    /// ```
    /// use kestrel_nav::error_model::ErrorStateModel;
    /// use kestrel_nav::nalgebra::{Matrix1, Vector1};
    /// let m = ErrorStateModel::from_continuous(Matrix1::new(-0.5), Vector1::new(3.0), 0.2);
    /// assert_eq!(m.q_continuous()[0], 3.0);
    /// ```
    pub fn q_continuous(&self) -> &SVector<f64, N> {
        &self.q
    }

    /// The interval `Φ` and `Q_d` were built for, s.
    ///
    /// ```
    /// use kestrel_nav::error_model::ErrorStateModel;
    /// use kestrel_nav::nalgebra::{Matrix1, Vector1};
    /// let m = ErrorStateModel::from_continuous(Matrix1::new(0.0), Vector1::new(1.0), 0.2);
    /// assert_eq!(m.dt(), 0.2);
    /// ```
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The transition matrix over [`dt`](Self::dt).
    ///
    /// ```
    /// use kestrel_nav::error_model::ErrorStateModel;
    /// use kestrel_nav::nalgebra::{Matrix1, Vector1};
    /// let m = ErrorStateModel::from_continuous(Matrix1::new(0.0), Vector1::new(1.0), 0.2);
    /// assert_eq!(m.phi()[0], 1.0);
    /// ```
    pub fn phi(&self) -> &SMatrix<f64, N, N> {
        &self.phi
    }

    /// The discrete process noise over [`dt`](Self::dt).
    ///
    /// ```
    /// use kestrel_nav::error_model::ErrorStateModel;
    /// use kestrel_nav::nalgebra::{Matrix1, Vector1};
    /// let m = ErrorStateModel::from_continuous(Matrix1::new(0.0), Vector1::new(1.0), 0.2);
    /// assert!((m.qd()[0] - 0.2).abs() < 1e-15);
    /// ```
    pub fn qd(&self) -> &SMatrix<f64, N, N> {
        &self.qd
    }

    /// `Φ` and `Q_d` for `dt`: the stored ones when `dt` is the construction
    /// interval (to the precision of `f32`), else recomputed.
    fn discrete(&self, dt: f64) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>) {
        if (dt - self.dt).abs() <= 1e-6 * self.dt.abs() {
            (self.phi, self.qd)
        } else {
            discretise(&self.f, &self.q, dt)
        }
    }
}

impl<T: Real, const N: usize> ProcessModel<T, N> for ErrorStateModel<N> {
    fn propagate(&self, x: &SVector<T, N>, dt: T) -> SVector<T, N> {
        self.discrete(to_f64(dt)).0.map(lit::<T>) * x
    }

    fn noise(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        self.discrete(to_f64(dt)).1.map(lit::<T>)
    }
}

impl<T: Real, const N: usize> LinearizedProcess<T, N> for ErrorStateModel<N> {
    fn transition(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        self.discrete(to_f64(dt)).0.map(lit::<T>)
    }
}
