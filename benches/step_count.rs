//! A fixed number of predict + update steps of one filter on the model of
//! the `step` benchmark, for instruction counts that do not depend on the
//! machine's load:
//!
//! ```sh
//! cargo bench --bench step_count --no-run          # prints the binary's path
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null BINARY kf 15 2000
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null BINARY kf 15 0
//! ```
//!
//! The difference of the two totals ("Collected") divided by 2000 is the
//! count per step. Callgrind counts a `rep stosb` once per byte it stores,
//! and glibc's `memset` uses one from 2 KiB on (the unscented steps zero
//! their sigma sets, 3,600 bytes at 15 states in `f64`); run valgrind with
//! `GLIBC_TUNABLES=glibc.cpu.x86_rep_stosb_threshold=100000000` to count
//! those stores as the vector loop's instructions instead.
//!
//! Filters: `kf`, `kf_nis` (the same steps, the caller
//! reading only the report's NIS in place instead of moving the report),
//! `kf_diag` (diagonal `R`: sequential scalar updates), `kf_diag_batch` (the
//! same `R` through the batch update; the two, and their `_f32` forms, also
//! take sizes `N`x`M`: 2x1, 2x2, 3x2, 3x3, 4x1, 4x2, 4x3, 4x4, 6x2, 6x3,
//! 6x4, 6x6, 9x2, 9x3, 9x4, 9x6, 15x3, 15x4, 15x6, 21x3, 21x6),
//! `kf_improved` (paper 000's
//! `ImprovedAdaptive`), `ukf`, `srukf`, `nalgebra`, `adskalman`,
//! `checked_by_hand` (the 2-state step written out by hand with
//! the library's checks, N = 2 only), `kf_f32`, `ukf_f32`, `srukf_f32` (f32
//! at N = 15 only), and
//! `kf_cycle`, `kf_improved_cycle`: the plain and the `ImprovedAdaptive` EKF
//! fed the simulated measurement cycle of the `adapters` benchmark (so the
//! adapter estimates, compresses and fades as it does there) instead of a
//! constant `z`; sizes 2, 4, 6, 9, 12, 15, 18, 24, 32 with `M = min(N, 6)`.
//! Without arguments (as `cargo bench` runs it) it prints this usage.

mod common;

use std::hint::black_box;

use common::adskalman_kf;
use common::checked_by_hand::CheckedByHand;
use common::hand::HandKf;
use common::model::Model;
use common::simulate::measurements;
use kestrel::form::{PredictForm, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Const, DimMin, SMatrix};
use kestrel::{Ekf, Filter, Real, SrUkf, Ukf};

fn model<T: Real, const N: usize, const M: usize>() -> Model<T, N, M> {
    Model::<f64, N, M>::of_step_benchmarks().to()
}

/// `steps` predict + update steps of `f`, handing `black_box` the whole
/// report (`WHOLE`, as the `step` benchmark does) or only its NIS (which the
/// compiler then reads where the update left it: no move of the report).
fn run<T, const N: usize, const M: usize, F, const WHOLE: bool>(
    mut f: Filter<T, N, F>,
    m: &Model<T, N, M>,
    r: SMatrix<T, M, M>,
    steps: usize,
) where
    T: Real,
    F: PredictForm<T, N, LinearProcess<T, N>> + UpdateForm<T, N, LinearMeasurement<T, N, M>, M>,
{
    let process = LinearProcess::new(m.phi, m.q);
    let measurement = LinearMeasurement::new(m.h, r);
    for _ in 0..steps {
        f.predict(&process, T::one()).expect("predict");
        let report = f.update(&measurement, black_box(&m.z)).expect("update");
        if WHOLE {
            black_box(report);
        } else {
            black_box(report.nis);
        }
    }
}

/// `steps` predict + update steps of the plain or the `ImprovedAdaptive`
/// EKF over the simulated measurement cycle.
fn cycle_steps<const N: usize, const M: usize>(improved: bool, steps: usize) -> bool {
    let m = Model::<f64, N, M>::of_step_benchmarks();
    let zs = measurements(&m);
    let process = LinearProcess::new(m.phi, m.q);
    let measurement = LinearMeasurement::new(m.h, m.r);
    fn go<A: kestrel::adapter::NoiseAdapter<f64, M>, const N: usize, const M: usize>(
        mut f: Filter<f64, N, kestrel::form::CovarianceForm<f64, N>, A>,
        process: &LinearProcess<f64, N>,
        measurement: &LinearMeasurement<f64, N, M>,
        zs: &[kestrel::nalgebra::SVector<f64, M>],
        steps: usize,
    ) {
        for z in zs.iter().cycle().take(steps) {
            f.predict(process, 1.0).expect("predict");
            black_box(f.update(measurement, black_box(z)).expect("update"));
        }
    }
    let f = Ekf::new(m.x0, m.p0).unwrap();
    if improved {
        let adapter = kestrel::adaptive::ImprovedAdaptive::as_published().unwrap();
        go(f.with_adapter(adapter), &process, &measurement, &zs, steps);
    } else {
        go(f, &process, &measurement, &zs, steps);
    }
    true
}

/// `steps` predict + update steps of the 2-state step written out by hand
/// with the library's checks ([`CheckedByHand`]).
fn checked_by_hand_steps(steps: usize) {
    let m = Model::<f64, 2, 2>::of_step_benchmarks();
    let mut f = CheckedByHand::new(m.x0, &m.p0).expect("initial covariance");
    for _ in 0..steps {
        f.predict(&m.phi, &m.q, 1.0).expect("predict");
        black_box(f.update(&m.h, &m.r, black_box(&m.z)).expect("update"));
    }
    black_box(f.x);
}

/// `steps` steps with the diagonal `R`, one component at a time (`kf_diag`)
/// or through the batch update (`kf_diag_batch`).
fn diag_steps<T: Real, const N: usize, const M: usize>(filter: &str, steps: usize) -> bool {
    let m = model::<T, N, M>();
    let mut f = Ekf::new(m.x0, m.p0).unwrap();
    match filter {
        "kf_diag" => f.form_mut().set_sequential(true),
        "kf_diag_batch" => f.form_mut().set_sequential(false),
        _ => return false,
    }
    run::<_, N, M, _, true>(f, &m, m.r_diag, steps);
    true
}

/// `steps` steps of `kf_diag` or `kf_diag_batch` (with `_f32`: in `f32`) at
/// a size `NxM`.
fn diag_steps_at(filter: &str, size: &str, steps: usize) -> bool {
    match filter.strip_suffix("_f32") {
        Some(filter) => diag_steps_of::<f32>(filter, size, steps),
        None => diag_steps_of::<f64>(filter, size, steps),
    }
}

fn diag_steps_of<T: Real>(filter: &str, size: &str, steps: usize) -> bool {
    match size {
        "2x1" => diag_steps::<T, 2, 1>(filter, steps),
        "2x2" => diag_steps::<T, 2, 2>(filter, steps),
        "3x2" => diag_steps::<T, 3, 2>(filter, steps),
        "3x3" => diag_steps::<T, 3, 3>(filter, steps),
        "4x1" => diag_steps::<T, 4, 1>(filter, steps),
        "4x2" => diag_steps::<T, 4, 2>(filter, steps),
        "4x3" => diag_steps::<T, 4, 3>(filter, steps),
        "4x4" => diag_steps::<T, 4, 4>(filter, steps),
        "6x2" => diag_steps::<T, 6, 2>(filter, steps),
        "6x3" => diag_steps::<T, 6, 3>(filter, steps),
        "6x4" => diag_steps::<T, 6, 4>(filter, steps),
        "6x6" => diag_steps::<T, 6, 6>(filter, steps),
        "9x2" => diag_steps::<T, 9, 2>(filter, steps),
        "9x3" => diag_steps::<T, 9, 3>(filter, steps),
        "9x4" => diag_steps::<T, 9, 4>(filter, steps),
        "9x6" => diag_steps::<T, 9, 6>(filter, steps),
        "15x3" => diag_steps::<T, 15, 3>(filter, steps),
        "15x4" => diag_steps::<T, 15, 4>(filter, steps),
        "15x6" => diag_steps::<T, 15, 6>(filter, steps),
        "21x3" => diag_steps::<T, 21, 3>(filter, steps),
        "21x6" => diag_steps::<T, 21, 6>(filter, steps),
        _ => false,
    }
}

fn steps_of<T: Real, const N: usize, const M: usize>(filter: &str, steps: usize) -> bool
where
    Const<M>: DimMin<Const<M>, Output = Const<M>>,
{
    let m = model::<T, N, M>();
    match filter {
        "kf" => run::<_, N, M, _, true>(Ekf::new(m.x0, m.p0).unwrap(), &m, m.r, steps),
        "kf_nis" => run::<_, N, M, _, false>(Ekf::new(m.x0, m.p0).unwrap(), &m, m.r, steps),
        "kf_diag" | "kf_diag_batch" => return diag_steps::<T, N, M>(filter, steps),
        "kf_improved" => {
            let adapter = kestrel::adaptive::ImprovedAdaptive::as_published().unwrap();
            let f = Ekf::new(m.x0, m.p0).unwrap().with_adapter(adapter);
            let process = LinearProcess::new(m.phi, m.q);
            let measurement = LinearMeasurement::new(m.h, m.r);
            let mut f = f;
            for _ in 0..steps {
                f.predict(&process, T::one()).expect("predict");
                black_box(f.update(&measurement, black_box(&m.z)).expect("update"));
            }
        }
        "ukf" => run::<_, N, M, _, true>(Ukf::new(m.x0, m.p0).unwrap(), &m, m.r, steps),
        "srukf" => run::<_, N, M, _, true>(SrUkf::new(m.x0, m.p0).unwrap(), &m, m.r, steps),
        "nalgebra" => {
            let mut f = HandKf::new(m.x0, m.p0);
            for _ in 0..steps {
                assert!(f.step(&m, &m.r, black_box(&m.z)));
            }
        }
        "adskalman" => {
            let (process, measurement) = adskalman_kf::models(&m, &m.r);
            let kf = ::adskalman::KalmanFilterNoControl::<T, Const<N>, Const<M>>::new(
                &process,
                &measurement,
            );
            let mut est = ::adskalman::StateAndCovariance::<T, Const<N>>::new(m.x0, m.p0);
            for _ in 0..steps {
                est = kf.step(&est, black_box(&m.z)).expect("adskalman step");
            }
            black_box(est);
        }
        _ => return false,
    }
    true
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [filter, size, steps] = args.as_slice()
        && let (Some(_), Ok(steps)) = (size.split_once('x'), steps.parse::<usize>())
    {
        if !diag_steps_at(filter, size, steps) {
            eprintln!("unknown filter or size: {filter} {size}");
            std::process::exit(2);
        }
        return;
    }
    let parsed = match args.as_slice() {
        [filter, n, steps] => n
            .parse::<usize>()
            .ok()
            .zip(steps.parse::<usize>().ok())
            .map(|(n, steps)| (filter.as_str(), n, steps)),
        _ => None,
    };
    let Some((filter, n, steps)) = parsed else {
        eprintln!("usage: step_count FILTER N STEPS (see the source's header)");
        return;
    };
    let cycle = match filter {
        "kf_cycle" => Some(false),
        "kf_improved_cycle" => Some(true),
        _ => None,
    };
    let known = match (cycle, filter.strip_suffix("_f32"), n) {
        (None, _, 2) if filter == "checked_by_hand" => {
            checked_by_hand_steps(steps);
            true
        }
        (Some(improved), _, 2) => cycle_steps::<2, 2>(improved, steps),
        (Some(improved), _, 4) => cycle_steps::<4, 4>(improved, steps),
        (Some(improved), _, 6) => cycle_steps::<6, 6>(improved, steps),
        (Some(improved), _, 9) => cycle_steps::<9, 6>(improved, steps),
        (Some(improved), _, 12) => cycle_steps::<12, 6>(improved, steps),
        (Some(improved), _, 15) => cycle_steps::<15, 6>(improved, steps),
        (Some(improved), _, 18) => cycle_steps::<18, 6>(improved, steps),
        (Some(improved), _, 24) => cycle_steps::<24, 6>(improved, steps),
        (Some(improved), _, 32) => cycle_steps::<32, 6>(improved, steps),
        (Some(_), _, _) => false,
        (None, Some(f), 15) => steps_of::<f32, 15, 6>(f, steps),
        (None, Some(_), _) => false,
        (None, None, 2) => steps_of::<f64, 2, 2>(filter, steps),
        (None, None, 4) => steps_of::<f64, 4, 4>(filter, steps),
        (None, None, 6) => steps_of::<f64, 6, 6>(filter, steps),
        (None, None, 9) => steps_of::<f64, 9, 6>(filter, steps),
        (None, None, 12) => steps_of::<f64, 12, 6>(filter, steps),
        (None, None, 15) => steps_of::<f64, 15, 6>(filter, steps),
        (None, None, 18) => steps_of::<f64, 18, 6>(filter, steps),
        (None, None, 24) => steps_of::<f64, 24, 6>(filter, steps),
        (None, None, 32) => steps_of::<f64, 32, 6>(filter, steps),
        _ => false,
    };
    if !known {
        eprintln!("unknown filter or size: {filter} {n}");
        std::process::exit(2);
    }
}
