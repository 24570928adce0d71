//! The `demo` command: a radar tracking Monte Carlo with the three update
//! forms side by side (accuracy, consistency, cost).

use std::time::Instant;

use kestrel::models::{ConstantVelocity2d, RangeBearing};
use kestrel::nalgebra::{Matrix2, Matrix4, Vector2, Vector4};
use kestrel::{Ekf, Filter, FilterError, MeasurementModel, ProcessModel, SrUkf, Ukf};
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// The demo's size and seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DemoOptions {
    /// Monte-Carlo runs.
    pub runs: usize,
    /// Radar scans per run (one per second).
    pub steps: usize,
    /// Seed of the random number generator (runs are reproducible).
    pub seed: u64,
}

/// One filter's figures over every scan of every run.
#[derive(Clone, Debug, PartialEq)]
pub struct DemoRow {
    /// The filter.
    pub name: &'static str,
    /// Position RMS, m.
    pub position_rms: f64,
    /// Velocity RMS, m/s.
    pub velocity_rms: f64,
    /// Mean NEES (4 for a consistent filter).
    pub mean_nees: f64,
    /// Mean NIS (2 for a consistent filter).
    pub mean_nis: f64,
    /// Cycles that failed.
    pub errors: usize,
    /// Wall time per predict + update cycle, ns.
    pub nanos_per_cycle: f64,
}

/// Acceleration noise density of the target (m²/s³).
pub const ACCEL_PSD: f64 = 0.5;
/// Radar range noise (m).
pub const RANGE_SIGMA: f64 = 10.0;
/// Radar bearing noise (rad).
pub const BEARING_SIGMA: f64 = 0.01;
/// Scan interval (s).
const DT: f64 = 1.0;

/// Accumulated statistics of one filter.
#[derive(Default)]
struct Stats {
    pos_sq: f64,
    vel_sq: f64,
    nees: f64,
    nis: f64,
    samples: usize,
    updates: usize,
    errors: usize,
    nanos: u128,
}

/// What one predict + update cycle gives: the estimate, its covariance and
/// the NIS.
type Cycle = Result<(Vector4<f64>, Matrix4<f64>, f64), FilterError>;

/// The most Monte-Carlo runs of the demo.
pub const MAX_RUNS: usize = 100_000;

/// The most radar scans per run.
pub const MAX_STEPS: usize = 100_000;

/// The most scans in all (runs × steps): about a minute on one core.
pub const MAX_SCANS: usize = 10_000_000;

/// Tracks a constant-velocity target with a range-bearing radar with the
/// covariance-form EKF, the UKF and the square-root UKF on the same data.
///
/// # Errors
/// A one-line message for zero runs or steps, or more than [`MAX_RUNS`],
/// [`MAX_STEPS`] or [`MAX_SCANS`].
///
/// ```
/// use kestrel_app::demo::{radar_demo, DemoOptions};
/// let rows = radar_demo(&DemoOptions { runs: 2, steps: 20, seed: 1 }).unwrap();
/// assert_eq!(rows.len(), 3);
/// assert!(rows.iter().all(|r| r.errors == 0 && r.position_rms < 100.0));
/// let e = radar_demo(&DemoOptions { runs: 1_000_000_000_000, steps: 20, seed: 1 }).unwrap_err();
/// assert!(e.starts_with("--runs is at most 100000"), "{e}");
/// ```
pub fn radar_demo(args: &DemoOptions) -> Result<Vec<DemoRow>, String> {
    if args.runs == 0 || args.steps == 0 {
        return Err("--runs and --steps must be at least 1".into());
    }
    if args.runs > MAX_RUNS || args.steps > MAX_STEPS {
        return Err(format!(
            "--runs is at most {MAX_RUNS} and --steps at most {MAX_STEPS}, found {} and {}",
            args.runs, args.steps
        ));
    }
    if args.runs * args.steps > MAX_SCANS {
        return Err(format!(
            "--runs × --steps is at most {MAX_SCANS} scans (about a minute), found {}",
            args.runs * args.steps
        ));
    }
    let cv = ConstantVelocity2d::new(ACCEL_PSD).map_err(|e| e.to_string())?;
    let radar = RangeBearing::<f64, 4>::new(
        0,
        2,
        Matrix2::new(RANGE_SIGMA.powi(2), 0.0, 0.0, BEARING_SIGMA.powi(2)),
    )
    .map_err(|e| e.to_string())?;
    let p0 = Matrix4::from_diagonal(&Vector4::new(
        50.0_f64.powi(2),
        5.0_f64.powi(2),
        50.0_f64.powi(2),
        5.0_f64.powi(2),
    ));
    let q_chol = cv
        .noise(&Vector4::zeros(), DT)
        .cholesky()
        .ok_or("process noise not positive definite")?
        .l();
    let p0_chol = p0.cholesky().ok_or("initial covariance")?.l();
    let r_chol = radar.noise().cholesky().ok_or("radar noise")?.l();

    let names = ["EKF (Joseph)", "UKF", "SR-UKF"];
    let mut stats: [Stats; 3] = Default::default();
    let mut rng = ChaCha8Rng::seed_from_u64(args.seed);
    for _ in 0..args.runs {
        let mut truth = Vector4::new(2000.0, -15.0, 1500.0, 10.0);
        let x0 = truth + p0_chol * normal4(&mut rng);
        let mut ekf = Ekf::new(x0, p0).map_err(|e| e.to_string())?;
        let mut ukf = Ukf::new(x0, p0).map_err(|e| e.to_string())?;
        let mut srukf = SrUkf::new(x0, p0).map_err(|e| e.to_string())?;
        for _ in 0..args.steps {
            truth = cv.propagate(&truth, DT) + q_chol * normal4(&mut rng);
            let noise =
                r_chol * Vector2::new(rng.sample(StandardNormal), rng.sample(StandardNormal));
            let z = radar.predict(&truth) + noise;
            let outcomes = [
                timed(|| cycle(&mut ekf, &cv, &radar, &z)),
                timed(|| cycle(&mut ukf, &cv, &radar, &z)),
                timed(|| cycle(&mut srukf, &cv, &radar, &z)),
            ];
            for ((outcome, nanos), s) in outcomes.into_iter().zip(stats.iter_mut()) {
                s.nanos += nanos;
                s.samples += 1;
                match outcome {
                    Ok((x, p, nis)) => {
                        let e = x - truth;
                        s.pos_sq += e[0] * e[0] + e[2] * e[2];
                        s.vel_sq += e[1] * e[1] + e[3] * e[3];
                        s.nees += p.cholesky().map_or(f64::NAN, |c| e.dot(&c.solve(&e)));
                        s.nis += nis;
                        s.updates += 1;
                    }
                    Err(_) => s.errors += 1,
                }
            }
        }
    }

    Ok(names
        .iter()
        .zip(&stats)
        .map(|(name, s)| {
            let n = s.updates.max(1) as f64;
            DemoRow {
                name,
                position_rms: (s.pos_sq / n).sqrt(),
                velocity_rms: (s.vel_sq / n).sqrt(),
                mean_nees: s.nees / n,
                mean_nis: s.nis / n,
                errors: s.errors,
                nanos_per_cycle: s.nanos as f64 / s.samples.max(1) as f64,
            }
        })
        .collect())
}

/// Runs `f` and measures its wall time in nanoseconds.
fn timed(f: impl FnOnce() -> Cycle) -> (Cycle, u128) {
    let start = Instant::now();
    let out = f();
    (out, start.elapsed().as_nanos())
}

/// One predict + update; returns the estimate, its covariance and the NIS.
fn cycle<F>(
    filter: &mut Filter<f64, 4, F>,
    cv: &ConstantVelocity2d<f64>,
    radar: &RangeBearing<f64, 4>,
    z: &Vector2<f64>,
) -> Cycle
where
    F: kestrel::form::PredictForm<f64, 4, ConstantVelocity2d<f64>>
        + kestrel::form::UpdateForm<f64, 4, RangeBearing<f64, 4>, 2>,
{
    filter.predict(cv, DT)?;
    let report = filter.update(radar, z)?;
    Ok((*filter.state(), filter.covariance(), report.nis))
}

/// Four independent standard normal draws.
fn normal4(rng: &mut impl Rng) -> Vector4<f64> {
    Vector4::new(
        rng.sample(StandardNormal),
        rng.sample(StandardNormal),
        rng.sample(StandardNormal),
        rng.sample(StandardNormal),
    )
}
