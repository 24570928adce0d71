use nalgebra::{SMatrix, SVector};

use super::checked_noise::CheckedNoise;
use super::driver::{self, after_predict, Moments, Parts};
use super::outcome::{dense_gain, dense_unadapted, nominal_ldl, AdaptedStep};
use super::pending::{Dense, PendingCovariance, PendingView};
use super::{FadeStates, Form, PredictForm, UpdateForm};
use crate::adapter::{FormFactor, NoiseAdapter, PriorAdapter};
use crate::error::ensure_finite;
use crate::linalg::{
    cholesky_semidefinite_in_place, mirror_lower, solve_lower, solve_lower_transpose, Ldl,
};
use crate::real::finite;
use crate::sigma::{self, MeasuredSigma, MerweParams, SigmaWeights};
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
        self.cov.set_covariance(p)
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
        let q = self.cov.checked_noise(model.noise(x, dt))?;
        let mut s = self.cov.prior(T::one());
        factor_in_place(&mut s)?;
        let propagated = sigma::propagate(x, &s, &self.weights, model, dt, space)?;
        // Into the spare buffer, current only once checked.
        let p = self.cov.spare();
        propagated.covariance_into(p, &self.weights);
        ensure_finite(p, Quantity::PropagatedCovariance)?;

        let fade = after_predict(adapter, dt);
        *x = propagated.mean;
        self.cov.predicted_spare(q.as_ref(), fade);
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
        let moments = SigmaMoments {
            model,
            z,
            weights: self.weights,
            space,
        };
        driver::update(&mut self.cov, x, space, adapter, &moments, (&r, &r_factor))
    }
}

/// The unscented form's moments: the sigma points' `P_xz` and `P_zz`
/// through the measurement model `model`, for the measurement `z`.
struct SigmaMoments<'m, T: Real, const M: usize, H, S> {
    model: &'m H,
    z: &'m SVector<T, M>,
    weights: SigmaWeights<T>,
    space: &'m S,
}

/// The sigma points of a prior through the measurement model, drawn from
/// the factor `s` of the prior, and their `P_zz`.
struct SigmaOf<T: Real, const N: usize, const M: usize> {
    s: SMatrix<T, N, N>,
    measured: MeasuredSigma<T, N, M>,
    pzz: SMatrix<T, M, M>,
}

impl<T, const N: usize, const M: usize, H, Sp> Moments<T, N, M> for SigmaMoments<'_, T, M, H, Sp>
where
    T: Real,
    H: MeasurementModel<T, N, M>,
    Sp: StateSpace<T, N>,
{
    type Storage = Dense;
    type Of = SigmaOf<T, N, M>;
    type Nominal = Ldl<T, M>;

    #[inline(always)]
    fn of(
        &self,
        prior: &SMatrix<T, N, N>,
        x: &SVector<T, N>,
        _noise_factor: impl FnOnce() -> Result<SMatrix<T, M, M>, FilterError>,
    ) -> Result<Self::Of, FilterError> {
        let s = factor(prior)?;
        let measured = sigma::measure(x, &s, &self.weights, self.model, self.space)?;
        let pzz = measured.covariance(&self.weights);
        Ok(SigmaOf { s, measured, pzz })
    }

    #[inline(always)]
    fn innovation(&self, of: &Self::Of) -> Result<SVector<T, M>, FilterError> {
        let nu = self.model.residual(self.z, &of.measured.z_hat);
        ensure_finite(&nu, Quantity::Measurement)?;
        Ok(nu)
    }

    #[inline(always)]
    fn unadapted<S, R, O>(
        &self,
        of: &Self::Of,
        prior: &SMatrix<T, N, N>,
        spare: &mut SMatrix<T, N, N>,
        x: &mut SVector<T, N>,
        space: &S,
        noise: (&SMatrix<T, M, M>, &SMatrix<T, M, M>),
        innovation: SVector<T, M>,
        fade: T,
    ) -> Result<O, FilterError>
    where
        S: StateSpace<T, N>,
        R: Default,
        O: UpdateOutcome<T, M, R>,
    {
        let moments = (prior, &of.measured.cross, &of.pzz);
        dense_unadapted(moments, spare, x, space, noise, innovation, fade)
    }

    #[inline(always)]
    fn nominal(&self, of: &Self::Of, r: &SMatrix<T, M, M>) -> Result<Ldl<T, M>, FilterError> {
        nominal_ldl(&of.pzz, r)
    }

    /// Through the statistical linearisation `H = P_xzᵀ P⁻¹`.
    #[inline(always)]
    fn split(
        &self,
        of: &Self::Of,
        view: &PendingView<'_, T, N, Dense>,
        _prior: &SMatrix<T, N, N>,
        _r: &SMatrix<T, M, M>,
    ) -> Parts<T, M> {
        let h = effective_jacobian(&of.s, &of.measured.cross);
        view.split(h.as_ref(), &of.pzz)
    }

    #[inline(always)]
    fn nominal_view<'s>(
        &self,
        of: &'s Self::Of,
        nominal: &'s Ldl<T, M>,
    ) -> (&'s SMatrix<T, M, M>, FormFactor<'s, T, M>) {
        (&of.pzz, FormFactor::Ldl(nominal))
    }

    #[inline(always)]
    fn gain<A, S, O>(
        &self,
        of: &Self::Of,
        prior: &SMatrix<T, N, N>,
        spare: &mut SMatrix<T, N, N>,
        x: &mut SVector<T, N>,
        space: &S,
        done: AdaptedStep<'_, '_, T, M, A::Report>,
        fades: (SVector<T, M>, T, T),
        noise_factor: &SMatrix<T, M, M>,
        adapter: &mut A,
    ) -> Result<O, FilterError>
    where
        A: NoiseAdapter<T, M>,
        S: StateSpace<T, N>,
        O: UpdateOutcome<T, M, A::Report>,
    {
        let moments = (prior, &of.measured.cross, &of.pzz);
        dense_gain(moments, spare, x, space, done, fades, noise_factor, adapter)
    }
}
