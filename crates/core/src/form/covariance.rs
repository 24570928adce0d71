use nalgebra::{SMatrix, SVector};

use super::checked_noise::CheckedNoise;
use super::outcome::{
    adapt, joseph_gain_on_ldl, nominal_ldl, unadapted_update, used_factorisation,
};
use super::pending::PendingCovariance;
use super::{sequential, FadeStates, Form, PredictForm, SequentialUpdates, UpdateForm};
use crate::adapter::{GainStep, NoiseAdapter, Posterior, PriorAdapter, PriorStep};
use crate::contract::{check_covariance, check_diagonal, check_noise_cached};
use crate::error::{diagnose, ensure_finite, is_finite};
use crate::linalg::{mirror_lower, sandwich_into, sandwich_transposed};
use crate::{
    FilterError, LinearizedMeasurement, LinearizedProcess, Quantity, Real, StateSpace,
    UpdateOutcome, UpdateReport,
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
/// which gives the same result as the batch update to rounding and is the
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
        check_covariance(p, Quantity::StateCovariance)?;
        let mut p = *p;
        mirror_lower(&mut p);
        self.cov.commit(p);
        Ok(())
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
        let mut q = model.noise(x, dt);
        let changed = check_noise_cached(&q, self.cov.noise(), Quantity::ProcessNoise)?;
        if changed {
            mirror_lower(&mut q);
        }
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

        let mut step = PriorStep::new(dt);
        adapter.after_predict(&mut step);
        *x = x_new;
        self.cov
            .predicted_spare(changed.then_some(&q), step.fade_factor());
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
        let prior = self.cov.prior(T::one());

        // Without a factor of `R` (diagonal, taken one component at a time).
        let Some(r_factor) = r_factor.as_ref() else {
            let out = sequential::update(&prior, &h, &r, &nu)?;
            let x_new = space.add(x, &out.correction);
            ensure_finite(&x_new, Quantity::UpdatedState)?;
            ensure_finite(&out.covariance, Quantity::UpdatedCovariance)?;
            *x = x_new;
            self.cov.commit(out.covariance);
            let report = UpdateReport {
                innovation: nu,
                innovation_used: nu,
                nis: out.nis,
                adapted_nis: out.nis,
                fade: T::one(),
                rejected: false,
                sequential: true,
                adapters: A::Report::default(),
            };
            let c = &out.innovation_covariance;
            return Ok(O::assemble(report, c, c, &r));
        };

        // Without an adapter the update leaves out every adapter step
        // (nothing to adapt, nothing to copy into a `GainStep`); equal to
        // the general path to rounding, as a test checks.
        if A::IS_IDENTITY {
            let hp = h * prior;
            let hph = sandwich_transposed(&hp, &h);
            let noise = (r, r_factor);
            // `B = P⁻ Hᵀ = (H P⁻)ᵀ`, as the gain's right-hand solves and the
            // Joseph update take it.
            let cross = hp.transpose();
            return unadapted_update(&mut self.cov, x, space, &prior, &cross, &hph, noise, nu)
                .or_else(|e| diagnose(|| jacobian().and(Err(e))));
        }

        // H P⁻ (= (P⁻ Hᵀ)ᵀ) and H P⁻ Hᵀ, one triangle. A fading adapter's
        // split into propagated and process-noise parts is computed only if
        // it asks (its divergence test failed).
        let hp = h * prior;
        let hph = sandwich_transposed(&hp, &h);
        // The view borrows what the split is computed from while the
        // posterior goes into the spare buffer (no copy of the view).
        let (pending, spare) = self.cov.view_and_spare();
        let parts = || pending.split(Some(&h), &hph);
        // Borrowed from the result, not moved out of it (a copy of the
        // factorisation a step).
        let nominal = nominal_ldl(&hph, &r);
        let ldl = match &nominal {
            Ok(ldl) => ldl,
            Err(e) => return Err(diagnose(|| jacobian().err().unwrap_or(*e))),
        };
        let mut step = if A::NEEDS_SPLIT {
            GainStep::with_lazy_split(nu, hph, &parts, r, ldl)
        } else {
            GainStep::with_ldl(nu, hph, None, r, ldl)
        };
        let mut done = adapt(adapter, &mut step);
        let fade = done.step.fade_factor();
        if done.step.is_rejected() {
            let report = done.rejected(nu);
            self.cov.commit(prior);
            return Ok(report);
        }

        // Borrowed, not moved: the matrices are hundreds of bytes each.
        let refaded;
        let (prior, hp, hph) = if fade == T::one() {
            (&prior, &hp, &hph)
        } else {
            let prior = pending.prior(fade);
            let hp = h * prior;
            let hph = sandwich_transposed(&hp, &h);
            refaded = (prior, hp, hph);
            (&refaded.0, &refaded.1, &refaded.2)
        };
        // By reference: `done.step` holds them (checked finite here).
        done.check_used()?;
        let (r_used, nu_used) = (done.step.noise(), done.step.innovation());
        let c = hph + r_used;
        let r_factor = done.noise_factor(Some(r_factor));
        // The view's factorisation of `C` is this `C`'s only when nothing
        // faded (a fade recomputes `predicted` from the faded prior, which
        // rounds differently from the view's update). In an epoch the
        // adapters left as they were it is the nominal `L D Lᵀ`, and this
        // is the update without adapters, bit for bit.
        let mut fresh = None;
        let (ldl, adapted_nis) = used_factorisation(done.step, fade, &c, &mut fresh)?;
        let cross = hp.transpose();
        let inputs = (prior, &cross, hph);
        let correction = joseph_gain_on_ldl(spare, inputs, (r_used, r_factor, &c), ldl, nu_used)?;
        let x_new = space.add(x, &correction);
        ensure_finite(&x_new, Quantity::UpdatedState)?;

        // Nothing below can fail: the adapters see the update before the
        // posterior in the spare buffer becomes current.
        *x = x_new;
        let total_fade = pending.total_fade(fade);
        adapter.after_update(
            &Posterior::on_ldl(nu_used, hph, r_used, ldl),
            &mut done.adapters,
        );
        let report = done.accepted(nu, &c, adapted_nis, total_fade);
        self.cov.commit_spare();
        Ok(report)
    }
}
