//! A fixed number of predict + update steps of the EKF with one noise
//! adapter (or paper 000's compositions) over the simulated measurement
//! cycle of the `adapters` benchmark, with that benchmark's parameters, for
//! instruction counts that do not depend on the machine's load:
//!
//! ```sh
//! cargo bench --bench adapter_count --no-run          # prints the binary's path
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null BINARY sage_husa 15 2000
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null BINARY sage_husa 15 0
//! ```
//!
//! The difference of the two totals ("Collected") divided by 2000 is the
//! count per step; the overhead of an adapter is its count over `plain`'s in
//! the same binary. Adapters: `plain` (none), `sage_husa`,
//! `divergence_fading` (`γ = 3`), `strong_tracking` (`ρ = 0.95`, `β = 1`),
//! `outlier_compression` (`α = 0.05`), `improved_adaptive`
//! (`ImprovedAdaptive::as_published`), `sage_husa_fading`
//! (`SageHusaFading::as_published`), `huber_inflation`, `chi_square_gate`
//! (`α = 0.01`), `windowed_noise` (window 10); not `fuzzy_gain`, whose inputs
//! the caller sets every epoch. Also the two measuring adapters of
//! `adapter_parts` (`common::parts`): `pass_through` (the adapter way, no
//! change) and `fixed_noise` (a fixed `R̂ = 1.25 R` put in place every
//! epoch). Sizes 6, 15 and 18 with `M = 6`.
//!
//! `step_count` counts the plain and the `ImprovedAdaptive` EKF on the same
//! cycle (`kf_cycle`, `kf_improved_cycle`) as it has since the adapter work
//! began; this is a binary of its own so that those counts stay comparable
//! from round to round. The same code can count differently in the two
//! binaries by up to a few hundred instructions at 15 states (the compiler
//! inlines and places it differently when a binary holds more adapters), so
//! compare an adapter with `plain` from the same binary.
//!
//! Without arguments, or with `--bench` alone (as `cargo bench` runs it), it
//! prints its usage; with arguments it cannot read, a message saying which
//! (or the usage, for the wrong number of them) and exit code 2.

#[allow(dead_code)]
mod common;

use common::parts::{FixedNoise, PassThrough};
use common::simulate::cycle_steps;
use kestrel::adaptive::{
    ChiSquareGate, DivergenceFading, HuberInflation, ImprovedAdaptive, OutlierCompression,
    SageHusa, SageHusaFading, StrongTracking, WindowedNoise,
};

/// `steps` steps with the adapter named `name` at `N` states; `false` for a
/// name it does not know.
fn steps_of<const N: usize>(name: &str, steps: usize) -> bool {
    const M: usize = 6;
    match name {
        "plain" => cycle_steps::<_, N, M>((), steps),
        "pass_through" => cycle_steps::<_, N, M>(PassThrough, steps),
        "fixed_noise" => {
            let r = common::model::Model::<f64, N, M>::of_step_benchmarks().r;
            cycle_steps::<_, N, M>(FixedNoise::scaled(&r), steps)
        }
        "sage_husa" => cycle_steps::<_, N, M>(SageHusa::as_published().unwrap(), steps),
        "divergence_fading" => {
            cycle_steps::<_, N, M>(DivergenceFading::new(3.0, 100.0).unwrap(), steps)
        }
        "strong_tracking" => cycle_steps::<_, N, M>(StrongTracking::new(0.95, 1.0).unwrap(), steps),
        "outlier_compression" => {
            cycle_steps::<_, N, M>(OutlierCompression::as_published().unwrap(), steps)
        }
        "improved_adaptive" => {
            cycle_steps::<_, N, M>(ImprovedAdaptive::as_published().unwrap(), steps)
        }
        "sage_husa_fading" => {
            cycle_steps::<_, N, M>(SageHusaFading::as_published().unwrap(), steps)
        }
        "huber_inflation" => cycle_steps::<_, N, M>(HuberInflation::as_published().unwrap(), steps),
        "chi_square_gate" => cycle_steps::<_, N, M>(ChiSquareGate::new(0.01).unwrap(), steps),
        "windowed_noise" => {
            cycle_steps::<_, N, M>(WindowedNoise::<f64, M, 10>::new(1e-3).unwrap(), steps)
        }
        _ => return false,
    }
    true
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [name, n, steps] = args.as_slice() else {
        eprintln!("usage: adapter_count ADAPTER N STEPS (see the source's header)");
        // `cargo bench` runs every benchmark with `--bench` and nothing else:
        // that is not an error; other argument lists are.
        if !(args.is_empty() || args == ["--bench"]) {
            std::process::exit(2);
        }
        return;
    };
    let fail = |message: String| -> ! {
        eprintln!("adapter_count: {message}");
        std::process::exit(2);
    };
    let Ok(steps) = steps.parse::<usize>() else {
        fail(format!("STEPS must be a whole number, got `{steps}`"));
    };
    let known = match n.as_str() {
        "6" => steps_of::<6>(name, steps),
        "15" => steps_of::<15>(name, steps),
        "18" => steps_of::<18>(name, steps),
        _ => fail(format!("N must be 6, 15 or 18, got `{n}`")),
    };
    if !known {
        fail(format!(
            "unknown adapter `{name}` (see the source's header)"
        ));
    }
}
