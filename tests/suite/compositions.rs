//! Every shipped composition built and run, with each form: adapter tuples
//! of one to six members (homogeneous, mixed, nested, and of `()`), and the
//! `kestrel_models::Stack` configurations its documentation shows. Size
//! checks of such compositions are compile-time assertions evaluated only
//! when code is generated, so `cargo check` alone does not exercise them.

use crate::support;

use kestrel::adapter::NoiseAdapter;
use kestrel::form::{PredictForm, UpdateForm};
use kestrel::models::{
    ConstantAcceleration1d, ConstantVelocity1d, ConstantVelocity2d, GaussMarkov, RandomWalk,
    Selection, Stack,
};
use kestrel::nalgebra::{SMatrix, SVector, Vector1};
use kestrel::real::lit;
use kestrel::{Ekf, Filter, LinearizedProcess, Real, SrUkf, Ukf};
use support::cv::{assert_same_estimate, phi, plain, position, process, q, LinForm, ZS};
use support::{log, Action, Event, Log, Probe, ProbeReport};

// Adapter tuples ---------------------------------------------------------------

/// The member reports of a tuple of probes, in order.
trait Reports {
    fn list(&self) -> Vec<ProbeReport>;
}

macro_rules! reports {
    (@probe $i:tt) => { ProbeReport };
    ($($i:tt),+) => {
        impl Reports for ($(reports!(@probe $i),)+) {
            fn list(&self) -> Vec<ProbeReport> {
                vec![$(self.$i),+]
            }
        }
    };
}
reports!(0);
reports!(0, 1);
reports!(0, 1, 2);
reports!(0, 1, 2, 3);
reports!(0, 1, 2, 3, 4);
reports!(0, 1, 2, 3, 4, 5);

/// A probe that doubles `R`.
fn doubler(id: u32, log: &Log) -> Probe {
    Probe::new(id, log).with_actions(&[Action::ScaleNoise(2.0)])
}

/// Runs `adapter` (a tuple of `k` doublers with ids 1..=k sharing `log`)
/// for four steps: the estimate must equal a plain filter with `R·2ᵏ`, and
/// each step must log the members' predict, gain and update hooks in order.
fn doublers<F: LinForm, A>(name: &str, f: Filter<f64, 2, F>, adapter: A, k: usize, log: &Log)
where
    A: NoiseAdapter<f64, 1>,
    A::Report: Reports,
{
    let name = &format!("{name} ×{k}");
    let r = 0.75 * f64::from(1u32 << k);
    let mut adapted = f.clone().with_adapter(adapter);
    let mut reference = f;
    for (step, z) in ZS.into_iter().enumerate() {
        let z = Vector1::new(z);
        adapted.predict(&process(), 1.0).unwrap();
        reference.predict(&process(), 1.0).unwrap();
        let detail = adapted.update_detailed(&position(0.75), &z).unwrap();
        reference.update(&position(r), &z).unwrap();
        assert_same_estimate(name, &adapted, &reference);
        assert_eq!(detail.noise[0], r, "{name}");

        let base = step * 3 * k;
        let list = detail.report.adapters.list();
        assert_eq!(list.len(), k, "{name}");
        let ids = 1..=k as u32;
        for (i, (rep, id)) in list.iter().zip(ids.clone()).enumerate() {
            let want = ProbeReport {
                id,
                gain_at: Some(base + k + i),
                update_at: Some(base + 2 * k + i),
            };
            assert_eq!(*rep, want, "{name}");
        }
        let want: Vec<Event> = (ids.clone().map(Event::Predict))
            .chain(ids.clone().map(Event::Gain))
            .chain(ids.map(Event::Update))
            .collect();
        assert_eq!(log.borrow()[base..], want, "{name}");
    }
}

/// Runs [`doublers`] with the tuple of doublers numbered `ids`, each tuple
/// arity being its own type.
macro_rules! doubler_tuple {
    ($name:expr, $f:expr, $($id:literal),+) => {{
        let l = log();
        let t = ($(doubler($id, &l),)+);
        doublers($name, $f, t, [$($id),+].len(), &l);
    }};
}

fn tuples_of_one_to_six<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    doubler_tuple!(name, f.clone(), 1);
    doubler_tuple!(name, f.clone(), 1, 2);
    doubler_tuple!(name, f.clone(), 1, 2, 3);
    doubler_tuple!(name, f.clone(), 1, 2, 3, 4);
    doubler_tuple!(name, f.clone(), 1, 2, 3, 4, 5);
    doubler_tuple!(name, f, 1, 2, 3, 4, 5, 6);
}

#[test]
fn adapter_tuples_of_one_to_six() {
    each_form!(tuples_of_one_to_six);
}

/// Six members of different kinds, one of them a nested pair and two of
/// them `()`: R doubled, a predict fade of 2 (this member asks for the
/// split), a gain fade of 1.5 and the innovation halved (the nested pair),
/// R tripled. The result must equal a plain filter with
/// `P⁻ = 3 Φ P Φᵀ + Q`, `R = 6·¾` and `z' = ẑ + ν/2`.
fn mixed_six<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    let l = log();
    let adapter = (
        doubler(1, &l),
        (),
        Probe::<true>::new(3, &l).with_predict_fade(2.0),
        (
            Probe::<false>::new(4, &l).with_actions(&[Action::Fade(1.5)]),
            Probe::<false>::new(5, &l).with_actions(&[Action::ScaleInnovation(0.5)]),
        ),
        Probe::<false>::new(6, &l).with_actions(&[Action::ScaleNoise(3.0)]),
        (),
    );
    let mut f = f.with_adapter(adapter);
    for z in ZS {
        let (x, p) = (*f.state(), f.covariance());
        let prior = phi() * p * phi().transpose() * 3.0 + q();
        f.predict(&process(), 1.0).unwrap();
        let mut reference = plain(&f, phi() * x, prior);
        let z_hat = reference.state()[0];
        let detail = f
            .update_detailed(&position(0.75), &Vector1::new(z))
            .unwrap();
        let moved = Vector1::new(z_hat + 0.5 * (z - z_hat));
        reference.update(&position(4.5), &moved).unwrap();
        assert_same_estimate(name, &f, &reference);
        assert!((detail.report.fade - 3.0).abs() < 1e-15, "{name}");
        assert!((detail.noise[0] - 4.5).abs() < 1e-15, "{name}");
        let ids: Vec<u32> = [
            detail.report.adapters.0.id,
            detail.report.adapters.2.id,
            detail.report.adapters.3 .0.id,
            detail.report.adapters.3 .1.id,
            detail.report.adapters.4.id,
        ]
        .to_vec();
        assert_eq!(ids, [1, 3, 4, 5, 6], "{name}");
    }
}

#[test]
fn mixed_and_nested_tuple_of_six() {
    each_form!(mixed_six);
}

/// Tuples of `()` are the identity: the covariance form still uses
/// sequential updates and every form gives the plain result.
fn identities<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    let sequential = name == "ekf";
    let mut reference = f.clone();
    let mut one = f.clone().with_adapter(((),));
    let mut six = f.clone().with_adapter(((), (), (), (), (), ()));
    let mut nested = f.with_adapter((((), ()), ((),)));
    for z in ZS {
        let z = Vector1::new(z);
        reference.predict(&process(), 1.0).unwrap();
        reference.update(&position(0.75), &z).unwrap();
        one.predict(&process(), 1.0).unwrap();
        let r1 = one.update(&position(0.75), &z).unwrap();
        six.predict(&process(), 1.0).unwrap();
        let r6 = six.update(&position(0.75), &z).unwrap();
        nested.predict(&process(), 1.0).unwrap();
        let rn = nested.update(&position(0.75), &z).unwrap();
        for (label, seq) in [
            ("1", r1.sequential),
            ("6", r6.sequential),
            ("n", rn.sequential),
        ] {
            assert_eq!(seq, sequential, "{name} {label}");
        }
        assert_same_estimate(name, &one, &reference);
        assert_same_estimate(name, &six, &reference);
        assert_same_estimate(name, &nested, &reference);
    }
}

#[test]
fn identity_tuples() {
    each_form!(identities);
}

// Stack configurations -----------------------------------------------------------

/// Panics unless `a` is within `tol · (1 + max|b|)` of `b`.
#[track_caller]
fn near<T: Real, const R: usize, const C: usize>(
    a: &SMatrix<T, R, C>,
    b: &SMatrix<T, R, C>,
    tol: T,
    what: &str,
) {
    let err = (a - b).amax();
    assert!(err <= tol * (T::one() + b.amax()), "{what}: {a} vs {b}");
}

/// Runs a filter on `stack = [first; second]` for ten steps measuring state
/// 0 (in the first block) from a diagonal `P₀`. The blocks never correlate,
/// so the first block must follow a covariance-form filter on `first` alone
/// with the same measurements, the second a predict-only filter on
/// `second`, and the cross-covariance must stay zero.
fn blockwise<T, F, S, A, B, const N: usize, const NA: usize, const NB: usize>(
    name: &str,
    make: impl Fn(SVector<T, N>, SMatrix<T, N, N>) -> Filter<T, N, F>,
    stack: &S,
    first: &A,
    second: &B,
    tol: T,
) where
    T: Real,
    F: PredictForm<T, N, S> + UpdateForm<T, N, Selection<T, N, 1>, 1>,
    A: LinearizedProcess<T, NA>,
    B: LinearizedProcess<T, NB>,
{
    let x0 = SVector::<T, N>::from_fn(|i, _| lit(0.5 * i as f64 - 1.0));
    let p0 = SMatrix::<T, N, N>::from_fn(|i, j| {
        if i == j {
            lit(1.0 + 0.25 * i as f64)
        } else {
            T::zero()
        }
    });
    let r = SMatrix::<T, 1, 1>::new(lit(0.5));
    let sensor = Selection::<T, N, 1>::new([0], r).unwrap();
    let part_sensor = Selection::<T, NA, 1>::new([0], r).unwrap();
    let mut f = make(x0, p0);
    let mut fa = Ekf::new(
        x0.fixed_rows::<NA>(0).into_owned(),
        p0.fixed_view::<NA, NA>(0, 0).into_owned(),
    )
    .unwrap();
    let mut fb = Ekf::new(
        x0.fixed_rows::<NB>(NA).into_owned(),
        p0.fixed_view::<NB, NB>(NA, NA).into_owned(),
    )
    .unwrap();
    let dt = lit::<T>(0.5);
    for k in 1..=10 {
        let z = Vector1::new(lit::<T>(0.7 * k as f64 - 1.0));
        f.predict(stack, dt).unwrap();
        fa.predict(first, dt).unwrap();
        fb.predict(second, dt).unwrap();
        f.update(&sensor, &z).unwrap();
        fa.update(&part_sensor, &z).unwrap();

        let p = f.covariance();
        near(
            &f.state().fixed_rows::<NA>(0).into_owned(),
            fa.state(),
            tol,
            name,
        );
        near(
            &f.state().fixed_rows::<NB>(NA).into_owned(),
            fb.state(),
            tol,
            name,
        );
        near(
            &p.fixed_view::<NA, NA>(0, 0).into_owned(),
            &fa.covariance(),
            tol,
            name,
        );
        near(
            &p.fixed_view::<NB, NB>(NA, NA).into_owned(),
            &fb.covariance(),
            tol,
            name,
        );
        let cross = p.fixed_view::<NA, NB>(0, NA).into_owned();
        near(&cross, &SMatrix::zeros(), tol, name);
    }
}

/// Runs `blockwise` with each form, for sizes `[$n; $na, $nb]` (a stack
/// implements its trait for every size; the wrong one fails to build).
macro_rules! stack_all_forms {
    ($name:expr, [$n:literal; $na:literal, $nb:literal], $stack:expr, $first:expr, $second:expr, $tol:expr) => {{
        let (stack, first, second) = ($stack, $first, $second);
        blockwise::<_, _, _, _, _, $n, $na, $nb>(
            concat!($name, " ekf"),
            |x, p| Ekf::new(x, p).unwrap(),
            &stack,
            &first,
            &second,
            $tol,
        );
        blockwise::<_, _, _, _, _, $n, $na, $nb>(
            concat!($name, " ukf"),
            |x, p| Ukf::new(x, p).unwrap(),
            &stack,
            &first,
            &second,
            $tol,
        );
        blockwise::<_, _, _, _, _, $n, $na, $nb>(
            concat!($name, " sr-ukf"),
            |x, p| SrUkf::new(x, p).unwrap(),
            &stack,
            &first,
            &second,
            $tol,
        );
    }};
}

fn cv1(q: f64) -> ConstantVelocity1d<f64> {
    ConstantVelocity1d::new(q).unwrap()
}

/// `Stack::new` with inferred sizes: constant velocity and a clock bias.
#[test]
fn stack_of_two() {
    let bias = RandomWalk::<f64, 1>::uniform(0.5).unwrap();
    stack_all_forms!("cv+rw", [3; 2, 1], Stack::new(cv1(0.1), bias), cv1(0.1), bias, 1e-10);
}

/// The documentation's example: position/velocity, a random-walk bias and
/// a Gauss-Markov drift, `Stack::<_, _, 3, 1>::new(Stack::new(cv, bias), drift)`.
#[test]
fn documented_stack_of_three() {
    let bias = RandomWalk::new(Vector1::new(4.0)).unwrap();
    let drift = GaussMarkov::<f64, 1>::uniform(0.5 / core::f64::consts::LN_2, 1.0).unwrap();
    let inner = Stack::new(cv1(0.1), bias);
    stack_all_forms!(
        "(cv+rw)+gm",
        [4; 3, 1],
        Stack::<_, _, 3, 1>::new(inner, drift),
        inner,
        drift,
        1e-10
    );
}

/// `Stack<Stack<A, B, 2, 2>, C, 4, 1>`, a 5-state model.
#[test]
fn nested_two_two_one() {
    let gm = GaussMarkov::<f64, 2>::uniform(2.0, 0.5).unwrap();
    let inner = Stack::<_, _, 2, 2>::new(cv1(1.0), gm);
    let rw = RandomWalk::<f64, 1>::uniform(0.1).unwrap();
    stack_all_forms!(
        "(cv+gm2)+rw",
        [5; 4, 1],
        Stack::<_, _, 4, 1>::new(inner, rw),
        inner,
        rw,
        1e-10
    );
}

/// Two-axis constant velocity, a 2-state Gauss-Markov and a random walk:
/// seven states.
#[test]
fn nested_seven_states() {
    let cv = ConstantVelocity2d::new(2.0).unwrap();
    let gm = GaussMarkov::new(
        kestrel::nalgebra::Vector2::new(1.0, 2.0),
        kestrel::nalgebra::Vector2::new(0.5, 1.5),
    )
    .unwrap();
    let rw = RandomWalk::new(Vector1::new(3.0)).unwrap();
    let inner = Stack::new(cv, gm);
    stack_all_forms!(
        "(cv2d+gm2)+rw",
        [7; 6, 1],
        Stack::<_, _, 6, 1>::new(inner, rw),
        inner,
        rw,
        1e-10
    );
}

/// Single precision: constant acceleration and a random walk.
#[test]
fn stack_in_f32() {
    let ca = ConstantAcceleration1d::new(1.0_f32).unwrap();
    let rw = RandomWalk::<f32, 1>::uniform(2.0).unwrap();
    stack_all_forms!("ca+rw f32", [4; 3, 1], Stack::new(ca, rw), ca, rw, 1e-4_f32);
}
