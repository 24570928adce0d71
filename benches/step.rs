//! Cost of one predict plus one update on a dense, stable, seeded linear
//! model, by state size `N` (measurement size `M = min(N, 6)`): the three
//! kestrel forms and their variants next to a hand-written nalgebra filter
//! and the `adskalman` crate, so one run gives every ratio.
//!
//! Each benchmark keeps one filter and steps it with a constant measurement:
//! the model is stable, so the filter converges to a fixed point and the
//! loop is stationary. Before timing, every filter is run a few steps and
//! checked against the hand-written `f64` filter, so a benchmark cannot
//! silently time a wrong or failing path.
//!
//! Groups (each `<group>/<N>`, N ∈ {2, 4, 6, 9, 12, 15, 18, 24, 32}):
//! `kf_step` (dense `R`, batch Joseph update), `kf_step_diag` (diagonal `R`,
//! sequential scalar updates at every size), `kf_step_diag_batch` (diagonal
//! `R`, batch; the default path below four measurement components and above
//! twelve states),
//! `ukf_step`, `srukf_step` (Householder time update), `srukf_step_rankone`,
//! and the baselines `nalgebra_step` and `adskalman_step`; in `f32` at
//! `N = 15` only: `kf_step_f32`, `ukf_step_f32`, `srukf_step_f32`.
//!
//! `cargo bench --bench step -- --warm-up-time 1 --measurement-time 3`
//! (append a filter such as `'/15$'` for one size).

mod common;

use std::hint::black_box;

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, BenchmarkId, Criterion};
use kestrel::form::{PredictForm, SquareRootForm, TimeUpdate, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Const, DimMin, SMatrix, SVector};
use kestrel::{Ekf, Filter, Real, SrUkf, Ukf};

use common::adskalman_kf;
use common::hand::HandKf;
use common::model::Model;
use common::reference::{self, CHECK_STEPS};

type Group<'a> = BenchmarkGroup<'a, WallTime>;

/// Which measurement noise a benchmark uses.
#[derive(Clone, Copy)]
enum Noise {
    Dense,
    Diagonal,
}

fn model<T: Real, const N: usize, const M: usize>() -> Model<T, N, M> {
    Model::<f64, N, M>::of_step_benchmarks().to()
}

fn noise<T: Real, const N: usize, const M: usize>(
    m: &Model<T, N, M>,
    n: Noise,
) -> SMatrix<T, M, M> {
    match n {
        Noise::Dense => m.r,
        Noise::Diagonal => m.r_diag,
    }
}

/// Panics unless `(x, p)` matches the hand-written `f64` filter (see
/// [`reference::check`]).
fn check<T: Real, const N: usize, const M: usize>(
    what: &str,
    x: &SVector<T, N>,
    p: &SMatrix<T, N, N>,
    n: Noise,
) {
    let m = model::<f64, N, M>();
    reference::check(what, &m, &noise(&m, n), x, p);
}

/// Checks `f` and times its predict + update.
fn time_filter<T, const N: usize, const M: usize, F>(
    g: &mut Group,
    name: &str,
    mut f: Filter<T, N, F>,
    m: &Model<T, N, M>,
    n: Noise,
    sequential: bool,
) where
    T: Real,
    F: PredictForm<T, N, LinearProcess<T, N>> + UpdateForm<T, N, LinearMeasurement<T, N, M>, M>,
{
    let process = LinearProcess::new(m.phi, m.q);
    let measurement = LinearMeasurement::new(m.h, noise(m, n));
    let z = m.z;
    for _ in 0..CHECK_STEPS {
        f.predict(&process, T::one()).expect("predict");
        let report = f.update(&measurement, &z).expect("update");
        assert_eq!(report.sequential, sequential, "{name}: update path");
    }
    check::<T, N, M>(name, f.state(), &f.covariance(), n);
    g.bench_function(BenchmarkId::from_parameter(N), |b| {
        b.iter(|| {
            f.predict(&process, T::one()).expect("predict");
            black_box(f.update(&measurement, black_box(&z)).expect("update"));
        })
    });
}

fn kf<T: Real, const N: usize, const M: usize>(g: &mut Group, name: &str) {
    let m = model::<T, N, M>();
    let f = Ekf::new(m.x0, m.p0).unwrap();
    time_filter(g, name, f, &m, Noise::Dense, false);
}

fn kf_diag<T: Real, const N: usize, const M: usize>(g: &mut Group, name: &str) {
    let m = model::<T, N, M>();
    let mut f = Ekf::new(m.x0, m.p0).unwrap();
    f.form_mut().set_sequential(true);
    time_filter(g, name, f, &m, Noise::Diagonal, true);
}

fn kf_diag_batch<T: Real, const N: usize, const M: usize>(g: &mut Group, name: &str) {
    let m = model::<T, N, M>();
    let mut f = Ekf::new(m.x0, m.p0).unwrap();
    f.form_mut().set_sequential(false);
    time_filter(g, name, f, &m, Noise::Diagonal, false);
}

fn ukf<T: Real, const N: usize, const M: usize>(g: &mut Group, name: &str) {
    let m = model::<T, N, M>();
    let f = Ukf::new(m.x0, m.p0).unwrap();
    time_filter(g, name, f, &m, Noise::Dense, false);
}

fn srukf<T: Real, const N: usize, const M: usize>(g: &mut Group, name: &str) {
    let m = model::<T, N, M>();
    let f = SrUkf::new(m.x0, m.p0).unwrap();
    time_filter(g, name, f, &m, Noise::Dense, false);
}

fn srukf_rankone<T: Real, const N: usize, const M: usize>(g: &mut Group, name: &str) {
    let m = model::<T, N, M>();
    let form = SquareRootForm::new(&m.p0)
        .unwrap()
        .with_time_update(TimeUpdate::RankOne);
    let f = Filter::with_form(m.x0, form).unwrap();
    time_filter(g, name, f, &m, Noise::Dense, false);
}

fn nalgebra<T: Real, const N: usize, const M: usize>(g: &mut Group, name: &str) {
    let m = model::<T, N, M>();
    let mut f = HandKf::new(m.x0, m.p0);
    for _ in 0..CHECK_STEPS {
        assert!(f.step(&m, &m.r, &m.z));
    }
    check::<T, N, M>(name, &f.x, &f.p, Noise::Dense);
    g.bench_function(BenchmarkId::from_parameter(N), |b| {
        b.iter(|| assert!(f.step(&m, &m.r, black_box(&m.z))))
    });
}

fn adskalman<T: Real, const N: usize, const M: usize>(g: &mut Group, name: &str)
where
    Const<M>: DimMin<Const<M>, Output = Const<M>>,
{
    let m = model::<T, N, M>();
    let (process, measurement) = adskalman_kf::models(&m, &m.r);
    let kf =
        ::adskalman::KalmanFilterNoControl::<T, Const<N>, Const<M>>::new(&process, &measurement);
    let mut est = ::adskalman::StateAndCovariance::<T, Const<N>>::new(m.x0, m.p0);
    for _ in 0..CHECK_STEPS {
        est = kf.step(&est, &m.z).expect("adskalman step");
    }
    check::<T, N, M>(name, est.state(), est.covariance(), Noise::Dense);
    g.bench_function(BenchmarkId::from_parameter(N), |b| {
        b.iter(|| est = kf.step(&est, black_box(&m.z)).expect("adskalman step"))
    });
}

/// Runs `$bench` at every state size (`M = min(N, 6)`) in group `$name`.
macro_rules! every_size {
    ($c:expr, $name:literal, $bench:ident) => {{
        let mut g = $c.benchmark_group($name);
        $bench::<f64, 2, 2>(&mut g, $name);
        $bench::<f64, 4, 4>(&mut g, $name);
        $bench::<f64, 6, 6>(&mut g, $name);
        $bench::<f64, 9, 6>(&mut g, $name);
        $bench::<f64, 12, 6>(&mut g, $name);
        $bench::<f64, 15, 6>(&mut g, $name);
        $bench::<f64, 18, 6>(&mut g, $name);
        $bench::<f64, 24, 6>(&mut g, $name);
        $bench::<f64, 32, 6>(&mut g, $name);
        g.finish();
    }};
}

/// Runs `$bench` in `f32` at `N = 15, M = 6` in group `$name`.
macro_rules! single_f32 {
    ($c:expr, $name:literal, $bench:ident) => {{
        let mut g = $c.benchmark_group($name);
        $bench::<f32, 15, 6>(&mut g, $name);
        g.finish();
    }};
}

fn benches(c: &mut Criterion) {
    every_size!(c, "kf_step", kf);
    every_size!(c, "ukf_step", ukf);
    every_size!(c, "srukf_step", srukf);
    every_size!(c, "kf_step_diag", kf_diag);
    every_size!(c, "kf_step_diag_batch", kf_diag_batch);
    every_size!(c, "srukf_step_rankone", srukf_rankone);
    every_size!(c, "nalgebra_step", nalgebra);
    every_size!(c, "adskalman_step", adskalman);
    single_f32!(c, "kf_step_f32", kf);
    single_f32!(c, "ukf_step_f32", ukf);
    single_f32!(c, "srukf_step_f32", srukf);
}

criterion_group!(step, benches);
criterion_main!(step);
