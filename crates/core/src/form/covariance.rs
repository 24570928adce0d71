use nalgebra::{SMatrix, SVector};

use super::checked_noise::CheckedNoise;
use super::driver::{self, after_predict, Moments, Parts};
use super::outcome::{dense_gain, dense_unadapted, nominal_ldl, unadapted_report, AdaptedStep};
use super::pending::{Dense, PendingCovariance, PendingView};
use super::{sequential, FadeStates, Form, PredictForm, SequentialUpdates, UpdateForm};
use crate::adapter::{FormFactor, NoiseAdapter, PriorAdapter};
use crate::contract::check_diagonal;
use crate::error::{diagnose, ensure_finite, is_finite};
use crate::linalg::{mirror_lower, sandwich_into, sandwich_transposed, Ldl};
use crate::{
    FilterError, LinearizedMeasurement, LinearizedProcess, Quantity, Real, StateSpace,
    UpdateOutcome,
};

/// The covariance form (Kalman filter, extended Kalman filter): stores `P`,
/// predicts `P⁻ = λ Φ P Φᵀ + Q` and updates with the Joseph form, expanded
/// to `O(N²M)` products with `K R Kᵀ` through a factor of `R` (see
/// [`joseph_factored_noise`](crate::linalg::joseph_factored_noise)). Requires
/// [`LinearizedProcess`] and [`LinearizedMeasurement`] models.
///
/// When the filter has no adapter, `R` is diagonal, the measurement has at
/// least four components and the state at most twelve, the update processes
/// the measurement one component at a time (sequential scalar updates),
/// which gives the same result as the batch update to rounding and was the
/// faster of the two there; see [`SequentialUpdates`] for the measurements
/// behind that choice and
/// [`set_sequential_updates`](Self::set_sequential_updates) to change it.
///
/// With adapters, the gain is taken on the `L D Lᵀ` of `C` as they left
/// it (no square roots on the way to the gain): the nominal one while they
/// faded nothing and kept `R`, the adapter view's own after a new `R`. So
/// an epoch in which they changed nothing is updated as without them, on
/// the same factorisation: an adapter that changes nothing gives the
/// filter without adapters bit for bit (the adapted NIS is then the NIS).
///
/// ```
/// use kestrel_core::form::{CovarianceForm, Form};
/// use kestrel_core::nalgebra::Matrix2;
/// let form = CovarianceForm::new(&Matrix2::new(2.0, 0.5, 0.5, 1.0)).unwrap();
/// assert_eq!(form.covariance()[(0, 1)], 0.5);
/// ```
///
/// Sources: see the [references](crate::references).
#[derive(Debug, Clone, PartialEq)]
pub struct CovarianceForm<T: Real, const N: usize> {
    cov: PendingCovariance<T, N>,
    sequential: SequentialUpdates,
    /// The last dense `R` and its factor.
    noise: CheckedNoise<T, N>,
}

impl<T: Real, const N: usize> CovarianceForm<T, N> {
    /// A form holding covariance `p0` (the lower triangle is used).
    pub fn new(p0: &SMatrix<T, N, N>) -> Result<Self, FilterError> {
        let mut form = Self {
            cov: PendingCovariance::new(SMatrix::zeros()),
            sequential: SequentialUpdates::BySize,
            noise: CheckedNoise::new(),
        };
        form.set_covariance(p0)?;
        Ok(form)
    }

    /// When a diagonal `R` is taken one component at a time (default:
    /// [`SequentialUpdates::BySize`]).
    ///
    /// ```
    /// use kestrel_core::form::{CovarianceForm, SequentialUpdates};
    /// use kestrel_core::nalgebra::Matrix2;
    /// let mut form = CovarianceForm::new(&Matrix2::<f64>::identity()).unwrap();
    /// assert_eq!(form.sequential_updates(), SequentialUpdates::BySize);
    /// form.set_sequential_updates(SequentialUpdates::Always);
    /// assert_eq!(form.sequential_updates(), SequentialUpdates::Always);
    /// ```
    pub fn set_sequential_updates(&mut self, when: SequentialUpdates) {
        self.sequential = when;
    }

    /// When a diagonal `R` is taken one component at a time.
    pub fn sequential_updates(&self) -> SequentialUpdates {
        self.sequential
    }

    /// Whether a diagonal `R` may be taken one component at a time (any
    /// setting but [`SequentialUpdates::Never`]).
    #[deprecated(note = "use `sequential_updates`, which also says for which sizes")]
    pub fn sequential(&self) -> bool {
        self.sequential != SequentialUpdates::Never
    }

    /// Shorthand: `true` takes every diagonal `R` one component at a time
    /// ([`SequentialUpdates::Always`]), `false` never
    /// ([`SequentialUpdates::Never`]).
    pub fn set_sequential(&mut self, enabled: bool) {
        self.sequential = if enabled {
            SequentialUpdates::Always
        } else {
            SequentialUpdates::Never
        };
    }

    /// Selects the states an adapter's fade scales (default: all, the
    /// scalar fade): `P⁻ = D Φ P Φᵀ D + Q`, `D = diag(√λ on the selected
    /// states, 1 elsewhere)`; exact in this form. See [`FadeStates`].
    ///
    /// ```
    /// use kestrel_core::form::{CovarianceForm, FadeStates};
    /// use kestrel_core::nalgebra::Matrix2;
    /// let mut form = CovarianceForm::new(&Matrix2::<f64>::identity()).unwrap();
    /// form.set_fade_states(FadeStates::range(1..2));
    /// assert!(form.fade_states().contains(1) && !form.fade_states().contains(0));
    /// ```
    pub fn set_fade_states(&mut self, states: FadeStates<N>) {
        self.cov.set_fade_states(states);
    }

    /// The states a fade scales.
    pub fn fade_states(&self) -> FadeStates<N> {
        self.cov.fade_states()
    }
}

impl<T: Real, const N: usize> Form<T, N> for CovarianceForm<T, N> {
    fn covariance(&self) -> SMatrix<T, N, N> {
        self.cov.prior(T::one())
    }

    fn set_covariance(&mut self, p: &SMatrix<T, N, N>) -> Result<(), FilterError> {
        self.cov.set_covariance(p)
    }
}

impl<T: Real, const N: usize, P: LinearizedProcess<T, N>> PredictForm<T, N, P>
    for CovarianceForm<T, N>
{
    fn predict<A: PriorAdapter<T>, S: StateSpace<T, N>>(
        &mut self,
        x: &mut SVector<T, N>,
        model: &P,
        dt: T,
        adapter: &mut A,
        _space: &S,
    ) -> Result<(), FilterError> {
        let q = self.cov.checked_noise(model.noise(x, dt))?;
        let phi = model.transition(x, dt);
        let x_new = model.propagate(x, dt);
        // Φ P Φᵀ into the spare buffer, current only once checked (no
        // copy either way). Two predictions in a row propagate the prior.
        let prior = self.cov.is_pending().then(|| self.cov.prior(T::one()));
        let (current, spare) = self.cov.current_and_spare();
        sandwich_into(&phi, prior.as_ref().unwrap_or(current), spare);
        // Only the outputs are checked on the way: a non-finite `Φ` makes
        // the diagonal of `Φ P Φᵀ` non-finite (`Φᵢⱼ² Pⱼⱼ`, or `∞ · 0`), so
        // if both pass, `Φ` is finite. If one fails, the checks run in
        // order to name the first quantity that is not finite.
        if !(is_finite(&x_new) && is_finite(spare)) {
            let spare = &*spare;
            diagnose(|| {
                ensure_finite(&phi, Quantity::Transition)?;
                ensure_finite(&x_new, Quantity::PropagatedState)?;
                ensure_finite(spare, Quantity::PropagatedCovariance)
            })?;
        }

        let fade = after_predict(adapter, dt);
        *x = x_new;
        self.cov.predicted_spare(q.as_ref(), fade);
        Ok(())
    }
}

impl<T: Real, const N: usize, H: LinearizedMeasurement<T, N, M>, const M: usize>
    UpdateForm<T, N, H, M> for CovarianceForm<T, N>
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
        // Diagonal R (the sequential path) needs no factor: its check is
        // the sign of each variance. Otherwise the factor the Joseph update
        // takes R through is the check.
        let diagonal =
            A::IS_IDENTITY && self.sequential.applies(N, M) && sequential::is_diagonal(&r);
        let r_factor = if diagonal {
            check_diagonal(&r, Quantity::MeasurementNoise)?;
            None
        } else {
            Some(self.noise.check(&r, Quantity::MeasurementNoise)?)
        };
        mirror_lower(&mut r);
        let z_hat = model.predict(x);
        ensure_finite(&z_hat, Quantity::PredictedMeasurement)?;
        let h = model.jacobian(x);
        // Outside the sequential path `H` is checked through the outputs: a
        // non-finite `Hᵢⱼ` makes `(H P Hᵀ)ᵢᵢ` non-finite (`Hᵢⱼ² Pⱼⱼ`, or
        // `∞ · 0`), which no factorisation of `C` passes, and `C` is
        // factored before any adapter sees `H P Hᵀ`. If the update fails,
        // `H` is checked first, as it would have been here.
        let jacobian = || ensure_finite(&h, Quantity::MeasurementJacobian);
        if diagonal {
            jacobian()?;
        }
        let nu = model.residual(z, &z_hat);
        let nu_check = |e| diagnose(|| jacobian().and(Err(e)));
        ensure_finite(&nu, Quantity::Measurement).or_else(nu_check)?;

        // Without a factor of `R` (diagonal, taken one component at a time).
        let Some(r_factor) = r_factor.as_ref() else {
            let prior = self.cov.prior(T::one());
            let out = sequential::update(&prior, &h, &r, &nu)?;
            let x_new = space.add(x, &out.correction);
            ensure_finite(&x_new, Quantity::UpdatedState)?;
            ensure_finite(&out.covariance, Quantity::UpdatedCovariance)?;
            *x = x_new;
            self.cov.commit(out.covariance);
            let c = &out.innovation_covariance;
            return Ok(unadapted_report(nu, c, &r, out.nis, T::one(), true));
        };
        let moments = LinearMoments { h: &h, nu };
        driver::update(&mut self.cov, x, space, adapter, &moments, (&r, r_factor))
    }
}

/// The covariance form's moments: `B = P⁻ Hᵀ = (H P⁻)ᵀ` and `H P⁻ Hᵀ` for
/// the Jacobian `h`, the innovation `nu` computed before them.
struct LinearMoments<'m, T: Real, const N: usize, const M: usize> {
    h: &'m SMatrix<T, M, N>,
    nu: SVector<T, M>,
}

/// `B = P⁻ Hᵀ` (as the gain's right-hand solves and the Joseph update take
/// it) and `H P⁻ Hᵀ`, one triangle.
struct LinearOf<T: Real, const N: usize, const M: usize> {
    cross: SMatrix<T, N, M>,
    predicted: SMatrix<T, M, M>,
}

impl<T: Real, const N: usize, const M: usize> Moments<T, N, M> for LinearMoments<'_, T, N, M> {
    type Storage = Dense;
    type Of = LinearOf<T, N, M>;
    type Nominal = Ldl<T, M>;

    #[inline(always)]
    fn of(
        &self,
        prior: &SMatrix<T, N, N>,
        _x: &SVector<T, N>,
        _noise_factor: impl FnOnce() -> Result<SMatrix<T, M, M>, FilterError>,
    ) -> Result<Self::Of, FilterError> {
        let hp = self.h * prior;
        let predicted = sandwich_transposed(&hp, self.h);
        Ok(LinearOf {
            cross: hp.transpose(),
            predicted,
        })
    }

    #[inline(always)]
    fn innovation(&self, _of: &Self::Of) -> Result<SVector<T, M>, FilterError> {
        Ok(self.nu)
    }

    /// `H` is checked through the outputs: a non-finite `Hᵢⱼ` makes
    /// `(H P Hᵀ)ᵢᵢ` non-finite (`Hᵢⱼ² Pⱼⱼ`, or `∞ · 0`), which no
    /// factorisation of `C` passes, and `C` is factored before any adapter
    /// sees `H P⁻ Hᵀ`. If the update fails, `H` is checked first, as it
    /// would have been with the inputs.
    #[inline(always)]
    fn diagnose(&self, e: FilterError) -> FilterError {
        diagnose(|| {
            ensure_finite(self.h, Quantity::MeasurementJacobian)
                .err()
                .unwrap_or(e)
        })
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
        let moments = (prior, &of.cross, &of.predicted);
        dense_unadapted(moments, spare, x, space, noise, innovation, fade)
    }

    #[inline(always)]
    fn nominal(&self, of: &Self::Of, r: &SMatrix<T, M, M>) -> Result<Ldl<T, M>, FilterError> {
        nominal_ldl(&of.predicted, r)
    }

    #[inline(always)]
    fn split(
        &self,
        of: &Self::Of,
        view: &PendingView<'_, T, N, Dense>,
        _prior: &SMatrix<T, N, N>,
        _r: &SMatrix<T, M, M>,
    ) -> Parts<T, M> {
        view.split(Some(self.h), &of.predicted)
    }

    #[inline(always)]
    fn nominal_view<'s>(
        &self,
        of: &'s Self::Of,
        nominal: &'s Ldl<T, M>,
    ) -> (&'s SMatrix<T, M, M>, FormFactor<'s, T, M>) {
        (&of.predicted, FormFactor::Ldl(nominal))
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
        let moments = (prior, &of.cross, &of.predicted);
        dense_gain(moments, spare, x, space, done, fades, noise_factor, adapter)
    }
}
