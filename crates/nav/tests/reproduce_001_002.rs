//! The reproductions of papers 001 and 002, full length, asserted.
//!
//! 001 (federated UKF vs SR-UKF): in `f64` the two are one filter (they
//! differ by rounding only, ≤ 10⁻⁶); with the paper's own tuning both also
//! complete in `f32` and in badly scaled units; with an over-confident
//! process noise (densities ×10⁻²) in `f32` and mixed units the UKF's
//! covariance loses positive definiteness within two minutes while the
//! SR-UKF completes, close to its `f64` run.
//!
//! 002 (ICT-EREKF vs EKF on urban multipath): over eight seeds the robust
//! filter's 3-D RMS is on average ≥ 25 % below the EKF's in position and
//! ≥ 40 % in velocity (the paper: 25 %, 50 %), and the EKF's errors have
//! the paper's size and shape (vertical ≫ horizontal).
//!
//! Figures: `cargo test --release -p kestrel-nav --test reproduce_001_002
//! -- --nocapture`.

use kestrel_adaptive::federated::FusionError;
use kestrel_nav::experiment::{
    compare_federated_precision, run, Outcome, Precision, PrecisionOptions, PrecisionSetup,
    RunError, RunOptions, RunSummary, StateScaling,
};
use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::scenario::{by_name, FilterKind};

const UKF: &str = "federated UKF";
const SRUKF: &str = "federated SR-UKF";

fn options(setups: Vec<PrecisionSetup>, noise: f64) -> PrecisionOptions {
    PrecisionOptions {
        run: RunOptions::default(),
        setups,
        process_noise_scale: noise,
    }
}

fn f32_in(scaling: StateScaling) -> PrecisionSetup {
    PrecisionSetup {
        precision: Precision::F32,
        scaling,
    }
}

#[test]
fn federated_srukf_equals_ukf_in_f64() {
    let s = by_name("001").unwrap();
    let r = compare_federated_precision(&s, s.seed, &options(vec![], 1.0)).unwrap();
    eprintln!("{r}");
    assert_eq!(r.runs.len(), 2);
    for row in &r.runs {
        assert_eq!(row.outcome, Outcome::Completed, "{}", row.filter);
        assert_eq!(row.summary.epochs, 600);
    }
    let d = r.f64_difference;
    assert_eq!(d.epochs, 600);
    assert!(d.position <= 1e-6, "{d:?}");
    assert!(d.velocity <= 1e-6, "{d:?}");
    assert!(d.attitude <= 1e-6, "{d:?}");
    // The comparison's f64 loop is the experiment runner's federated loop:
    // same data, same RMS.
    let ukf = run(
        &s,
        &s.filters[0],
        s.seed,
        &RunOptions::default().without_records(),
    )
    .unwrap()
    .summary;
    assert_eq!(ukf.filter, UKF);
    let mine = &r.runs[0].summary;
    assert_eq!(mine.data_digest, ukf.data_digest);
    assert!((mine.rms_position - ukf.rms_position).norm() < 1e-9);
    assert!((mine.rms_velocity - ukf.rms_velocity).norm() < 1e-12);
}

#[test]
fn with_the_paper_tuning_both_complete_in_f32_and_mixed_units() {
    let s = by_name("001").unwrap();
    let r = compare_federated_precision(&s, s.seed, &PrecisionOptions::default()).unwrap();
    eprintln!("{r}");
    assert_eq!(r.runs.len(), 8);
    for row in &r.runs {
        assert_eq!(
            row.outcome,
            Outcome::Completed,
            "{} {}",
            row.setup,
            row.filter
        );
        assert_eq!(row.summary.epochs, 600);
        // Measured: at most 3.3e-4 m (f32, mixed units, SR-UKF).
        assert!(row.from_f64.position < 1e-3, "{} {}", row.setup, row.filter);
        assert_eq!(row.from_f64.epochs, 600);
    }
}

#[test]
fn with_small_process_noise_the_f32_ukf_fails_and_the_srukf_does_not() {
    let s = by_name("001").unwrap();
    let setups = vec![f32_in(StateScaling::mixed())];
    for seed in 1..=3 {
        let r = compare_federated_precision(&s, seed, &options(setups.clone(), 0.01)).unwrap();
        eprintln!("{r}");
        // f64: still one filter.
        assert!(r.f64_difference.position <= 1e-6, "{seed}");
        assert!(r.runs[..2].iter().all(|row| row.outcome.completed()));
        let ukf = r.run(UKF, Precision::F32, "mixed units").unwrap();
        let sr = r.run(SRUKF, Precision::F32, "mixed units").unwrap();
        // The UKF's (or, after a reset from the fusion, the EKF's) covariance
        // is no longer positive definite: measured at 90–106 s.
        match &ukf.outcome {
            Outcome::Failed(RunError::Fusion {
                time,
                error: FusionError::NotPositiveDefinite { .. },
                ..
            }) => assert!(*time < 200.0, "{seed}: {time}"),
            other => panic!("seed {seed}: {other}"),
        }
        assert_eq!(sr.outcome, Outcome::Completed, "{seed}");
        assert_eq!(sr.summary.epochs, 600);
        // Measured: 1.7–3.5 cm from its f64 run.
        assert!(sr.from_f64.position < 0.1, "{seed}: {:?}", sr.from_f64);
    }
}

/// 1 − ‖RMS_robust‖ / ‖RMS_EKF‖ of the 3-D RMS vectors.
fn gain(ekf: &Vector3<f64>, robust: &Vector3<f64>) -> f64 {
    1.0 - robust.norm() / ekf.norm()
}

fn show(seed: u64, m: &RunSummary) {
    let xyz = |v: &Vector3<f64>| format!("{:.3} {:.3} {:.3}", v.x, v.y, v.z);
    eprintln!(
        "002 seed {seed} {:>10}: position {} m, velocity {} m/s, attitude {}°",
        m.filter,
        xyz(&m.rms_position),
        xyz(&m.rms_velocity),
        xyz(&m.rms_attitude.map(f64::to_degrees))
    );
}

#[test]
fn ict_erekf_beats_the_ekf_on_urban_multipath() {
    let s = by_name("002").unwrap();
    assert!(matches!(s.filters[1], FilterKind::IctErekf { .. }));
    let opts = RunOptions::default().without_records();
    let seeds: Vec<u64> = (0..8).collect();
    // One thread per seed: the runs are independent.
    let pairs: Vec<(RunSummary, RunSummary)> = std::thread::scope(|scope| {
        let (s, opts) = (&s, &opts);
        let handles: Vec<_> = seeds
            .iter()
            .map(|&seed| {
                scope.spawn(move || {
                    let ekf = run(s, &s.filters[0], seed, opts).unwrap().summary;
                    let ict = run(s, &s.filters[1], seed, opts).unwrap().summary;
                    (ekf, ict)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let n = pairs.len() as f64;
    let (mut pos, mut vel) = (0.0, 0.0);
    let (mut ekf_pos, mut ekf_vel) = (Vector3::zeros(), Vector3::zeros());
    for (seed, (ekf, ict)) in seeds.iter().zip(&pairs) {
        show(*seed, ekf);
        show(*seed, ict);
        let (p, v) = (
            gain(&ekf.rms_position, &ict.rms_position),
            gain(&ekf.rms_velocity, &ict.rms_velocity),
        );
        eprintln!(
            "002 seed {seed}: position {:.1} %, velocity {:.1} % better",
            100.0 * p,
            100.0 * v
        );
        pos += p / n;
        vel += v / n;
        ekf_pos += ekf.rms_position / n;
        ekf_vel += ekf.rms_velocity / n;
        // An urban canyon: the EKF's vertical error dominates.
        assert!(ekf.rms_position.z > ekf.rms_position.xy().norm(), "{seed}");
        // Every seed improves; only the mean has to reach the targets.
        assert!(p > 0.1 && v > 0.3, "seed {seed}: {p} {v}");
    }
    eprintln!(
        "002 mean of {n} seeds: position {:.1} %, velocity {:.1} % better; EKF position {:.2} m, \
         velocity {:.3} m/s (3-D; paper 8.66 m, 0.164 m/s)",
        100.0 * pos,
        100.0 * vel,
        ekf_pos.norm(),
        ekf_vel.norm()
    );
    // The paper's vertical is 2.3 times its horizontal.
    assert!(ekf_pos.z > 1.5 * ekf_pos.xy().norm(), "{ekf_pos:?}");
    assert!(pos >= 0.25, "{pos}");
    assert!(vel >= 0.40, "{vel}");
    // The EKF's errors have the paper's size (3-D RMS 8.66 m, 0.164 m/s)
    // within 25 %.
    assert!((ekf_pos.norm() / 8.66 - 1.0).abs() < 0.25, "{ekf_pos:?}");
    assert!((ekf_vel.norm() / 0.164 - 1.0).abs() < 0.25, "{ekf_vel:?}");
}
