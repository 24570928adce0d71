//! Cost of the noise adapters: one EKF predict plus one update with each
//! adapter of `kestrel-adaptive` alone and with the compositions of paper
//! 000, next to the plain step, so the overhead of each can be read off.
//!
//! The model is the dense, stable, seeded linear model of the step
//! benchmarks (`common::model`) at `N = 15` and `N = 18`, `M = 6`, with a
//! dense `R` (the plain filter takes the batch update). Unlike the step
//! benchmarks the measurements are not constant: a cycle of 1024 epochs
//! simulated from the model itself (Gaussian process and measurement
//! noise), so each adapter takes the branches it takes on a consistent
//! filter at their natural rates. Before timing, every filter runs the whole
//! cycle once and must accept every update; the set-up checks that the
//! adapter acted (an estimate, a compression, a fade …).
//!
//! Groups `adapter_step/<N>/<variant>`, variants: `plain`, `sage_husa`,
//! `divergence_fading` (`γ = 3`), `strong_tracking` (`ρ = 0.95`, `β = 1`: it
//! fades in a large share of the epochs), `outlier_compression`
//! (`α = 0.05`), `improved_adaptive` (`ImprovedAdaptive::as_published`),
//! `sage_husa_fading` (`SageHusaFading::as_published`), `huber_inflation`,
//! `chi_square_gate` (`α = 0.01`), `windowed_noise` (window 10),
//! `fuzzy_gain` (odometer rule base, inputs set every epoch).
//!
//! `cargo bench --bench adapters -- --warm-up-time 1 --measurement-time 3`
//! (append a filter such as `'/18/'` for one size).

#[allow(dead_code)]
mod common;

use std::hint::black_box;

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion};
use kestrel::adapter::NoiseAdapter;
use kestrel::adaptive::{
    ChiSquareGate, DivergenceFading, FuzzyGain, HuberInflation, ImprovedAdaptive, OdometerInputs,
    OutlierCompression, SageHusa, SageHusaFading, StrongTracking, WindowedNoise,
};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::SVector;
use kestrel::{Ekf, UpdateReport};

use common::model::Model;
use common::simulate::{measurements, CYCLE};

type Group<'a> = BenchmarkGroup<'a, WallTime>;

const M: usize = 6;
/// The per-epoch hook (sets the fuzzy gain's inputs; nothing for the rest).
type Hook<A> = fn(&mut A);

fn no_hook<A>(_: &mut A) {}

fn odometer_inputs(a: &mut FuzzyGain<f64, M>) {
    a.set_inputs(OdometerInputs::new(1.0, 0.0, SVector::zeros()));
}

/// Runs the cycle once (every update must succeed; `acted` must hold for
/// some epoch's report), then times predict + update over the cycle.
fn time<const N: usize, A: NoiseAdapter<f64, M>>(
    g: &mut Group,
    name: &str,
    adapter: A,
    hook: Hook<A>,
    acted: fn(&UpdateReport<f64, M, A::Report>) -> bool,
) {
    let m = Model::<f64, N, M>::of_step_benchmarks();
    let zs = measurements(&m);
    let process = LinearProcess::new(m.phi, m.q);
    let sensor = LinearMeasurement::new(m.h, m.r);
    let mut f = Ekf::new(m.x0, m.p0).unwrap().with_adapter(adapter);
    let mut any = false;
    for z in &zs {
        f.predict(&process, 1.0).expect("predict");
        hook(f.adapter_mut());
        let report = f.update(&sensor, z).expect("update");
        assert!(!report.sequential, "{name}: batch update");
        any |= acted(&report);
    }
    assert!(any, "{name}/{N}: the adapter never acted");
    let mut k = 0;
    g.bench_function(format!("{N}/{name}"), |b| {
        b.iter(|| {
            f.predict(&process, 1.0).expect("predict");
            hook(f.adapter_mut());
            black_box(f.update(&sensor, black_box(&zs[k])).expect("update"));
            k = (k + 1) % CYCLE;
        })
    });
}

fn size<const N: usize>(g: &mut Group) {
    time::<N, ()>(g, "plain", (), no_hook, |_| true);
    time::<N, _>(
        g,
        "sage_husa",
        SageHusa::as_published().unwrap(),
        no_hook,
        |r| r.adapters.estimated,
    );
    time::<N, _>(
        g,
        "divergence_fading",
        DivergenceFading::new(3.0, 100.0).unwrap(),
        no_hook,
        |r| r.adapters.diverged,
    );
    time::<N, _>(
        g,
        "strong_tracking",
        StrongTracking::new(0.95, 1.0).unwrap(),
        no_hook,
        |r| r.adapters.fade > 1.0,
    );
    time::<N, _>(
        g,
        "outlier_compression",
        OutlierCompression::as_published().unwrap(),
        no_hook,
        |r| r.adapters.compressed,
    );
    time::<N, _>(
        g,
        "improved_adaptive",
        ImprovedAdaptive::as_published().unwrap(),
        no_hook,
        |r| r.adapters.sage_husa.estimated && r.adapters.tests.0.compressed,
    );
    time::<N, _>(
        g,
        "sage_husa_fading",
        SageHusaFading::as_published().unwrap(),
        no_hook,
        |r| r.adapters.sage_husa.estimated,
    );
    time::<N, _>(
        g,
        "huber_inflation",
        HuberInflation::as_published().unwrap(),
        no_hook,
        |r| r.adapters.inflated > 0,
    );
    time::<N, _>(
        g,
        "chi_square_gate",
        ChiSquareGate::new(0.01).unwrap(),
        no_hook,
        |r| r.rejected,
    );
    time::<N, _>(
        g,
        "windowed_noise",
        WindowedNoise::<f64, M, 10>::new(1e-3).unwrap(),
        no_hook,
        |r| r.adapters.estimated,
    );
    time::<N, _>(
        g,
        "fuzzy_gain",
        FuzzyGain::odometer().unwrap(),
        odometer_inputs,
        |r| r.adapters.alpha != 1.0,
    );
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("adapter_step");
    size::<15>(&mut g);
    size::<18>(&mut g);
    g.finish();
}

criterion_group!(adapters, benches);
criterion_main!(adapters);
