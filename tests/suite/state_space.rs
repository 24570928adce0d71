//! Non-vector states: a heading that wraps at ±π, handled through a
//! `StateSpace` in the unscented forms (sigma points, means, corrections)
//! and a wrapped measurement residual.

use std::f64::consts::PI;

use kestrel::nalgebra::{Matrix1, Vector1};
use kestrel::{Filter, MeasurementModel, ProcessModel, SrUkf, StateSpace, Ukf};

fn wrap(a: f64) -> f64 {
    let w = (a + PI).rem_euclid(2.0 * PI) - PI;
    if w == -PI {
        PI
    } else {
        w
    }
}

/// A heading in (−π, π].
#[derive(Clone, Copy)]
struct Heading;

impl StateSpace<f64, 1> for Heading {
    fn add(&self, x: &Vector1<f64>, dx: &Vector1<f64>) -> Vector1<f64> {
        Vector1::new(wrap(x[0] + dx[0]))
    }
    fn difference(&self, a: &Vector1<f64>, b: &Vector1<f64>) -> Vector1<f64> {
        Vector1::new(wrap(a[0] - b[0]))
    }
}

/// The heading turns at `rate` rad/s; the result is wrapped.
struct Turn {
    rate: f64,
}

impl ProcessModel<f64, 1> for Turn {
    fn propagate(&self, x: &Vector1<f64>, dt: f64) -> Vector1<f64> {
        Vector1::new(wrap(x[0] + self.rate * dt))
    }
    fn noise(&self, _x: &Vector1<f64>, dt: f64) -> Matrix1<f64> {
        Matrix1::new(1e-4 * dt)
    }
}

/// A compass reading the heading directly, with a wrapped residual.
struct Compass;

impl MeasurementModel<f64, 1, 1> for Compass {
    fn predict(&self, x: &Vector1<f64>) -> Vector1<f64> {
        *x
    }
    fn noise(&self) -> Matrix1<f64> {
        Matrix1::new(0.01)
    }
    fn residual(&self, z: &Vector1<f64>, z_hat: &Vector1<f64>) -> Vector1<f64> {
        Vector1::new(wrap(z[0] - z_hat[0]))
    }
}

/// Turns through ±π for 40 s, updating with exact compass readings; the
/// estimate must follow the truth across the cut, never jumping to ~0.
fn follows_across_the_cut<F>(mut filter: Filter<f64, 1, F, (), Heading>)
where
    F: kestrel::form::PredictForm<f64, 1, Turn> + kestrel::form::UpdateForm<f64, 1, Compass, 1>,
{
    let turn = Turn { rate: 0.02 };
    let mut truth = 3.0;
    for _ in 0..40 {
        truth = wrap(truth + 0.02);
        filter.predict(&turn, 1.0).unwrap();
        let predicted = filter.state()[0];
        assert!(
            wrap(predicted - truth).abs() < 1e-9,
            "predict: {predicted} vs {truth}"
        );
        filter.update(&Compass, &Vector1::new(truth)).unwrap();
        let x = filter.state()[0];
        assert!(x > -PI && x <= PI);
        assert!(wrap(x - truth).abs() < 1e-9, "update: {x} vs {truth}");
    }
    // The run did cross the cut.
    assert!(truth < 0.0);
}

#[test]
fn ukf_tracks_a_heading_through_the_cut() {
    let f = Ukf::new(Vector1::new(3.0), Matrix1::new(0.05))
        .unwrap()
        .with_state_space(Heading);
    follows_across_the_cut(f);
}

#[test]
fn sr_ukf_tracks_a_heading_through_the_cut() {
    let f = SrUkf::new(Vector1::new(3.0), Matrix1::new(0.05))
        .unwrap()
        .with_state_space(Heading);
    follows_across_the_cut(f);
}

#[test]
fn plain_vector_arithmetic_fails_at_the_cut() {
    // Negative control: the same UKF without the heading state space. Once
    // the sigma points straddle the cut, their plain mean lands far from π.
    let mut f = Ukf::new(Vector1::new(3.0), Matrix1::new(0.05)).unwrap();
    let turn = Turn { rate: 0.02 };
    let mut truth = 3.0;
    let mut worst: f64 = 0.0;
    for _ in 0..40 {
        truth = wrap(truth + 0.02);
        if f.predict(&turn, 1.0).is_err() || f.update(&Compass, &Vector1::new(truth)).is_err() {
            worst = f64::INFINITY;
            break;
        }
        worst = worst.max(wrap(f.state()[0] - truth).abs());
    }
    assert!(worst > 0.1, "{worst}");
}
