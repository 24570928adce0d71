//! The update steps the three forms share, written once: the no-adapter
//! shortcut, the adapter round and a rejection, the moments again after a
//! fade, and the gain, commit and report. A form supplies its *moments*
//! ([`Moments`]: `H P⁻` and `H P⁻ Hᵀ`, or the sigma points' `P_xz` and
//! `P_zz`, and how its gain takes them) on a *storage* ([`Storage`]: dense
//! `P` or a Cholesky factor).

use nalgebra::{SMatrix, SVector};

use super::outcome::{adapt, AdaptedStep};
use super::pending::{Pending, PendingView, Storage};
pub(crate) use crate::adapter::Parts;
use crate::adapter::{FormFactor, GainStep, NoiseAdapter, PriorAdapter, PriorStep};
use crate::linalg::cholesky_semidefinite;
use crate::{FilterError, Quantity, Real, StateSpace, UpdateOutcome};

/// A form's measurement moments of a prior and how its gain takes them.
/// Implemented by what a form knows for one update (its model, the
/// measurement, its sigma-point weights) after the input checks.
pub(crate) trait Moments<T: Real, const N: usize, const M: usize> {
    /// How the form stores its covariance.
    type Storage: Storage<T, N>;
    /// The moments of one prior.
    type Of;
    /// What the adapters' view is built on besides the moments: the
    /// nominal `L D Lᵀ` of `C` for the dense storage.
    type Nominal;

    /// Whether the noise and innovation the adapters left are checked
    /// before the moments are made again (the factor storage's `S_z` is
    /// made from the `R` used) rather than after.
    const CHECKS_BEFORE_REFADE: bool = false;

    /// The moments of `prior` (or its factor) at the state `x`;
    /// `noise_factor` gives the lower factor of `R` where the moments take
    /// it (the factor storage's `S_z`).
    fn of(
        &self,
        prior: &SMatrix<T, N, N>,
        x: &SVector<T, N>,
        noise_factor: impl FnOnce() -> Result<SMatrix<T, M, M>, FilterError>,
    ) -> Result<Self::Of, FilterError>;

    /// The innovation for the nominal moments, checked finite.
    fn innovation(&self, of: &Self::Of) -> Result<SVector<T, M>, FilterError>;

    /// The error an update reports for `e` (the covariance form names a
    /// non-finite Jacobian first).
    #[inline(always)]
    fn diagnose(&self, e: FilterError) -> FilterError {
        e
    }

    /// The update without adapters: the posterior into `spare`, from the
    /// moments `of` of `prior`, `R` with its lower factor and the
    /// innovation; once nothing can fail, the updated state into `x` and
    /// the report, for the total fade `fade`.
    #[allow(clippy::too_many_arguments)]
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
        O: UpdateOutcome<T, M, R>;

    /// The factorisation of the nominal `C` the adapters' view is built
    /// on, failing where `C` is not positive definite.
    fn nominal(&self, of: &Self::Of, r: &SMatrix<T, M, M>) -> Result<Self::Nominal, FilterError>;

    /// The split of the predicted measurement covariance into propagated
    /// part and process noise, for an adapter that asks.
    fn split(
        &self,
        of: &Self::Of,
        view: &PendingView<'_, T, N, Self::Storage>,
        prior: &SMatrix<T, N, N>,
        r: &SMatrix<T, M, M>,
    ) -> Parts<T, M>;

    /// What the adapters' view is built on: the predicted measurement
    /// covariance and the factorisation of the nominal `C`.
    fn nominal_view<'s>(
        &self,
        of: &'s Self::Of,
        nominal: &'s Self::Nominal,
    ) -> (&'s SMatrix<T, M, M>, FormFactor<'s, T, M>);

    /// The prior and its moments the gain takes after the adapters, into
    /// `refaded` when they differ from the nominal ones: those of the prior
    /// faded by `fade ≠ 1`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn refaded<R>(
        &self,
        _of: &Self::Of,
        view: &PendingView<'_, T, N, Self::Storage>,
        _prior: &SMatrix<T, N, N>,
        (fade, done): (T, &AdaptedStep<'_, '_, T, M, R>),
        x: &SVector<T, N>,
        noise_factor: &SMatrix<T, M, M>,
        refaded: &mut Option<(SMatrix<T, N, N>, Self::Of)>,
    ) -> Result<(), FilterError> {
        faded(self, view, (fade, done), x, noise_factor, refaded)
    }

    /// The update after the adapters: the gain on the moments `of` of
    /// `prior` with the noise and innovation the adapters settled on, the
    /// posterior into `spare`, and, once nothing can fail, the updated
    /// state into `x`, the adapters' `after_update` and the report for the
    /// raw innovation, the fade and the total fade in `fades`.
    /// `noise_factor` is the model's factor of `R`.
    #[allow(clippy::too_many_arguments)]
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
        O: UpdateOutcome<T, M, A::Report>;
}

/// The prior faded by `fade` and its moments into `refaded`, nothing for
/// `fade = 1`.
#[inline(always)]
pub(crate) fn faded<T, const N: usize, const M: usize, Mo, R>(
    moments: &Mo,
    view: &PendingView<'_, T, N, Mo::Storage>,
    (fade, done): (T, &AdaptedStep<'_, '_, T, M, R>),
    x: &SVector<T, N>,
    noise_factor: &SMatrix<T, M, M>,
    refaded: &mut Option<(SMatrix<T, N, N>, Mo::Of)>,
) -> Result<(), FilterError>
where
    T: Real,
    Mo: Moments<T, N, M> + ?Sized,
{
    if fade == T::one() {
        return Ok(());
    }
    let prior = view.prior(fade);
    let of = moments.of(&prior, x, || used_noise_factor(done, noise_factor))?;
    *refaded = Some((prior, of));
    Ok(())
}

/// The lower factor of the `R` the adapters settled on: the model's
/// (`model`), the one an adapter gave with its `R`, or one computed here.
#[inline(always)]
pub(crate) fn used_noise_factor<T: Real, const M: usize, R>(
    done: &AdaptedStep<'_, '_, T, M, R>,
    model: &SMatrix<T, M, M>,
) -> Result<SMatrix<T, M, M>, FilterError> {
    match done.noise_factor(Some(model)) {
        Some(l) => Ok(*l),
        // An `R` an adapter set without a factor: it may be singular, not
        // indefinite.
        None => {
            cholesky_semidefinite(done.step.noise()).map_err(|e| FilterError::NotPositiveDefinite {
                what: Quantity::MeasurementNoise,
                index: e.index,
            })
        }
    }
}

/// An update after the form's input checks, for the noise `R` of the model
/// with its lower factor: the moments of the prior, the innovation, then
/// without adapters the update on them, else the adapter round (a
/// rejection leaves the prior as the posterior), the moments again where
/// the adapters faded, the gain and the report. On error nothing is
/// changed.
#[inline(always)]
pub(crate) fn update<T, const N: usize, const M: usize, Mo, A, S, O>(
    storage: &mut Pending<T, N, Mo::Storage>,
    x: &mut SVector<T, N>,
    space: &S,
    adapter: &mut A,
    moments: &Mo,
    (r, r_factor): (&SMatrix<T, M, M>, &SMatrix<T, M, M>),
) -> Result<O, FilterError>
where
    T: Real,
    Mo: Moments<T, N, M>,
    A: NoiseAdapter<T, M>,
    S: StateSpace<T, N>,
    O: UpdateOutcome<T, M, A::Report>,
{
    // The posterior goes into the spare buffer while the view (what the
    // prior and the split are made of) stays borrowed: no copy of either.
    let (view, spare) = storage.view_and_spare();
    let computed;
    let prior = match view.borrowed() {
        Some(prior) => prior,
        None => {
            computed = view.prior(T::one());
            &computed
        }
    };
    let of = moments.of(prior, x, || Ok(*r_factor))?;
    let nu = moments.innovation(&of)?;

    // Without an adapter the update leaves out every adapter step (nothing
    // to adapt, nothing to copy into a `GainStep`); equal to the general
    // path to rounding, as a test checks.
    if A::IS_IDENTITY {
        let fade = view.total_fade(T::one());
        let report = moments
            .unadapted::<S, A::Report, O>(&of, prior, spare, x, space, (r, r_factor), nu, fade)
            .map_err(|e| moments.diagnose(e))?;
        storage.commit_spare();
        return Ok(report);
    }

    // Borrowed from the result, not moved out of it (a copy of the
    // factorisation a step).
    let nominal = moments.nominal(&of, r);
    let nominal = match &nominal {
        Ok(nominal) => nominal,
        Err(e) => return Err(moments.diagnose(*e)),
    };
    // The split is computed only if an adapter asks (a fading adapter
    // whose test passes never does).
    let parts = || moments.split(&of, &view, prior, r);
    let split: Option<&dyn Fn() -> Parts<T, M>> = if A::NEEDS_SPLIT { Some(&parts) } else { None };
    let (predicted, factor) = moments.nominal_view(&of, nominal);
    let mut step = GainStep::on_form(nu, *predicted, split, *r, factor);
    let done = adapt(adapter, &mut step);
    let fade = done.step.fade_factor();
    if done.step.is_rejected() {
        let report = done.rejected(nu);
        let prior = *prior;
        storage.commit(prior);
        return Ok(report);
    }

    if Mo::CHECKS_BEFORE_REFADE {
        done.check_used()?;
    }
    // Borrowed, not moved: the prior and the moments are kilobytes.
    let mut refaded = None;
    moments.refaded(&of, &view, prior, (fade, &done), x, r_factor, &mut refaded)?;
    let (prior, of) = match &refaded {
        Some((prior, of)) => (prior, of),
        None => (prior, &of),
    };
    if !Mo::CHECKS_BEFORE_REFADE {
        done.check_used()?;
    }
    let fades = (nu, fade, view.total_fade(fade));
    let report = moments.gain(of, prior, spare, x, space, done, fades, r_factor, adapter)?;
    storage.commit_spare();
    Ok(report)
}

/// The fade of the after-predict hook, run once the prediction passed its
/// checks.
#[inline(always)]
pub(crate) fn after_predict<T: Real, A: PriorAdapter<T>>(adapter: &mut A, dt: T) -> T {
    let mut step = PriorStep::new(dt);
    adapter.after_predict(&mut step);
    step.fade_factor()
}
