//! The discrete process noise of every model is symmetric positive
//! semi-definite for any step and any valid parameters.

use kestrel_core::linalg::cholesky;
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{ProcessModel, Real};
use kestrel_models::{
    ConstantAcceleration1d, ConstantAcceleration2d, ConstantAcceleration3d, ConstantVelocity1d,
    ConstantVelocity2d, ConstantVelocity3d, GaussMarkov, Lti, RandomWalk, Stack,
};
use proptest::prelude::*;

/// `Q` is exactly symmetric and `Q + δ I` is positive definite for
/// `δ = rel · tr Q`, i.e. no eigenvalue is below `−δ` (a zero trace
/// requires `Q = 0`).
fn assert_psd<T: Real, const N: usize>(
    q: &SMatrix<T, N, N>,
    rel: f64,
) -> Result<(), TestCaseError> {
    prop_assert!(q.iter().all(|v| v.is_finite()), "non-finite Q: {q}");
    prop_assert_eq!(q, &q.transpose());
    if q.trace() == T::zero() {
        prop_assert!(
            q.iter().all(|v| *v == T::zero()),
            "zero trace but Q ≠ 0: {q}"
        );
        return Ok(());
    }
    let delta = q.trace() * kestrel_core::real::lit(rel);
    let shifted = q + SMatrix::<T, N, N>::identity() * delta;
    prop_assert!(cholesky(&shifted).is_ok(), "Q not PSD: {q}");
    Ok(())
}

fn noise<T: Real, P: ProcessModel<T, N>, const N: usize>(p: &P, dt: T) -> SMatrix<T, N, N> {
    p.noise(&SVector::zeros(), dt)
}

proptest! {
    #[test]
    fn kinematic(dt in 0.0..10.0, q in prop::array::uniform3(0.0..100.0)) {
        assert_psd(&noise(&ConstantVelocity1d::new(q[0]).unwrap(), dt), 1e-12)?;
        assert_psd(&noise(&ConstantVelocity2d::per_axis(&q[..2]).unwrap(), dt), 1e-12)?;
        assert_psd(&noise(&ConstantVelocity3d::per_axis(&q).unwrap(), dt), 1e-12)?;
        assert_psd(&noise(&ConstantAcceleration1d::new(q[0]).unwrap(), dt), 1e-12)?;
        assert_psd(&noise(&ConstantAcceleration2d::per_axis(&q[..2]).unwrap(), dt), 1e-12)?;
        assert_psd(&noise(&ConstantAcceleration3d::per_axis(&q).unwrap(), dt), 1e-12)?;
        let (dt32, q32) = (dt as f32, q.map(|v| v as f32));
        assert_psd(&noise(&ConstantVelocity3d::per_axis(&q32).unwrap(), dt32), 1e-5)?;
        assert_psd(&noise(&ConstantAcceleration3d::per_axis(&q32).unwrap(), dt32), 1e-5)?;
    }

    #[test]
    fn diagonal_states(
        dt in 0.0..100.0,
        q in prop::array::uniform3(0.0..100.0),
        tau in prop::array::uniform3(1e-3..1e4),
        sigma in prop::array::uniform3(0.0..10.0),
    ) {
        let rw = RandomWalk::new(SVector::from(q)).unwrap();
        let gm = GaussMarkov::new(SVector::from(tau), SVector::from(sigma)).unwrap();
        assert_psd(&noise(&rw, dt), 1e-12)?;
        assert_psd(&noise(&gm, dt), 1e-12)?;
        assert_psd(&noise::<_, _, 6>(&Stack::new(rw, gm), dt), 1e-12)?;
        let gm32 = GaussMarkov::new(SVector::from(tau.map(|v| v as f32)), SVector::from(sigma.map(|v| v as f32))).unwrap();
        assert_psd(&noise(&gm32, dt as f32), 1e-5)?;
    }

    /// Random coupled systems `ẋ = F x + G w` with `Q_c = L Lᵀ`.
    #[test]
    fn van_loan_lti(
        dt in 0.0..3.0,
        f in prop::array::uniform16(-1.5..1.5),
        g in prop::array::uniform8(-2.0..2.0),
        l in prop::array::uniform4(-1.0..1.0),
    ) {
        let f = SMatrix::<f64, 4, 4>::from_row_slice(&f);
        let g = SMatrix::<f64, 4, 2>::from_row_slice(&g);
        let l = SMatrix::<f64, 2, 2>::from_row_slice(&l);
        let lti = Lti::new(f, g, l * l.transpose());
        assert_psd(&noise(&lti, dt), 1e-12)?;
        let stacked = Stack::<_, _, 4, 2>::new(lti, ConstantVelocity1d::new(1.0).unwrap());
        assert_psd(&noise::<_, _, 6>(&stacked, dt), 1e-12)?;
        let lti32 = Lti::new(f.cast::<f32>(), g.cast::<f32>(), (l * l.transpose()).cast::<f32>());
        assert_psd(&noise(&lti32, dt as f32), 1e-5)?;
    }
}
