//! Monte-Carlo consistency of every form on a simulated constant-velocity
//! target (Bar-Shalom, Li & Kirubarajan, ch. 5.4).
//!
//! The truth is drawn from exactly the model the filter uses: the initial
//! state from `N(x̂₀, P₀)`, process noise as `L w` with `L Lᵀ = Q` and
//! `w ~ N(0, I)`, measurement noise as `√r v`. For `R` runs the average NEES
//! at each step is `χ²(R n) / R` distributed and the average NIS
//! `χ²(R m) / R`; both must lie in their two-sided 95 % interval at no fewer
//! than 90 % of the steps, and the averages over all steps in the 99 %
//! interval of `χ²(R K n) / (R K)` (resp. `m`). A filter that assumes a
//! tenth of the true process noise must fail the NEES criterion.
//!
//! The generator is seeded, so the test is deterministic.

use kestrel::form::{PredictForm, SquareRootForm, TimeUpdate, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Matrix1, Matrix1x2, Matrix2, Vector1, Vector2};
use kestrel::{Ekf, Filter, SrUkf, Ukf};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use statrs::distribution::{ChiSquared, ContinuousCDF};

const RUNS: usize = 200;
const STEPS: usize = 100;
/// State and measurement dimensions.
const N: usize = 2;
const M: usize = 1;
const R_POS: f64 = 1.0;

/// White-noise acceleration of unit spectral density over dt = 1:
/// Q = [1/3 1/2; 1/2 1].
fn q_true() -> Matrix2<f64> {
    Matrix2::new(1.0 / 3.0, 0.5, 0.5, 1.0)
}
fn phi() -> Matrix2<f64> {
    Matrix2::new(1.0, 1.0, 0.0, 1.0)
}
fn x0() -> Vector2<f64> {
    Vector2::new(0.0, 1.0)
}
fn p0() -> Matrix2<f64> {
    Matrix2::new(4.0, 0.0, 0.0, 1.0)
}
fn sensor() -> LinearMeasurement<f64, 2, 1> {
    LinearMeasurement::new(Matrix1x2::new(1.0, 0.0), Matrix1::new(R_POS))
}

/// One simulated run: the true states and the measurements of steps 1..=K.
struct Run {
    truth: Vec<Vector2<f64>>,
    z: Vec<f64>,
}

fn normal2(rng: &mut ChaCha8Rng) -> Vector2<f64> {
    Vector2::new(rng.sample(StandardNormal), rng.sample(StandardNormal))
}

fn simulate(seed: u64) -> Vec<Run> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let lq = q_true().cholesky().expect("Q is positive definite").l();
    let lp = p0().cholesky().expect("P₀ is positive definite").l();
    (0..RUNS)
        .map(|_| {
            let mut x = x0() + lp * normal2(&mut rng);
            let mut run = Run {
                truth: Vec::with_capacity(STEPS),
                z: Vec::with_capacity(STEPS),
            };
            for _ in 0..STEPS {
                x = phi() * x + lq * normal2(&mut rng);
                let v: f64 = rng.sample(StandardNormal);
                run.truth.push(x);
                run.z.push(x[0] + R_POS.sqrt() * v);
            }
            run
        })
        .collect()
}

/// Average NEES and NIS over the runs, per step.
struct Averages {
    nees: Vec<f64>,
    nis: Vec<f64>,
}

/// Runs a filter made by `make` over every run, assuming process noise
/// `q_scale · Q`.
fn evaluate<F>(data: &[Run], q_scale: f64, make: impl Fn() -> Filter<f64, 2, F>) -> Averages
where
    F: PredictForm<f64, 2, LinearProcess<f64, 2>>
        + UpdateForm<f64, 2, LinearMeasurement<f64, 2, 1>, 1>,
{
    let process = LinearProcess::new(phi(), q_true() * q_scale);
    let mut avg = Averages {
        nees: vec![0.0; STEPS],
        nis: vec![0.0; STEPS],
    };
    for run in data {
        let mut f = make();
        for k in 0..STEPS {
            f.predict(&process, 1.0).unwrap();
            let report = f.update(&sensor(), &Vector1::new(run.z[k])).unwrap();
            let e = run.truth[k] - f.state();
            let p = f
                .covariance()
                .cholesky()
                .expect("posterior covariance is PD");
            avg.nees[k] += e.dot(&p.solve(&e)) / RUNS as f64;
            avg.nis[k] += report.nis / RUNS as f64;
        }
    }
    avg
}

/// The two-sided interval of probability `mass` of `χ²(dof) / scale`.
fn interval(dof: usize, scale: usize, mass: f64) -> (f64, f64) {
    let chi2 = ChiSquared::new(dof as f64).unwrap();
    let tail = (1.0 - mass) / 2.0;
    (
        chi2.inverse_cdf(tail) / scale as f64,
        chi2.inverse_cdf(1.0 - tail) / scale as f64,
    )
}

/// How a sequence of run-averaged statistics with `dim` degrees of freedom
/// per run and step compares with its χ² distribution.
#[derive(Debug)]
struct Verdict {
    /// Fraction of steps inside the 95 % interval.
    inside: f64,
    /// The average over all steps, and its 99 % interval.
    mean: f64,
    bounds: (f64, f64),
}

impl Verdict {
    fn new(avg: &[f64], dim: usize) -> Self {
        let (lo, hi) = interval(RUNS * dim, RUNS, 0.95);
        let inside = avg.iter().filter(|&&v| lo <= v && v <= hi).count();
        Self {
            inside: inside as f64 / avg.len() as f64,
            mean: avg.iter().sum::<f64>() / avg.len() as f64,
            bounds: interval(RUNS * STEPS * dim, RUNS * STEPS, 0.99),
        }
    }

    fn consistent(&self) -> bool {
        self.inside >= 0.9 && self.bounds.0 <= self.mean && self.mean <= self.bounds.1
    }
}

fn check<F>(name: &str, data: &[Run], make: impl Fn() -> Filter<f64, 2, F> + Copy)
where
    F: PredictForm<f64, 2, LinearProcess<f64, 2>>
        + UpdateForm<f64, 2, LinearMeasurement<f64, 2, 1>, 1>,
{
    let avg = evaluate(data, 1.0, make);
    let nees = Verdict::new(&avg.nees, N);
    let nis = Verdict::new(&avg.nis, M);
    assert!(nees.consistent(), "{name}: NEES {nees:?}");
    assert!(nis.consistent(), "{name}: NIS {nis:?}");

    // Negative control: Q/10 makes the filter overconfident.
    let avg = evaluate(data, 0.1, make);
    let nees = Verdict::new(&avg.nees, N);
    assert!(
        !nees.consistent(),
        "{name}: overconfident filter passed {nees:?}"
    );
    assert!(nees.inside < 0.9, "{name}: {nees:?}");
    assert!(nees.mean > nees.bounds.1, "{name}: {nees:?}");
}

#[test]
fn chi_square_quantiles() {
    // Tabulated values: χ²₀.₉₇₅(1) = 5.0239, χ²₀.₀₂₅(10) = 3.2470.
    let chi2 = |k: f64| ChiSquared::new(k).unwrap();
    assert!((chi2(1.0).inverse_cdf(0.975) - 5.0239).abs() < 1e-4);
    assert!((chi2(10.0).inverse_cdf(0.025) - 3.2470).abs() < 1e-4);
}

#[test]
fn ekf_is_consistent() {
    check("ekf", &simulate(1), || Ekf::new(x0(), p0()).unwrap());
}

#[test]
fn ukf_is_consistent() {
    check("ukf", &simulate(2), || Ukf::new(x0(), p0()).unwrap());
}

#[test]
fn square_root_ukf_is_consistent() {
    let data = simulate(3);
    check("sr-ukf", &data, || SrUkf::new(x0(), p0()).unwrap());
    check("sr-ukf rank-one", &data, || {
        let form = SquareRootForm::new(&p0())
            .unwrap()
            .with_time_update(TimeUpdate::RankOne);
        SrUkf::with_form(x0(), form).unwrap()
    });
}
