//! Measurements simulated from a benchmark model, so that adapters take the
//! branches they take on a consistent filter at their natural rates.

use kestrel::nalgebra::{SMatrix, SVector};

use super::model::Model;
use super::rng::SplitMix64;

/// Length of the measurement cycle.
pub const CYCLE: usize = 1024;

/// A standard normal draw (Box–Muller on two uniforms in `(0, 1]`).
fn normal(rng: &mut SplitMix64) -> f64 {
    let u1 = 0.5 * (1.0 - rng.symmetric());
    let u2 = 0.5 * (1.0 - rng.symmetric());
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

fn gaussian<const D: usize>(rng: &mut SplitMix64, cov: &SMatrix<f64, D, D>) -> SVector<f64, D> {
    let l = cov.cholesky().expect("SPD by construction").l();
    l * SVector::<f64, D>::from_fn(|_, _| normal(rng))
}

/// `CYCLE` measurements of a truth simulated from `m` (Gaussian process and
/// measurement noise), starting from its `x0`; seeded by `N`.
pub fn measurements<const N: usize, const M: usize>(m: &Model<f64, N, M>) -> Vec<SVector<f64, M>> {
    let mut rng = SplitMix64::new(0x6164_6170_7465_7273 + N as u64);
    let mut x = m.x0;
    (0..CYCLE)
        .map(|_| {
            x = m.phi * x + gaussian(&mut rng, &m.q);
            m.h * x + gaussian(&mut rng, &m.r)
        })
        .collect()
}

/// `steps` predict + update steps of the EKF with `adapter` (`()` for none)
/// over the cycle of [`measurements`], for instruction counts: the model of
/// the step benchmarks, its dense `R` (the batch update), each report handed
/// to `black_box`.
pub fn cycle_steps<A, const N: usize, const M: usize>(adapter: A, steps: usize)
where
    A: kestrel::adapter::NoiseAdapter<f64, M>,
{
    use kestrel::models::{LinearMeasurement, LinearProcess};
    use std::hint::black_box;
    let m = Model::<f64, N, M>::of_step_benchmarks();
    let zs = measurements(&m);
    let process = LinearProcess::new(m.phi, m.q);
    let measurement = LinearMeasurement::new(m.h, m.r);
    let mut f = kestrel::Ekf::new(m.x0, m.p0).unwrap().with_adapter(adapter);
    for z in zs.iter().cycle().take(steps) {
        f.predict(&process, 1.0).expect("predict");
        black_box(f.update(&measurement, black_box(z)).expect("update"));
    }
}

/// `f` after one pass over the cycle `zs` (panics unless every update is
/// accepted on the batch path and `acted` holds for some epoch's report).
pub fn cycled<A, const N: usize, const M: usize>(
    name: &str,
    mut f: kestrel::Filter<f64, N, kestrel::form::CovarianceForm<f64, N>, A>,
    m: &Model<f64, N, M>,
    zs: &[SVector<f64, M>],
    acted: fn(&kestrel::UpdateReport<f64, M, A::Report>) -> bool,
) -> kestrel::Filter<f64, N, kestrel::form::CovarianceForm<f64, N>, A>
where
    A: kestrel::adapter::NoiseAdapter<f64, M>,
{
    use kestrel::models::{LinearMeasurement, LinearProcess};
    let process = LinearProcess::new(m.phi, m.q);
    let measurement = LinearMeasurement::new(m.h, m.r);
    let mut any = false;
    for z in zs {
        f.predict(&process, 1.0).expect("predict");
        let report = f.update(&measurement, z).expect("update");
        assert!(!report.sequential, "{name}: batch update");
        any |= acted(&report);
    }
    assert!(any, "{name}: the adapter never acted");
    f
}
