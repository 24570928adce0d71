//! Huber inflation under a gross error, alone and behind the χ² gate, in
//! the square-root UKF (the case of the library-contract report: a 10³⁰ m
//! range).

use kestrel_adaptive::{gated_huber, HuberInflation};
use kestrel_core::nalgebra::{Matrix2, Vector2};
use kestrel_core::{MeasurementModel, SrUkf};

/// Range and bearing from the origin, state `[x, y]`.
struct Radar;
impl MeasurementModel<f64, 2, 2> for Radar {
    fn predict(&self, x: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(x.norm(), x[1].atan2(x[0]))
    }
    fn noise(&self) -> Matrix2<f64> {
        Matrix2::new(1.0, 0.0, 0.0, 1e-6)
    }
}

#[test]
fn a_gross_error_moves_huber_alone_but_not_the_gated_combination() {
    let x0 = Vector2::new(300.0, 400.0);
    let p0 = Matrix2::identity() * 4.0;
    let z = Vector2::new(1e30, 0.927);

    let mut alone = SrUkf::new(x0, p0)
        .unwrap()
        .with_adapter(HuberInflation::<f64, 2>::as_published().unwrap());
    alone.update(&Radar, &z).unwrap();
    let moved = (alone.state() - x0).norm();
    // The documented failure: the floored weight lets the error through.
    assert!(moved > 1e12, "Huber alone moved the state by {moved:e} m");

    let mut gated = SrUkf::new(x0, p0)
        .unwrap()
        .with_adapter(gated_huber::<f64, 2>(0.05, 1e-6).unwrap());
    let report = gated.update(&Radar, &z).unwrap();
    assert!(report.rejected && report.adapters.0.rejected);
    assert_eq!(*gated.state(), x0);

    // A moderate outlier (6σ in range) passes the gate and is down-weighted.
    let z = Vector2::new(506.0, 0.927_295);
    let report = gated.update(&Radar, &z).unwrap();
    assert!(!report.rejected);
    assert!(report.adapters.1.fault && report.adapters.1.factors[0] < 1.0);
}
