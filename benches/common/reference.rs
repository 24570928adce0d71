//! The check every timed filter passes before it is timed: its estimate
//! after a few steps against the hand-written `f64` filter's, so a benchmark
//! cannot silently time a wrong or failing path.

use kestrel::nalgebra::{SMatrix, SVector};
use kestrel::real::to_f64;
use kestrel::Real;

use super::hand::HandKf;
use super::model::Model;

/// Steps run (and checked) before timing.
pub const CHECK_STEPS: usize = 30;

/// Panics unless `(x, p)` matches the hand-written `f64` filter on `m` with
/// measurement noise `r` after [`CHECK_STEPS`] steps, to `1000 ε` relative
/// in the filter's precision (observed: below `5 ε`).
pub fn check<T: Real, const N: usize, const M: usize>(
    what: &str,
    m: &Model<f64, N, M>,
    r: &SMatrix<f64, M, M>,
    x: &SVector<T, N>,
    p: &SMatrix<T, N, N>,
) {
    let mut reference = HandKf::new(m.x0, m.p0);
    for _ in 0..CHECK_STEPS {
        assert!(reference.step(m, r, &m.z), "reference step failed");
    }
    let tol = kestrel::real::epsilon::<T>() * kestrel::real::lit(1000.0);
    let dx = (x.map(to_f64) - reference.x).norm() / reference.x.norm().max(1.0);
    let dp = (p.map(to_f64) - reference.p).norm() / reference.p.norm();
    assert!(
        dx < to_f64(tol) && dp < to_f64(tol),
        "{what}/{N}: state error {dx:e}, covariance error {dp:e}"
    );
}
