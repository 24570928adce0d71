//! The linear test case of the adapter tests: 2-D constant velocity,
//! Φ = [1 1; 0 1], Q = [¼ ½; ½ 1], position measured with R = r, from
//! x₀ = (1, 2), P₀ = [4 1; 1 2]. The first predict gives x⁻ = (3, 2),
//! Φ P₀ Φᵀ = [8 3; 3 2] and P⁻ = [8.25 3.5; 3.5 3] (see hand_computed.rs).

use core::fmt::Debug;

use kestrel::form::{PredictForm, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Matrix1, Matrix1x2, Matrix2, Vector2};
use kestrel::Filter;

use super::assert_close;

pub const TOL: f64 = 1e-12;
pub const X0: Vector2<f64> = Vector2::new(1.0, 2.0);
/// Position measurements of a four-step run.
pub const ZS: [f64; 4] = [6.0, 8.5, 9.0, 13.0];

pub fn p0() -> Matrix2<f64> {
    Matrix2::new(4.0, 1.0, 1.0, 2.0)
}
pub fn phi() -> Matrix2<f64> {
    Matrix2::new(1.0, 1.0, 0.0, 1.0)
}
pub fn q() -> Matrix2<f64> {
    Matrix2::new(0.25, 0.5, 0.5, 1.0)
}
pub fn process() -> LinearProcess<f64, 2> {
    LinearProcess::new(phi(), q())
}
/// Position, with `R = r`.
pub fn position(r: f64) -> LinearMeasurement<f64, 2, 1> {
    LinearMeasurement::new(Matrix1x2::new(1.0, 0.0), Matrix1::new(r))
}
/// Position and position + velocity, correlated noise.
pub fn two_sensors() -> LinearMeasurement<f64, 2, 2> {
    LinearMeasurement::new(
        Matrix2::new(1.0, 0.0, 1.0, 1.0),
        Matrix2::new(1.0, 0.2, 0.2, 2.0),
    )
}

/// A form that runs the linear models of this module.
pub trait LinForm:
    PredictForm<f64, 2, LinearProcess<f64, 2>>
    + UpdateForm<f64, 2, LinearMeasurement<f64, 2, 1>, 1>
    + UpdateForm<f64, 2, LinearMeasurement<f64, 2, 2>, 2>
    + Clone
    + Debug
{
}
impl<F> LinForm for F where
    F: PredictForm<f64, 2, LinearProcess<f64, 2>>
        + UpdateForm<f64, 2, LinearMeasurement<f64, 2, 1>, 1>
        + UpdateForm<f64, 2, LinearMeasurement<f64, 2, 2>, 2>
        + Clone
        + Debug
{
}

/// The same form as `f` without adapter, at `(x, p)` with nothing pending.
pub fn plain<F: LinForm, A: Clone>(
    f: &Filter<f64, 2, F, A>,
    x: Vector2<f64>,
    p: Matrix2<f64>,
) -> Filter<f64, 2, F> {
    let mut g = f.clone().with_adapter(());
    g.set_state(x).unwrap();
    g.set_covariance(&p).unwrap();
    g
}

/// Panics unless both filters hold the same estimate to `TOL`.
#[track_caller]
pub fn assert_same_estimate<F: LinForm, A, B>(
    name: &str,
    got: &Filter<f64, 2, F, A>,
    want: &Filter<f64, 2, F, B>,
) {
    assert_close(got.state(), want.state(), TOL, name);
    assert_close(&got.covariance(), &want.covariance(), TOL, name);
}

/// Runs `$check(name, filter, args…)` with a fresh adapter-free filter of
/// each form at `(X0, P0)`: covariance (taking every diagonal `R` one
/// component at a time), unscented, and square-root with both time-update
/// methods.
#[allow(unused_macros)]
macro_rules! each_form {
    ($check:ident $(, $arg:expr)*) => {{
        use kestrel::form::{SquareRootForm, TimeUpdate};
        use kestrel::{Ekf, SrUkf, Ukf};
        use $crate::support::cv::{p0, X0};
        let rank_one = SquareRootForm::new(&p0())
            .unwrap()
            .with_time_update(TimeUpdate::RankOne);
        let mut ekf = Ekf::new(X0, p0()).unwrap();
        ekf.form_mut().set_sequential(true);
        $check("ekf", ekf $(, $arg)*);
        $check("ukf", Ukf::new(X0, p0()).unwrap() $(, $arg)*);
        $check("sr-ukf", SrUkf::new(X0, p0()).unwrap() $(, $arg)*);
        $check("sr-ukf rank-one", SrUkf::with_form(X0, rank_one).unwrap() $(, $arg)*);
    }};
}
