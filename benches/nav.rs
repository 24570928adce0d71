//! Cost of the navigation building blocks.
//!
//! - `nav_step/mechanisation`: one strapdown step (200 Hz increments of a
//!   manoeuvring vehicle, cycled).
//! - `nav_step/error_model`: building the 15-state `Φ` and `Q_d` for one
//!   propagation interval (continuous `F`, second-order `Φ`, trapezoidal
//!   `Q_d`); `nav_step/error_model_18` the same for 18 states.
//! - `nav_step/gnss_update_15`: one GNSS position + velocity update of the
//!   loosely coupled engine (measurement, 15-state update, feedback).
//! - `nav_run/ins_gnss_1h`: a full 1 h INS/GNSS run at 200 Hz (sample size
//!   10; the real-time factor is printed first). Set-up in `nav_aiding`.
//!
//! `cargo bench --bench nav -- --warm-up-time 1 --measurement-time 3`
//! (append a filter such as `mechanisation` for one benchmark). Shared set-up
//! lives in `nav_common`; add new groups as functions registered in
//! `criterion_group!` below.

mod nav_aiding;
mod nav_common;

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use kestrel::nav::error_model::{Ins15Model, Ins18Model};
use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::Strapdown;

use nav_common::{earth, increments, spec, start_state};

fn mechanisation(c: &mut Criterion) {
    let imu = increments(4096);
    let mut ins = Strapdown::new(earth(), start_state());
    let mut k = 0;
    c.bench_function("nav_step/mechanisation", |b| {
        b.iter(|| {
            ins.step(black_box(&imu[k & 4095]));
            k += 1;
        })
    });
    assert!(ins.state().pos.lat.is_finite());
}

fn error_model(c: &mut Criterion) {
    let (earth, spec, nav) = (earth(), spec(), start_state());
    let f = Vector3::new(0.3, 1.9, -9.79);
    c.bench_function("nav_step/error_model", |b| {
        b.iter(|| {
            let m = Ins15Model::new(&earth, &spec, black_box(&nav), black_box(&f), 0.1);
            black_box((m.phi()[(3, 1)], m.qd()[(0, 0)]))
        })
    });
    c.bench_function("nav_step/error_model_18", |b| {
        b.iter(|| {
            let m = Ins18Model::new(&earth, &spec, black_box(&nav), black_box(&f), 0.1);
            black_box((m.phi()[(3, 1)], m.qd()[(0, 0)]))
        })
    });
}

criterion_group!(benches, mechanisation, error_model);
criterion_group!(aiding, nav_aiding::gnss_update, nav_aiding::ins_gnss_hour);
criterion_main!(benches, aiding);
