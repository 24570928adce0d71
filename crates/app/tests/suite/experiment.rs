//! The experiment runner on the five built-in scenarios, shortened to the
//! first minutes so the suite stays fast (full-length figures come from
//! the ignored `full_length_figures`, run in release).
//!
//! Asserted: every filter kind of every scenario runs, with exactly the
//! aiding epochs its sensors deliver; the federated filters of 001 equal
//! the centralised EKF (Carlson's equivalence for linear models); runs are deterministic and all
//! filter kinds of a scenario consume identical data; a failing filter is
//! an error naming it and the time; the records show what the adapters
//! did; on 000 the standard KF beats the raw GNSS and both adaptive
//! filters stay stable and beat the standard KF on every position and
//! velocity axis over the first 300 s (the scenario's γ and λ_max are
//! chosen for that stability, see `scenario_000`).

use kestrel::nav::nalgebra::Vector3;
use kestrel_app::experiment::{run, run_with, PositionAxes, RunError, RunOptions, RunSummary};
use kestrel_app::scenario::{builtin, by_name, FilterKind, MeasurementNoise, Scenario};

fn short(seconds: f64) -> RunOptions {
    RunOptions::default().with_duration(seconds)
}

fn print(name: &str, m: &RunSummary) {
    eprintln!(
        "{name} {:>18}: epochs {:5} rejected {:4}; position RMS {:9.2} {:9.2} {:9.2} m ({:?}); \
         velocity RMS {:8.3} {:8.3} {:8.3} m/s; attitude RMS {:.1e} {:.1e} {:.1e} rad",
        m.filter,
        m.epochs,
        m.rejected,
        m.rms_position.x,
        m.rms_position.y,
        m.rms_position.z,
        m.axes,
        m.rms_velocity.x,
        m.rms_velocity.y,
        m.rms_velocity.z,
        m.rms_attitude.x,
        m.rms_attitude.y,
        m.rms_attitude.z,
    );
}

/// Aiding epochs in the first 100 s: 1 Hz GNSS (with the attitude
/// reference for 004) from 1 s to 100 s, the 10 Hz GNSS of 000 and the
/// 10 Hz odometer of 003 from 0.1 s to 100 s.
fn expected_epochs(name: &str) -> usize {
    match name {
        "000" | "003" => 1000,
        _ => 100,
    }
}

#[test]
fn every_filter_of_every_scenario_runs() {
    for s in builtin() {
        let mut digests = Vec::new();
        for kind in &s.filters {
            let r = run(&s, kind, s.seed, &short(100.0).without_records())
                .unwrap_or_else(|e| panic!("{}: {e}", s.name));
            let m = r.summary;
            print(&s.name, &m);
            assert!(r.records.is_empty());
            assert_eq!(m.filter, kind.label());
            assert_eq!(
                m.epochs,
                expected_epochs(&s.name),
                "{} {}",
                s.name,
                m.filter
            );
            assert_eq!(m.rms_epochs, m.epochs);
            assert!((m.end_time - 100.0).abs() < 1e-9);
            assert!(m.rms_position.iter().all(|v| v.is_finite()));
            digests.push(m.data_digest);
        }
        // Every filter kind consumed exactly the same sensor data.
        assert!(digests.windows(2).all(|w| w[0] == w[1]), "{}", s.name);
    }
}

#[test]
fn runs_are_deterministic_and_share_their_data() {
    let s = by_name("002").unwrap();
    let opts = short(60.0);
    let a = run(&s, &s.filters[1], 11, &opts).unwrap();
    let b = run(&s, &s.filters[1], 11, &opts).unwrap();
    assert_eq!(a, b, "same seed, same kind: identical records");
    let ekf = run(&s, &s.filters[0], 11, &opts).unwrap();
    assert_eq!(ekf.summary.data_digest, a.summary.data_digest);
    let other = run(&s, &s.filters[1], 12, &opts).unwrap();
    assert_ne!(other.summary.data_digest, a.summary.data_digest);
    // At the first epoch the robust filter's χ² test passes (NIS 4.2 <
    // χ²₀.₉₅(6) = 12.6), so its update is the EKF's: equal up to the rounding
    // of the batch against the EKF's sequential scalar update.
    let (e, r) = (&ekf.records[0], &a.records[0]);
    assert!(r.adaptation.inflated == 0 && r.adaptation.nis < 12.6);
    assert!((e.position - r.position).norm() < 1e-9);
    assert!((e.velocity - r.velocity).norm() < 1e-12);
    assert!((e.attitude - r.attitude).norm() < 1e-12);
}

/// With information shares summing to one, a reset at every fusion and a
/// linear (error-state) model, the federated estimate is the centralised
/// Kalman filter's: the federated UKF and SR-UKF of 001 (position local EKF,
/// velocity local UKF / SR-UKF) must reproduce the standard EKF fed with
/// both. Only rounding separates them; the UKF's α = 10⁻³ gives
/// W₀ ≈ 1 − 1/α² ≈ −10⁶, which amplifies the rounding of P by about 10⁶
/// (≈ 10⁻¹⁰ relative): nanometres on metre-sized corrections.
#[test]
fn federated_filters_equal_the_centralised_ekf() {
    let s = by_name("001").unwrap();
    let opts = short(100.0);
    let central = run(&s, &FilterKind::Standard, 1, &opts).unwrap();
    for kind in &s.filters {
        let fed = run(&s, kind, 1, &opts).unwrap();
        assert_eq!(fed.records.len(), central.records.len());
        for (c, f) in central.records.iter().zip(&fed.records) {
            assert_eq!(c.time, f.time);
            let label = fed.summary.filter;
            assert!(
                (c.position - f.position).norm() < 1e-7,
                "{label} at {}",
                c.time
            );
            assert!(
                (c.velocity - f.velocity).norm() < 1e-10,
                "{label} at {}",
                c.time
            );
            assert!(
                (c.attitude - f.attitude).norm() < 1e-12,
                "{label} at {}",
                c.time
            );
        }
    }
}

#[test]
fn streaming_gives_the_stored_records() {
    let s = by_name("004").unwrap();
    let opts = short(30.0);
    let stored = run(&s, &s.filters[1], 4, &opts).unwrap();
    let mut streamed = Vec::new();
    let summary = run_with(&s, &s.filters[1], 4, &opts, |r| streamed.push(*r)).unwrap();
    assert_eq!(summary, stored.summary);
    assert_eq!(streamed, stored.records);
}

#[test]
fn a_failing_filter_is_an_error_with_its_name_and_time() {
    for name in ["000", "001"] {
        let mut s: Scenario = by_name(name).unwrap();
        // A NaN measurement variance: the first GNSS update (at 1/rate s:
        // 0.1 s for 000, 1 s for 001) must fail.
        let first = 1.0 / s.gnss.as_ref().unwrap().rate;
        s.filter.r = MeasurementNoise::gnss(Vector3::repeat(f64::NAN), Vector3::repeat(0.3));
        for kind in &s.filters {
            match run(&s, kind, 0, &short(5.0)) {
                Err(RunError::Filter { filter, time, .. }) => {
                    assert_eq!(filter, kind.label());
                    assert!((time - first).abs() < 1e-9, "{filter} failed at {time} s");
                }
                other => panic!("{}: {other:?}", kind.label()),
            }
        }
    }
}

#[test]
fn kinds_that_do_not_fit_are_refused() {
    let s = by_name("000").unwrap();
    let r = run(
        &s,
        &FilterKind::MaxThreshold {
            threshold: 1.0,
            r_window: None,
        },
        0,
        &short(1.0),
    );
    assert!(matches!(r, Err(RunError::Incompatible { .. })));
    let s3 = by_name("003").unwrap();
    let r = run(
        &s3,
        &FilterKind::IctErekf { significance: 0.05 },
        0,
        &short(1.0),
    );
    assert!(matches!(r, Err(RunError::Incompatible { .. })));
    let r = run(
        &s3,
        &FilterKind::FuzzyAdaptive { window: 7 },
        0,
        &short(1.0),
    );
    assert!(matches!(r, Err(RunError::Unsupported { .. })));
    let r = run(
        &s,
        &FilterKind::IctErekf { significance: 0.5 },
        0,
        &short(1.0),
    );
    assert!(matches!(r, Err(RunError::InvalidParameter { .. })));
}

#[test]
fn records_show_what_the_adapters_did() {
    // 002 up to the end of the first multipath episode (300–340 s).
    let s = by_name("002").unwrap();
    let ekf = run(&s, &s.filters[0], s.seed, &short(340.0)).unwrap();
    let robust = run(&s, &s.filters[1], s.seed, &short(340.0)).unwrap();
    let neutral = |r: &kestrel_app::experiment::EpochRecord| {
        let a = r.adaptation;
        a.fade == 1.0 && a.inflation == 1.0 && a.inflated == 0 && a.compression == 1.0
    };
    assert!(ekf.records.iter().all(neutral));
    let inflated = |lo: f64, hi: f64| {
        robust
            .records
            .iter()
            .filter(|r| r.time > lo && r.time <= hi && r.adaptation.inflated > 0)
            .count()
    };
    eprintln!(
        "002 ICT-EREKF: inflated in {} of the 40 multipath epochs, {} of the 299 before",
        inflated(300.0, 340.0),
        inflated(0.0, 299.0)
    );
    assert!(inflated(300.0, 340.0) >= 30);
    print("002", &ekf.summary);
    print("002", &robust.summary);

    // 000: the fading filters report λ > 1 at some epochs (with γ = 4 the
    // first fades fall in the 1.5 m/s velocity-noise window, 50–100 s).
    let s0 = by_name("000").unwrap();
    let faded = run(&s0, &s0.filters[1], s0.seed, &short(100.0)).unwrap();
    assert!(faded.records.iter().any(|r| r.adaptation.fade > 1.0));
    // 003: the fuzzy gain departs from 1 at some epochs.
    let s3 = by_name("003").unwrap();
    let fuzzy = run(&s3, &s3.filters[2], s3.seed, &short(60.0)).unwrap();
    assert!(fuzzy.records.iter().any(|r| r.adaptation.alpha1 != 1.0));
}

#[test]
fn scenario_000_shortened() {
    let s = by_name("000").unwrap();
    let opts = short(300.0).without_records();
    let results: Vec<_> = s
        .filters
        .iter()
        .map(|k| (k.label(), run(&s, k, s.seed, &opts)))
        .collect();
    for (label, r) in &results {
        match r {
            Ok(r) => print("000", &r.summary),
            Err(e) => eprintln!("000 {label}: {e}"),
        }
    }
    let kf = results[0].1.as_ref().unwrap().summary;
    assert_eq!(kf.axes, PositionAxes::EastNorthUp);
    // The standard KF beats the raw GNSS (5 m, 0.3 m/s per axis).
    assert!(
        kf.rms_position.iter().all(|&v| v < 5.0),
        "{:?}",
        kf.rms_position
    );
    assert!(
        kf.rms_velocity.iter().all(|&v| v < 0.3),
        "{:?}",
        kf.rms_velocity
    );
    // Paper 000's ordering against the standard KF: both adaptive filters
    // run through the noise windows and stay below the KF on every axis
    // (fading the whole covariance with γ = 1, λ ≤ 100 diverged here).
    for (label, r) in &results[1..] {
        let m = r
            .as_ref()
            .unwrap_or_else(|e| panic!("{label}: {e}"))
            .summary;
        for (a, k) in m.rms_position.iter().zip(kf.rms_position.iter()) {
            assert!(a < k, "{label}: {:?}", m.rms_position);
        }
        for (a, k) in m.rms_velocity.iter().zip(kf.rms_velocity.iter()) {
            assert!(a < k, "{label}: {:?}", m.rms_velocity);
        }
    }
}

/// Full-length runs of every scenario: `cargo test --release -p kestrel-nav
/// --test experiment -- --ignored --nocapture`.
#[test]
#[ignore]
fn full_length_figures() {
    for s in builtin() {
        for kind in &s.filters {
            match run(&s, kind, s.seed, &RunOptions::default().without_records()) {
                Ok(r) => print(&s.name, &r.summary),
                Err(e) => eprintln!("{} {}: {e}", s.name, kind.label()),
            }
        }
    }
}
