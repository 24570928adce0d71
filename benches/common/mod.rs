//! Shared pieces of the step benchmarks: a deterministic random linear model
//! and the two baselines (a hand-written nalgebra Kalman filter and the
//! `adskalman` crate).

pub mod adskalman_kf;
// Only the benchmarks that look at the 2-state step's least cost use it.
#[allow(dead_code)]
pub mod checked_by_hand;
pub mod hand;
pub mod model;
// Only the benchmarks that take the adapter path apart use them.
#[allow(dead_code)]
pub mod parts;
// Only the benchmarks that compare estimates check against the reference.
#[allow(dead_code)]
pub mod reference;
pub mod rng;
// Only the benchmarks that time workloads in turns use it.
#[allow(dead_code)]
pub mod rounds;
// Only the benchmarks with adapters simulate measurements.
#[allow(dead_code)]
pub mod simulate;
