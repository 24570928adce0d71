use nalgebra::{SMatrix, SVector};

use super::checked_noise::CheckedNoise;
use super::outcome::{
    adapt, joseph_gain_on_ldl, nominal_ldl, unadapted_update, used_factorisation,
};
use super::pending::PendingCovariance;
use super::{FadeStates, Form, PredictForm, UpdateForm};
use crate::adapter::{GainStep, NoiseAdapter, Posterior, PriorAdapter, PriorStep};
use crate::contract::{check_covariance, check_noise_cached};
use crate::error::ensure_finite;
use crate::linalg::{
    cholesky_semidefinite_in_place, mirror_lower, solve_lower, solve_lower_transpose,
};
use crate::real::finite;
use crate::sigma::{self, MerweParams, SigmaWeights};
use crate::{
    FilterError, MeasurementModel, ProcessModel, Quantity, Real, StateSpace, UpdateOutcome,
};

/// The unscented form (UKF) with Merwe scaled sigma points. Needs no
/// Jacobians: plain [`ProcessModel`] and [`MeasurementModel`] suffice.
///
/// Predict propagates `2N + 1` sigma points drawn from `P` and keeps their
/// covariance apart from `Q`. Update redraws the sigma points from
/// `P⁻ = λ Φ P Φᵀ + Q` (so, on a linear model, the result equals the Kalman
/// filter exactly), and applies `P⁺ = P⁻ − K P_xzᵀ − P_xz Kᵀ + K C Kᵀ`, the
/// expanded Joseph form with `P_xz` in place of `P Hᵀ`, with `K R Kᵀ` taken
/// through a factor of `R` ([`joseph_factored_noise`](crate::linalg::joseph_factored_noise)).
/// The gain is taken on the `L D Lᵀ` of `C`, with adapters as they left it,
/// so an adapter that changes nothing gives the filter without adapters bit
/// for bit, as in the [`CovarianceForm`](super::CovarianceForm).
///
/// ```
/// use kestrel_core::form::UnscentedForm;
/// use kestrel_core::sigma::MerweParams;
/// use kestrel_core::nalgebra::Matrix2;
/// let form = UnscentedForm::new(&Matrix2::identity()).unwrap()
///     .with_params(MerweParams::new(0.5, 2.0, 1.0)).unwrap();
/// assert_eq!(form.params().alpha, 0.5);
/// ```
///
/// Sources: see the [references](crate::references).
#[derive(Debug, Clone, PartialEq)]
pub struct UnscentedForm<T: Real, const N: usize> {
    cov: PendingCovariance<T, N>,
    params: MerweParams<T>,
    weights: SigmaWeights<T>,
    /// The last `R` and its factor.
    noise: CheckedNoise<T, N>,
}

impl<T: Real, const N: usize> UnscentedForm<T, N> {
    /// A form holding covariance `p0` (lower triangle used) with the default
    /// sigma points.
    pub fn new(p0: &SMatrix<T, N, N>) -> Result<Self, FilterError> {
        let params = MerweParams::default();
        let weights = params.weights(N).ok_or(FilterError::InvalidParameter {
            name: "N",
            valid: "at least 1 (a state of dimension 0 has no sigma points)",
        })?;
        let mut form = Self {
            cov: PendingCovariance::new(SMatrix::zeros()),
            params,
            weights,
            noise: CheckedNoise::new(),
        };
        form.set_covariance(p0)?;
        Ok(form)
    }

    /// The same form with sigma-point parameters `params`.
    pub fn with_params(mut self, params: MerweParams<T>) -> Result<Self, FilterError> {
        self.weights = params.weights(N).ok_or(MerweParams::<T>::INVALID)?;
        self.params = params;
        Ok(self)
    }

    /// The sigma-point parameters.
    pub fn params(&self) -> &MerweParams<T> {
        &self.params
    }

    /// The sigma-point weights for this state size.
    pub fn weights(&self) -> &SigmaWeights<T> {
        &self.weights
    }

    /// Selects the states an adapter's fade scales (default: all, the
    /// scalar fade): the sigma points of the update are drawn from
    /// `D P_prop D + Q`, `D = diag(√λ on the selected states, 1
    /// elsewhere)`. See [`FadeStates`].
    ///
    /// ```
    /// use kestrel_core::form::{FadeStates, UnscentedForm};
    /// use kestrel_core::nalgebra::Matrix2;
    /// let mut form = UnscentedForm::new(&Matrix2::<f64>::identity()).unwrap();
    /// form.set_fade_states(FadeStates::range(0..1));
    /// assert_eq!(form.fade_states().count(), 1);
    /// ```
    pub fn set_fade_states(&mut self, states: FadeStates<N>) {
        self.cov.set_fade_states(states);
    }

    /// The states a fade scales.
    pub fn fade_states(&self) -> FadeStates<N> {
        self.cov.fade_states()
    }
}

fn factor<T: Real, const N: usize>(p: &SMatrix<T, N, N>) -> Result<SMatrix<T, N, N>, FilterError> {
    let mut s = *p;
    factor_in_place(&mut s)?;
    Ok(s)
}

/// Overwrites the covariance `p` with its factor (no copies in or out).
fn factor_in_place<T: Real, const N: usize>(p: &mut SMatrix<T, N, N>) -> Result<(), FilterError> {
    cholesky_semidefinite_in_place(p).map_err(|e| FilterError::NotPositiveDefinite {
        what: Quantity::StateCovariance,
        index: e.index,
    })
}

/// The statistical linearisation `H = P_xzᵀ P⁻¹` (through the factor `S` of
/// `P`), or `None` where `P` is singular.
pub(crate) fn effective_jacobian<T: Real, const N: usize, const M: usize>(
    s: &SMatrix<T, N, N>,
    cross: &SMatrix<T, N, M>,
) -> Option<SMatrix<T, M, N>> {
    let mut g = *cross;
    solve_lower(s, &mut g);
    solve_lower_transpose(s, &mut g);
    g.iter().all(|&v| finite(v)).then(|| g.transpose())
}

impl<T: Real, const N: usize> Form<T, N> for UnscentedForm<T, N> {
    fn covariance(&self) -> SMatrix<T, N, N> {
        self.cov.prior(T::one())
    }

    fn set_covariance(&mut self, p: &SMatrix<T, N, N>) -> Result<(), FilterError> {
        check_covariance(p, Quantity::StateCovariance)?;
        let mut p = *p;
        mirror_lower(&mut p);
        self.cov.commit(p);
        Ok(())
    }
}

impl<T: Real, const N: usize, P: ProcessModel<T, N>> PredictForm<T, N, P> for UnscentedForm<T, N> {
    fn predict<A: PriorAdapter<T>, S: StateSpace<T, N>>(
        &mut self,
        x: &mut SVector<T, N>,
        model: &P,
        dt: T,
        adapter: &mut A,
        space: &S,
    ) -> Result<(), FilterError> {
        let mut q = model.noise(x, dt);
        let changed = check_noise_cached(&q, self.cov.noise(), Quantity::ProcessNoise)?;
        if changed {
            mirror_lower(&mut q);
        }
        let mut s = self.cov.prior(T::one());
        factor_in_place(&mut s)?;
        let propagated = sigma::propagate(x, &s, &self.weights, model, dt, space)?;
        // Into the spare buffer, current only once checked.
        let p = self.cov.spare();
        propagated.covariance_into(p, &self.weights);
        ensure_finite(p, Quantity::PropagatedCovariance)?;

        let mut step = PriorStep::new(dt);
        adapter.after_predict(&mut step);
        *x = propagated.mean;
        self.cov
            .predicted_spare(changed.then_some(&q), step.fade_factor());
        Ok(())
    }
}

impl<T: Real, const N: usize, H: MeasurementModel<T, N, M>, const M: usize> UpdateForm<T, N, H, M>
    for UnscentedForm<T, N>
{
    fn update<A, S, O>(
        &mut self,
        x: &mut SVector<T, N>,
        model: &H,
        z: &SVector<T, M>,
        adapter: &mut A,
        space: &S,
    ) -> Result<O, FilterError>
    where
        A: NoiseAdapter<T, M>,
        S: StateSpace<T, N>,
        O: UpdateOutcome<T, M, A::Report>,
    {
        ensure_finite(z, Quantity::Measurement)?;
        let mut r = model.noise();
        let r_factor = self.noise.check(&r, Quantity::MeasurementNoise)?;
        mirror_lower(&mut r);
        let w = self.weights;

        let prior = self.cov.prior(T::one());
        let s = factor(&prior)?;
        let measured = sigma::measure(x, &s, &w, model, space)?;
        let pzz = measured.covariance(&w);
        let nu = model.residual(z, &measured.z_hat);
        ensure_finite(&nu, Quantity::Measurement)?;

        if A::IS_IDENTITY {
            // Nothing to adapt: the adapter round left out (equal to it to
            // rounding, as a test checks).
            let noise = (r, &r_factor);
            return unadapted_update(
                &mut self.cov,
                x,
                space,
                &prior,
                &measured.cross,
                &pzz,
                noise,
                nu,
            );
        }

        let split = A::NEEDS_SPLIT.then(|| {
            let h = effective_jacobian(&s, &measured.cross);
            self.cov.split(h.as_ref(), &pzz)
        });
        // Borrowed from the result, not moved out of it (a copy of the
        // factorisation a step).
        let nominal = nominal_ldl(&pzz, &r);
        let ldl = nominal.as_ref().map_err(|e| *e)?;
        let mut step = GainStep::with_ldl(nu, pzz, split, r, ldl);
        let mut done = adapt(adapter, &mut step);
        let fade = done.step.fade_factor();
        if done.step.is_rejected() {
            self.cov.commit(prior);
            return Ok(done.rejected(nu));
        }

        // Borrowed, not moved: the sigma set and P are kilobytes.
        let refaded;
        let (prior, measured, pzz) = if fade == T::one() {
            (&prior, &measured, &pzz)
        } else {
            let prior = self.cov.prior(fade);
            let measured = sigma::measure(x, &factor(&prior)?, &w, model, space)?;
            let pzz = measured.covariance(&w);
            refaded = (prior, measured, pzz);
            (&refaded.0, &refaded.1, &refaded.2)
        };
        // By reference: `done.step` holds them (checked finite here).
        done.check_used()?;
        let (r_used, nu_used) = (done.step.noise(), done.step.innovation());
        let c = pzz + r_used;
        let r_factor = done.noise_factor(Some(&r_factor));
        // The view's factorisation of `C` is this `C`'s only when nothing
        // faded (a fade recomputes `predicted` from the faded prior, which
        // rounds differently from the view's update).
        let mut fresh = None;
        let (ldl, adapted_nis) = used_factorisation(done.step, fade, &c, &mut fresh)?;
        let inputs = (prior, &measured.cross, pzz);
        let noise = (r_used, r_factor, &c);
        let correction = joseph_gain_on_ldl(self.cov.spare(), inputs, noise, ldl, nu_used)?;
        let x_new = space.add(x, &correction);
        ensure_finite(&x_new, Quantity::UpdatedState)?;

        *x = x_new;
        let total_fade = self.cov.total_fade(fade);
        self.cov.commit_spare();
        adapter.after_update(
            &Posterior::on_ldl(nu_used, pzz, r_used, ldl),
            &mut done.adapters,
        );
        Ok(done.accepted(nu, &c, adapted_nis, total_fade))
    }
}
