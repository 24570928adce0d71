//! The federated filter: local filters, fusion, reset and fault isolation.

use kestrel_core::linalg::{cholesky, mirror_lower};
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{Real, UpdateReport};

use super::{
    edop, FusionError, FusionReport, Information, Isolation, LocalReport, LocalSet, LocalStatus,
    Policy, PredictSet, SharedNoise, Sharing, Verdict,
};

/// A federated filter (paper 001, after Carlson): `L` local filters of the
/// common `N`-state, possibly of different forms, each processing its own
/// sensors; a fusion `P_g = (Σ P_i⁻¹)⁻¹`, `x_g = P_g Σ P_i⁻¹ x_i` over the
/// admitted locals (in information form through Cholesky solves, see
/// [`Information`]); a reset `x_i = x_g`, `P_i = β_i⁻¹ P_g` by the
/// [`Sharing`] policy, with the local process noise `Q_i = β_i⁻¹ Q`
/// ([`SharedNoise`]); and optional fault isolation ([`Isolation`]).
///
/// One epoch: [`predict`](Self::predict) every local (or predict them by hand
/// with [`shared_noise`](Self::shared_noise)), update each local with its own
/// measurements through [`locals_mut`](Self::locals_mut), pass each
/// [`UpdateReport`] to [`record`](Self::record) for the innovation test, and
/// [`fuse`](Self::fuse). Locals are a tuple of two to six filters of any
/// forms, or an array of one type ([`LocalSet`]). Nothing allocates.
///
/// With `Σ β_i = 1`, reset at every fusion, and linear models, the fused
/// estimate equals the centralised Kalman filter processing every
/// measurement: each local's prior carries exactly `β_i` of the information.
///
/// ```
/// use kestrel_adaptive::federated::{FederatedFilter, Sharing};
/// use kestrel_core::{Ekf, SrUkf, nalgebra::{Matrix1, Matrix1x2, Matrix2, Vector1, Vector2}};
/// use kestrel_models::{LinearMeasurement, LinearProcess};
///
/// // Position and velocity; two position sensors of different precision.
/// let model = LinearProcess::new(Matrix2::new(1.0, 1.0, 0.0, 1.0), Matrix2::identity() * 0.01);
/// let gps = LinearMeasurement::new(Matrix1x2::new(1.0, 0.0), Matrix1::new(4.0));
/// let radar = LinearMeasurement::new(Matrix1x2::new(1.0, 0.0), Matrix1::new(1.0));
/// let (x0, p0) = (Vector2::new(0.0, 1.0), Matrix2::identity() * 10.0);
///
/// let locals = (Ekf::new(x0, p0).unwrap(), SrUkf::new(x0, p0).unwrap());
/// let mut fed = FederatedFilter::new(locals, Sharing::fixed([0.5, 0.5]).unwrap(), x0, p0).unwrap();
/// // The centralised filter, for comparison.
/// let mut central = Ekf::new(x0, p0).unwrap();
/// for k in 1..=10 {
///     let truth = k as f64;
///     fed.predict(&model, 1.0).unwrap();
///     central.predict(&model, 1.0).unwrap();
///     let (z1, z2) = (Vector1::new(truth + 0.3), Vector1::new(truth - 0.1));
///     let r = fed.locals_mut().0.update(&gps, &z1).unwrap();
///     fed.record(0, &r).unwrap();
///     let r = fed.locals_mut().1.update(&radar, &z2).unwrap();
///     fed.record(1, &r).unwrap();
///     let report = fed.fuse().unwrap();
///     assert_eq!(report.fused, 2);
///     central.update(&gps, &z1).unwrap();
///     central.update(&radar, &z2).unwrap();
/// }
/// assert!((fed.state() - central.state()).norm() < 1e-9);
/// assert!((fed.covariance() - central.covariance()).norm() < 1e-9);
/// ```
///
/// Sources: see the [references](kestrel_core::references).
#[derive(Debug, Clone)]
pub struct FederatedFilter<T: Real, const N: usize, const L: usize, Locals> {
    locals: Locals,
    sharing: Sharing<T, L>,
    isolation: Option<Isolation<T>>,
    shares: [T; L],
    status: [LocalStatus; L],
    verdicts: [Verdict; L],
    x: SVector<T, N>,
    p: SMatrix<T, N, N>,
}

impl<T: Real, const N: usize, const L: usize, Locals: LocalSet<T, N, L>>
    FederatedFilter<T, N, L, Locals>
{
    /// A federated filter over `locals` sharing by `sharing`, starting from
    /// the common estimate `x0`, `p0` (lower triangle used): every local is
    /// reset to `x0` with `β_i⁻¹ p0` (also without reset: Carlson's
    /// initialisation). Every local is admitted; no isolation until
    /// [`with_isolation`](Self::with_isolation).
    ///
    /// # Errors
    /// [`FusionError::NoSuchLocal`] if `L = 0`, [`FusionError::FusedNonFinite`]
    /// for a non-finite `x0` or `p0`, [`FusionError::FusedNotPositiveDefinite`]
    /// if `p0` is not positive definite, [`FusionError::Local`] if a local
    /// refuses its reset.
    pub fn new(
        locals: Locals,
        sharing: Sharing<T, L>,
        x0: SVector<T, N>,
        p0: SMatrix<T, N, N>,
    ) -> Result<Self, FusionError> {
        if L == 0 {
            return Err(FusionError::NoSuchLocal { local: 0 });
        }
        if !finite(x0.as_slice()) || !finite(p0.as_slice()) {
            return Err(FusionError::FusedNonFinite);
        }
        cholesky(&p0).map_err(|e| FusionError::FusedNotPositiveDefinite { index: e.index })?;
        let mut p = p0;
        mirror_lower(&mut p);
        let shares = *sharing.shares();
        let mut filter = Self {
            locals,
            sharing,
            isolation: None,
            shares,
            status: [LocalStatus::default(); L],
            verdicts: [Verdict::Untested; L],
            x: x0,
            p,
        };
        filter.reset_locals(true)?;
        Ok(filter)
    }

    /// The same filter with fault isolation by `isolation`.
    pub fn with_isolation(mut self, isolation: Isolation<T>) -> Self {
        self.isolation = Some(isolation);
        self
    }

    /// The local filters.
    pub fn locals(&self) -> &Locals {
        &self.locals
    }

    /// The local filters, to update them with their measurements (a reset
    /// made here is overwritten at the next fusion).
    pub fn locals_mut(&mut self) -> &mut Locals {
        &mut self.locals
    }

    /// The fused state of the last successful fusion (or the initial one).
    pub fn state(&self) -> &SVector<T, N> {
        &self.x
    }

    /// The fused covariance `P_g` of the last successful fusion.
    pub fn covariance(&self) -> &SMatrix<T, N, N> {
        &self.p
    }

    /// The sharing policy.
    pub fn sharing(&self) -> &Sharing<T, L> {
        &self.sharing
    }

    /// The isolation rule, if any.
    pub fn isolation(&self) -> Option<&Isolation<T>> {
        self.isolation.as_ref()
    }

    /// The shares `β_i` the locals hold now (1 for an isolated local), which
    /// scale their process noise until the next fusion.
    pub fn shares(&self) -> &[T; L] {
        &self.shares
    }

    /// Every local's status.
    pub fn statuses(&self) -> &[LocalStatus; L] {
        &self.status
    }

    /// `model` with its noise divided by local `local`'s share, for
    /// predicting that local by hand (when the locals have different process
    /// models).
    ///
    /// # Errors
    /// [`FusionError::NoSuchLocal`] for `local ≥ L`.
    pub fn shared_noise<'m, P>(
        &self,
        local: usize,
        model: &'m P,
    ) -> Result<SharedNoise<'m, T, P>, FusionError> {
        let share = *self
            .shares
            .get(local)
            .ok_or(FusionError::NoSuchLocal { local })?;
        SharedNoise::new(model, share).map_err(|error| FusionError::Local { local, error })
    }

    /// Predicts every local over `dt` with the common process model `model`,
    /// each with its noise divided by its share.
    ///
    /// # Errors
    /// [`FusionError::Local`] naming the first local that refused (the locals
    /// before it have been predicted).
    pub fn predict<'m, P>(&mut self, model: &'m P, dt: T) -> Result<(), FusionError>
    where
        Locals: PredictSet<'m, T, N, L, P>,
    {
        self.locals.predict_each(model, &self.shares, dt)
    }

    /// Records the innovation test of one update of local `local`: its NIS
    /// against `χ²_{1−α}(M)`. Returns the verdict of this test
    /// ([`Verdict::Untested`] without isolation). The epoch's verdict, a
    /// failure if any test of the epoch failed, is applied at the next
    /// [`fuse`](Self::fuse).
    ///
    /// # Errors
    /// [`FusionError::NoSuchLocal`] for `local ≥ L`.
    pub fn record<const M: usize, R>(
        &mut self,
        local: usize,
        report: &UpdateReport<T, M, R>,
    ) -> Result<Verdict, FusionError> {
        self.record_nis(local, report.nis, M)
    }

    /// As [`record`](Self::record), from a test statistic `nis` with `dof`
    /// degrees of freedom.
    ///
    /// # Errors
    /// [`FusionError::NoSuchLocal`] for `local ≥ L`, [`FusionError::Local`]
    /// if `dof = 0`.
    pub fn record_nis(&mut self, local: usize, nis: T, dof: usize) -> Result<Verdict, FusionError> {
        if local >= L {
            return Err(FusionError::NoSuchLocal { local });
        }
        let Some(isolation) = &self.isolation else {
            return Ok(Verdict::Untested);
        };
        let verdict = isolation
            .test(nis, dof)
            .map_err(|error| FusionError::Local { local, error })?;
        self.verdicts[local] = self.verdicts[local].and(verdict);
        Ok(verdict)
    }

    /// Ends the epoch: applies the recorded verdicts (isolating or
    /// re-admitting locals), fuses the estimates of the locals admitted
    /// before and after this epoch, computes the new shares, and resets
    /// every local (unless [`Policy::NoReset`]): admitted ones to
    /// `(x_g, β_i⁻¹ P_g)`, isolated ones to `(x_g, P_g)` so they keep
    /// testing their sensors against the healthy fusion.
    ///
    /// A re-admitted local joins at the next fusion: its estimate still holds
    /// the whole fused information of its last reset, and fusing it now would
    /// count that prior twice.
    ///
    /// # Errors
    /// - [`FusionError::AllIsolated`]: nothing to fuse. The statuses advance
    ///   (so locals can be re-admitted), the last fused estimate is kept and
    ///   the locals are not reset.
    /// - [`FusionError::NotPositiveDefinite`] / [`FusionError::NonFinite`]
    ///   naming a local, [`FusionError::FusedNotPositiveDefinite`],
    ///   [`FusionError::FusedNonFinite`]: nothing changes (the epoch's
    ///   verdicts stay recorded).
    /// - [`FusionError::Local`]: a local refused its reset after the fusion
    ///   was committed; the locals before it were reset.
    pub fn fuse(&mut self) -> Result<FusionReport<T, L>, FusionError> {
        let mut next = self.status;
        if let Some(isolation) = &self.isolation {
            for (s, &v) in next.iter_mut().zip(&self.verdicts) {
                *s = isolation.advance(*s, v);
            }
        }
        let admitted = next.map(|s| s.admitted);
        let fused: [bool; L] = core::array::from_fn(|i| self.status[i].admitted && admitted[i]);

        let mut estimates = [(SVector::<T, N>::zeros(), SMatrix::<T, N, N>::zeros()); L];
        let mut edops = [T::zero(); L];
        for i in 0..L {
            estimates[i] = self
                .locals
                .estimate(i)
                .ok_or(FusionError::NoSuchLocal { local: i })?;
            edops[i] = edop(&estimates[i].1);
        }

        let Some(reference) = fused.iter().position(|&f| f) else {
            self.status = next;
            self.verdicts = [Verdict::Untested; L];
            return Err(FusionError::AllIsolated);
        };
        let x_ref = estimates[reference].0;
        let mut info = Information::new();
        for i in (0..L).filter(|&i| fused[i]) {
            let (x, p) = &estimates[i];
            let d = self
                .locals
                .deviation(i, x, &x_ref)
                .ok_or(FusionError::NoSuchLocal { local: i })?;
            info.add(i, &d, p)?;
        }
        let (dx, p) = info.solve()?;
        let x = self
            .locals
            .moved(reference, &x_ref, &dx)
            .ok_or(FusionError::NoSuchLocal { local: reference })?;
        if !finite(x.as_slice()) {
            return Err(FusionError::FusedNonFinite);
        }

        let reset = self.sharing.policy() != Policy::NoReset;
        let mut shares = self.sharing.distribute(&admitted, &edops)?;
        if reset {
            for (share, _) in shares.iter_mut().zip(&admitted).filter(|&(_, &a)| !a) {
                *share = T::one();
            }
            // Every reset covariance must be finite before any local changes.
            for &share in &shares {
                let inverse = share.recip();
                if !(inverse.is_finite() && finite((p * inverse).as_slice())) {
                    return Err(FusionError::FusedNonFinite);
                }
            }
        }

        self.x = x;
        self.p = p;
        self.status = next;
        self.shares = shares;
        let verdicts = core::mem::replace(&mut self.verdicts, [Verdict::Untested; L]);
        self.reset_locals(reset)?;
        Ok(FusionReport {
            locals: core::array::from_fn(|i| LocalReport {
                status: next[i],
                fused: fused[i],
                verdict: verdicts[i],
                share: shares[i],
                edop: edops[i],
            }),
            fused: info.count(),
        })
    }

    /// Resets every local to `(x_g, β_i⁻¹ P_g)` if `reset`.
    fn reset_locals(&mut self, reset: bool) -> Result<(), FusionError> {
        if !reset {
            return Ok(());
        }
        for i in 0..L {
            let p = self.p * self.shares[i].recip();
            if !finite(p.as_slice()) {
                return Err(FusionError::FusedNonFinite);
            }
            self.locals.reset(i, &self.x, &p)?;
        }
        Ok(())
    }
}

fn finite<T: Real>(values: &[T]) -> bool {
    values.iter().all(|v| v.is_finite())
}
