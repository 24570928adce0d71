//! `update` and `update_detailed` are one update returning two outcomes:
//! the report `update` returns is the detail's report bit for bit, the
//! filters after either are bit for bit the same, and a failing update
//! fails with the same error. Checked for every form, without adapter (the
//! covariance form's sequential and batch paths), with the paper-000
//! composition, and through a χ² gate that rejects outliers, the last also
//! through `update_with` / `update_detailed_with`.

use crate::common;

use std::fmt::Debug;

use kestrel::adapter::{NoiseAdapter, PriorAdapter};
use kestrel::adaptive::{ChiSquareGate, ImprovedAdaptive};
use kestrel::form::{PredictForm, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Matrix2, SVector, Vector2, Vector4};
use kestrel::{Ekf, Filter, FilterError, SrUkf, Ukf, UpdateDetail, UpdateReport};

const STEPS: usize = 60;

/// Position measurements of a constant-velocity track, every seventh one
/// 40 m off (about 25 σ of a 2.5 m² `R`), and one NaN at the end.
fn measurements() -> Vec<SVector<f64, 2>> {
    let mut rng = common::rng(0x5e7a_11ed);
    let mut zs: Vec<_> = (0..STEPS)
        .map(|k| {
            let t = 0.1 * k as f64;
            let noise = common::gaussian::<2, 1>(&mut rng) * 1.5;
            let outlier = if k % 7 == 6 { 40.0 } else { 0.0 };
            Vector2::new(1.0 + t, 3.0 - 2.0 * t) + noise + Vector2::repeat(outlier)
        })
        .collect();
    zs.push(Vector2::new(f64::NAN, 0.0));
    zs
}

fn models(r: Matrix2<f64>) -> (LinearProcess<f64, 4>, LinearMeasurement<f64, 4, 2>) {
    common::constant_velocity(r)
}

fn bits<const R: usize, const C: usize>(m: &kestrel::nalgebra::SMatrix<f64, R, C>) -> Vec<u64> {
    m.iter().map(|v| v.to_bits()).collect()
}

/// What a lockstep run saw.
#[derive(Debug, Default)]
struct Seen {
    accepted: usize,
    rejected: usize,
    sequential: usize,
    failed: usize,
}

type Sensor = LinearMeasurement<f64, 4, 2>;

/// Runs `filter` and a clone in lockstep, one through `lean` (`update` or
/// `update_with`), the other through `detailed` (`update_detailed` or
/// `update_detailed_with`), asserting the two agree bit for bit at every
/// step.
fn lockstep<F, A, R>(
    what: &str,
    filter: Filter<f64, 4, F, A>,
    r: Matrix2<f64>,
    mut lean: impl FnMut(&mut Filter<f64, 4, F, A>, &Sensor, &SVector<f64, 2>) -> Lean<R>,
    mut detailed: impl FnMut(&mut Filter<f64, 4, F, A>, &Sensor, &SVector<f64, 2>) -> Detailed<R>,
) -> Seen
where
    F: PredictForm<f64, 4, LinearProcess<f64, 4>> + Clone,
    A: PriorAdapter<f64> + Clone,
    R: PartialEq + Debug,
{
    let (process, sensor) = models(r);
    let mut a = filter;
    let mut b = a.clone();
    let mut seen = Seen::default();
    for (k, z) in measurements().iter().enumerate() {
        let at = format!("{what}, step {k}");
        a.predict(&process, 0.1).expect("predict");
        b.predict(&process, 0.1).expect("predict");
        match (lean(&mut a, &sensor, z), detailed(&mut b, &sensor, z)) {
            (Ok(report), Ok(detail)) => {
                assert_eq!(report, detail.report, "{at}");
                // `==` says nothing of NaN or the sign of zero: the bits.
                assert_eq!(report.nis.to_bits(), detail.report.nis.to_bits(), "{at}");
                seen.accepted += usize::from(!report.rejected);
                seen.rejected += usize::from(report.rejected);
                seen.sequential += usize::from(report.sequential);
            }
            (Err(x), Err(y)) => {
                assert_eq!(x, y, "{at}");
                seen.failed += 1;
            }
            (x, y) => panic!("{at}: update {x:?}, update_detailed {y:?}"),
        }
        assert_eq!(bits(a.state()), bits(b.state()), "{at}: state");
        assert_eq!(
            bits(&a.covariance()),
            bits(&b.covariance()),
            "{at}: covariance"
        );
    }
    seen
}

type Lean<R> = Result<UpdateReport<f64, 2, R>, FilterError>;
type Detailed<R> = Result<UpdateDetail<f64, 2, R>, FilterError>;

/// [`lockstep`] through the filter's own adapter.
fn own<F, A>(what: &str, filter: Filter<f64, 4, F, A>, r: Matrix2<f64>) -> Seen
where
    F: PredictForm<f64, 4, LinearProcess<f64, 4>> + UpdateForm<f64, 4, Sensor, 2> + Clone,
    A: NoiseAdapter<f64, 2> + Clone,
    A::Report: PartialEq + Debug,
{
    lockstep(
        what,
        filter,
        r,
        |f, s, z| f.update(s, z),
        |f, s, z| f.update_detailed(s, z),
    )
}

fn x0() -> Vector4<f64> {
    Vector4::new(1.0, 3.0, 1.0, -2.0)
}

fn p0() -> kestrel::nalgebra::Matrix4<f64> {
    kestrel::nalgebra::Matrix4::identity() * 4.0
}

const DIAGONAL: Matrix2<f64> = Matrix2::new(2.5, 0.0, 0.0, 2.5);
const CORRELATED: Matrix2<f64> = Matrix2::new(2.5, 0.8, 0.8, 2.0);

#[test]
fn without_adapter_every_form_and_path() {
    let ekf = || Ekf::<f64, 4>::new(x0(), p0()).expect("finite");
    let mut sequential = ekf();
    sequential.form_mut().set_sequential(true);
    let seen = own("EKF sequential", sequential, DIAGONAL);
    assert_eq!(
        (seen.accepted, seen.sequential, seen.failed),
        (STEPS, STEPS, 1)
    );
    let seen = own("EKF batch", ekf(), CORRELATED);
    assert_eq!((seen.accepted, seen.sequential, seen.failed), (STEPS, 0, 1));
    let ukf = Ukf::<f64, 4>::new(x0(), p0()).expect("finite");
    let seen = own("UKF", ukf, CORRELATED);
    assert_eq!((seen.accepted, seen.failed), (STEPS, 1));
    let sr = SrUkf::<f64, 4>::new(x0(), p0()).expect("finite");
    let seen = own("SR-UKF", sr, CORRELATED);
    assert_eq!((seen.accepted, seen.failed), (STEPS, 1));
}

#[test]
fn with_the_paper_000_composition() {
    let adapter = || ImprovedAdaptive::<f64, 2>::as_published().expect("paper parameters");
    let ekf = Ekf::<f64, 4>::new(x0(), p0()).expect("finite");
    let ukf = Ukf::<f64, 4>::new(x0(), p0()).expect("finite");
    let sr = SrUkf::<f64, 4>::new(x0(), p0()).expect("finite");
    for (what, seen) in [
        ("EKF", own("EKF", ekf.with_adapter(adapter()), CORRELATED)),
        ("UKF", own("UKF", ukf.with_adapter(adapter()), CORRELATED)),
        (
            "SR-UKF",
            own("SR-UKF", sr.with_adapter(adapter()), CORRELATED),
        ),
    ] {
        assert_eq!((seen.accepted, seen.failed), (STEPS, 1), "{what}");
    }
}

/// [`lockstep`] of a filter without adapter of its own, both copies
/// updating through a clone of `gate` (`update_with`,
/// `update_detailed_with`).
fn with_gate<F>(what: &str, filter: Filter<f64, 4, F>, gate: ChiSquareGate<f64, 2>) -> Seen
where
    F: PredictForm<f64, 4, LinearProcess<f64, 4>> + UpdateForm<f64, 4, Sensor, 2> + Clone,
{
    let (mut a, mut b) = (gate, gate);
    lockstep(
        what,
        filter,
        CORRELATED,
        |f, s, z| f.update_with(s, z, &mut a),
        |f, s, z| f.update_detailed_with(s, z, &mut b),
    )
}

#[test]
fn through_a_rejecting_gate_with_the_with_variants() {
    let gate = ChiSquareGate::<f64, 2>::new(0.01).expect("significance");
    let ekf = Ekf::<f64, 4>::new(x0(), p0()).expect("finite");
    let ukf = Ukf::<f64, 4>::new(x0(), p0()).expect("finite");
    let sr = SrUkf::<f64, 4>::new(x0(), p0()).expect("finite");
    for (what, seen) in [
        ("EKF", with_gate("EKF", ekf, gate)),
        ("UKF", with_gate("UKF", ukf, gate)),
        ("SR-UKF", with_gate("SR-UKF", sr, gate)),
    ] {
        // Every seventh measurement is 40 m off in both axes: the gate
        // rejects those (and, at 1 %, possibly a rare clean one).
        assert!(seen.rejected >= STEPS / 7, "{what}: {seen:?}");
        assert!(seen.rejected <= STEPS / 7 + 2, "{what}: {seen:?}");
        assert_eq!(seen.accepted + seen.rejected, STEPS, "{what}: {seen:?}");
        assert_eq!(seen.failed, 1, "{what}: {seen:?}");
    }
}
