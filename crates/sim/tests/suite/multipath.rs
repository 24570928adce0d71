//! GNSS multipath bursts: their shape (trapezoid bias, constant Doppler
//! bias), their window, and that they draw from their own stream.

use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState};
use kestrel_sim::{GnssConfig, GnssSensor, MultipathBursts, Outlier, OutlierKind, TimeWindow};

fn truth(t: f64) -> NavState {
    NavState::new(
        t,
        Geodetic::from_degrees(30.5, 114.4, 20.0),
        Vector3::zeros(),
        Euler::default(),
    )
}

/// A noise-free receiver with one multipath process in `window`.
fn receiver(bursts: MultipathBursts, window: TimeWindow, seed: u64) -> GnssSensor {
    let mut c = GnssConfig::new(1.0, Vector3::zeros(), Some(Vector3::zeros()));
    c.outliers.push(Outlier {
        window,
        kind: OutlierKind::Multipath(bursts),
    });
    GnssSensor::new(c, Ellipsoid::wgs84(), seed)
}

/// Position (NED, m) and velocity errors of the fix at whole second `t`.
fn errors(g: &mut GnssSensor, t: u32) -> (Vector3<f64>, Vector3<f64>, bool) {
    let s = truth(t as f64);
    let fix = g.sample(&s, &Vector3::zeros()).unwrap();
    let dp = Ellipsoid::wgs84().ned_offset(&s.pos, &fix.value.pos);
    (dp, fix.value.vel.unwrap(), fix.faulty)
}

const SURE: MultipathBursts = MultipathBursts {
    onset_probability: 1.0,
    duration: (10.0, 10.0),
    rise: 4.0,
    position: Vector3::new(10.0, 20.0, 30.0),
    position_jitter: Vector3::new(0.0, 0.0, 0.0),
    velocity_bias: Vector3::new(1.0, 2.0, 3.0),
    velocity: Vector3::new(0.0, 0.0, 0.0),
};

#[test]
fn a_burst_is_a_trapezoid_with_a_constant_doppler_bias() {
    let mut g = receiver(SURE, TimeWindow::new(0.0, 100.0), 3);
    // Onset certain: bursts at 1–10 s, 11–20 s, … (each ends where the
    // next starts). Envelope over 1..=10 s: up over 4 s, down over 4 s.
    let envelope = [0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 0.75, 0.5, 0.25];
    let mut first = Vec::new();
    for t in 1..=10 {
        first.push(errors(&mut g, t));
    }
    let (bias, vbias, _) = first[4];
    for k in 0..3 {
        assert!(bias[k].abs() <= SURE.position[k] && bias[k] != 0.0);
        assert!(vbias[k].abs() <= SURE.velocity_bias[k] && vbias[k] != 0.0);
    }
    for (i, (p, v, faulty)) in first.iter().enumerate() {
        assert!(faulty);
        // Millimetres: the geodetic displacement and back.
        assert!((p - bias * envelope[i]).norm() < 1e-3, "{i}: {p:?}");
        assert_eq!(*v, vbias, "{i}");
    }
    // The next burst draws a new bias.
    let (_, v2, _) = errors(&mut g, 15);
    assert_ne!(v2, vbias);
}

#[test]
fn a_burst_stops_at_the_end_of_its_window() {
    let mut long = SURE;
    long.duration = (100.0, 100.0);
    let mut g = receiver(long, TimeWindow::new(0.0, 20.5), 4);
    for t in 1..=20 {
        assert!(errors(&mut g, t).2, "{t}");
    }
    for t in 21..=30 {
        let (p, v, faulty) = errors(&mut g, t);
        assert!(!faulty && p.norm() < 1e-6 && v == Vector3::zeros(), "{t}");
    }
}

#[test]
fn adding_bursts_leaves_the_noise_and_the_other_outliers_unchanged() {
    let mut base = GnssConfig::new(1.0, Vector3::repeat(3.0), Some(Vector3::repeat(0.1)));
    base.outliers.push(Outlier {
        window: TimeWindow::new(0.0, 1000.0),
        kind: OutlierKind::Spikes {
            probability: 0.1,
            position: (10.0, 20.0),
            velocity: (1.0, 2.0),
        },
    });
    let mut with = base.clone();
    let mut bursts = SURE;
    bursts.onset_probability = 0.05;
    with.outliers.push(Outlier {
        window: TimeWindow::new(0.0, 1000.0),
        kind: OutlierKind::Multipath(bursts),
    });
    let earth = Ellipsoid::wgs84();
    let (mut a, mut b) = (
        GnssSensor::new(base, earth, 7),
        GnssSensor::new(with, earth, 7),
    );
    let (mut clean, mut hit) = (0, 0);
    for t in 1..1000 {
        let s = truth(t as f64);
        let fa = a.sample(&s, &Vector3::zeros()).unwrap();
        let fb = b.sample(&s, &Vector3::zeros()).unwrap();
        if fa.faulty {
            assert!(fb.faulty, "{t}");
        }
        if !fb.faulty {
            // No burst and no spike: the very same fix.
            assert_eq!(fa, fb, "{t}");
            clean += 1;
        } else if !fa.faulty {
            hit += 1;
        }
    }
    // Bursts of 10 s starting with 5 % per fix cover about a third of the
    // fixes: both kinds of epoch are exercised.
    assert!(clean > 300 && hit > 200, "{clean} {hit}");
}
