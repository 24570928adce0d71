//! Paired timing of the adapter path's parts at 15 states: where the time
//! paper 000's `ImprovedAdaptive` adds over the plain EKF goes.
//!
//! Six EKFs on the model and measurement cycle of `adapter_step/15` (the
//! dense model of the step benchmarks, `M = 6`, 1024 simulated epochs) take
//! turns within one process, as `common::rounds` describes:
//!
//! - `plain`: no adapter;
//! - `pass_through`: an adapter that changes nothing but takes the adapter
//!   way ([`PassThrough`](common::parts::PassThrough));
//! - `fixed_noise`: puts a fixed `R̂` and its factor in place every epoch
//!   ([`FixedNoise`](common::parts::FixedNoise)), as Sage–Husa does;
//! - `sage_husa`: `SageHusa::as_published()` alone;
//! - `tests`: `(OutlierCompression::as_published(), DivergenceFading::new(3, 100))`,
//!   the composition's tests without `R̂`;
//! - `improved`: `ImprovedAdaptive::as_published()`, the tests around Sage–Husa.
//!
//! Each ratio is taken within a round, so a part's cost is the ratio of two
//! neighbours: the adapter way (`pass_through ÷ plain`), a new `R`
//! (`fixed_noise ÷ pass_through`), the estimate of `R̂`
//! (`sage_husa ÷ fixed_noise`) and the tests on top (`improved ÷
//! sage_husa`). Every filter runs the cycle once before it is timed (every
//! update accepted on the batch path, the adapter acting).
//!
//! ```sh
//! cargo bench --bench adapter_parts                 # 1000 rounds
//! cargo bench --bench adapter_parts -- --rounds 3000
//! ```

#[allow(dead_code)]
mod common;

use std::hint::black_box;

use common::model::Model;
use common::parts::{FixedNoise, PassThrough};
use common::rounds::{
    print_medians, probe_levels, rounds_or_exit, spread, take_turns, time_chunk, Probe, CONTENDED,
};
use common::simulate::{cycled, measurements, CYCLE};
use kestrel::adaptive::{DivergenceFading, ImprovedAdaptive, OutlierCompression, SageHusa};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::Ekf;

const N: usize = 15;
const M: usize = 6;

/// Rounds unless `--rounds` says otherwise (about nine seconds).
const DEFAULT_ROUNDS: usize = 1000;

/// The timed workloads, in the order of the printed columns; the probe is
/// the last.
const WORKLOADS: [&str; 7] = [
    "plain",
    "pass_through",
    "fixed_noise",
    "sage_husa",
    "tests",
    "improved",
    "probe",
];

/// The probe's index in [`WORKLOADS`].
const PROBE: usize = 6;

/// The printed ratios: name, numerator, denominator.
const RATIOS: [(&str, usize, usize); 7] = [
    ("the adapter way: `pass_through` ÷ `plain`", 1, 0),
    ("a new `R`: `fixed_noise` ÷ `pass_through`", 2, 1),
    ("the estimate of `R̂`: `sage_husa` ÷ `fixed_noise`", 3, 2),
    ("the tests on top: `improved` ÷ `sage_husa`", 5, 3),
    ("the tests alone: `tests` ÷ `pass_through`", 4, 1),
    ("`sage_husa` ÷ `plain`", 3, 0),
    ("`improved` ÷ `plain` (goal ≤ 1.2)", 5, 0),
];

/// Nanoseconds a step (a probe call for the probe), per workload and round.
fn measure(rounds: usize) -> [Vec<f64>; WORKLOADS.len()] {
    let m = Model::<f64, N, M>::of_step_benchmarks();
    let zs = measurements(&m);
    let ekf = || Ekf::new(m.x0, m.p0).unwrap();
    let tests = || {
        (
            OutlierCompression::<f64, M>::as_published().unwrap(),
            DivergenceFading::new(3.0, 100.0).unwrap(),
        )
    };
    let mut plain = cycled("plain", ekf(), &m, &zs, |_| true);
    let mut pass = cycled(
        "pass_through",
        ekf().with_adapter(PassThrough),
        &m,
        &zs,
        |_| true,
    );
    let fixed = FixedNoise::scaled(&m.r);
    let mut fixed = cycled("fixed_noise", ekf().with_adapter(fixed), &m, &zs, |r| {
        r.adapted_nis != r.nis
    });
    let sage_husa = SageHusa::<f64, M>::as_published().unwrap();
    let mut sage_husa = cycled("sage_husa", ekf().with_adapter(sage_husa), &m, &zs, |r| {
        r.adapters.estimated
    });
    let mut tests = cycled("tests", ekf().with_adapter(tests()), &m, &zs, |r| {
        r.adapters.0.compressed || r.adapters.1.diverged
    });
    let improved = ImprovedAdaptive::as_published().unwrap();
    let mut improved = cycled("improved", ekf().with_adapter(improved), &m, &zs, |r| {
        r.adapters.sage_husa.estimated && r.adapters.tests.0.compressed
    });

    let process = LinearProcess::new(m.phi, m.q);
    let sensor = LinearMeasurement::new(m.h, m.r);
    // One closure per workload, each stepping through the cycle.
    macro_rules! step {
        ($f:ident) => {{
            let mut k = 0;
            let (process, sensor, zs) = (&process, &sensor, &zs);
            move || {
                $f.predict(process, 1.0).expect("predict");
                black_box($f.update(sensor, black_box(&zs[k])).expect("update"));
                k = (k + 1) % CYCLE;
            }
        }};
    }
    let mut plain_step = step!(plain);
    let mut pass_step = step!(pass);
    let mut fixed_step = step!(fixed);
    let mut sage_husa_step = step!(sage_husa);
    let mut tests_step = step!(tests);
    let mut improved_step = step!(improved);
    let mut probe = Probe::new();
    let mut probe_call = || probe.call();

    take_turns(
        rounds,
        [
            &mut |n| time_chunk(&mut plain_step, n),
            &mut |n| time_chunk(&mut pass_step, n),
            &mut |n| time_chunk(&mut fixed_step, n),
            &mut |n| time_chunk(&mut sage_husa_step, n),
            &mut |n| time_chunk(&mut tests_step, n),
            &mut |n| time_chunk(&mut improved_step, n),
            &mut |n| time_chunk(&mut probe_call, n),
        ],
    )
}

fn main() {
    let rounds = rounds_or_exit("adapter_parts", DEFAULT_ROUNDS);
    let times = measure(rounds);
    let probe = &times[PROBE];
    let fastest = probe.iter().copied().fold(f64::INFINITY, f64::min);
    let uncontended: Vec<usize> = (0..rounds)
        .filter(|&i| probe[i] <= CONTENDED * fastest)
        .collect();

    println!("{N} states, M = {M}, the cycle of `adapter_step`: ns a step (the probe: a call), median over rounds (10th–90th percentile); {rounds} rounds");
    println!();
    print_medians(&WORKLOADS, &times);
    println!();
    println!("Each ratio within a round: median over rounds (10th–90th percentile)");
    println!(
        "uncontended: the probe took at most {CONTENDED} × its fastest round ({} of {rounds} rounds); probe: its 10th–90th percentile ÷ its fastest, {}",
        uncontended.len(),
        probe_levels(probe, fastest)
    );
    println!();
    println!("| part | all rounds | uncontended |");
    println!("|---|---|---|");
    for (name, num, den) in RATIOS {
        let ratio = |i: usize| times[num][i] / times[den][i];
        let all: Vec<f64> = (0..rounds).map(ratio).collect();
        let quiet: Vec<f64> = uncontended.iter().map(|&i| ratio(i)).collect();
        println!("| {name} | {} | {} |", spread(&all, 3), spread(&quiet, 3));
    }
}
