//! Helpers of the hand-computed epochs: a tolerance check, linear models
//! with a fixed `Φ`, `Q`, `H`, `R`, one predict / update epoch, and a
//! macro running the same body through every form.

use kestrel_core::adapter::NoiseAdapter;
use kestrel_core::form::{PredictForm, UpdateForm};
use kestrel_core::nalgebra::{Matrix2, SVector};
use kestrel_core::{Filter, FilterError, UpdateDetail, UpdateReport};
use kestrel_models::{LinearMeasurement, LinearProcess};

/// Agreement required of every form with the hand values (the square-root
/// and unscented forms round differently from the scalar arithmetic).
pub const TOL: f64 = 1e-12;

/// Asserts `got` = `want` to [`TOL`], relative above 1, absolute below.
#[track_caller]
pub fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= TOL * want.abs().max(1.0),
        "{what}: got {got}, want {want}"
    );
}

/// A process and a measurement model of an `N`-state, `M`-measurement
/// linear system.
pub type Models<const N: usize, const M: usize> =
    (LinearProcess<f64, N>, LinearMeasurement<f64, N, M>);

/// `x⁻ = x + w`, `Q = ½ I`; `z = x + v` with noise `r`, in two dimensions.
pub fn planar_walk(r: Matrix2<f64>) -> Models<2, 2> {
    (
        LinearProcess::new(Matrix2::identity(), Matrix2::identity() * 0.5),
        LinearMeasurement::new(Matrix2::identity(), r),
    )
}

/// Predicts over `dt = 1` and updates once with `z`.
pub fn epoch<F, A, const N: usize, const M: usize>(
    f: &mut Filter<f64, N, F, A>,
    models: &Models<N, M>,
    z: SVector<f64, M>,
) -> Result<UpdateReport<f64, M, A::Report>, FilterError>
where
    F: PredictForm<f64, N, LinearProcess<f64, N>>
        + UpdateForm<f64, N, LinearMeasurement<f64, N, M>, M>,
    A: NoiseAdapter<f64, M>,
{
    epoch_detailed(f, models, z).map(|d| d.report)
}

/// As [`epoch`], returning the update's detail (its matrices too).
pub fn epoch_detailed<F, A, const N: usize, const M: usize>(
    f: &mut Filter<f64, N, F, A>,
    (process, sensor): &Models<N, M>,
    z: SVector<f64, M>,
) -> Result<UpdateDetail<f64, M, A::Report>, FilterError>
where
    F: PredictForm<f64, N, LinearProcess<f64, N>>
        + UpdateForm<f64, N, LinearMeasurement<f64, N, M>, M>,
    A: NoiseAdapter<f64, M>,
{
    f.predict(process, 1.0)?;
    f.update_detailed(sensor, &z)
}

/// Runs `$body` with `$f` bound to a fresh filter (x₀ = `$x0`, P₀ = `$p0`)
/// of each form — EKF, UKF, SR-UKF — carrying adapter `$adapter`, and
/// `$name` naming the form.
#[macro_export]
macro_rules! each_hand_form {
    ($x0:expr, $p0:expr, $adapter:expr, |$name:ident, $f:ident| $body:block) => {{
        let (x0, p0) = ($x0, $p0);
        {
            let $name = "EKF";
            let mut $f = $crate::support::ekf(x0, p0).with_adapter($adapter);
            $body
        }
        {
            let $name = "UKF";
            let mut $f = $crate::support::ukf(x0, p0).with_adapter($adapter);
            $body
        }
        {
            let $name = "SR-UKF";
            let mut $f = $crate::support::sr_ukf(x0, p0).with_adapter($adapter);
            $body
        }
    }};
}
