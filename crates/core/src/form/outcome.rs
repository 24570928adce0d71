//! The adapter round shared by every form: build the measurement-space
//! view, run `before_gain`, and assemble the report.

use nalgebra::{SMatrix, SVector};

use super::pending::PendingCovariance;
use crate::adapter::{GainStep, NoiseAdapter};
use crate::error::ensure_finite;
use crate::linalg::{
    cholesky_semidefinite, joseph_expanded, joseph_factored_noise_negated, solve_lower, Ldl,
};
use crate::{FilterError, Quantity, Real, StateSpace, UpdateOutcome, UpdateReport};

/// The state correction `K ν` from the negated gain `−K` (an exact sign
/// change of `(−K) ν`).
#[inline(always)]
fn correction<T: Real, const N: usize, const M: usize>(
    negated_k: &SMatrix<T, N, M>,
    innovation: &SVector<T, M>,
) -> SVector<T, N> {
    -(negated_k * innovation)
}

/// The expanded Joseph update of `prior` into `covariance` for the gain
/// `−K` already formed, the cross covariance `b` (`P⁻ Hᵀ` or `P_xz`), the
/// predicted measurement covariance `predicted` (`H P⁻ Hᵀ` or `P_zz`), the
/// noise `noise` (with its lower Cholesky factor `noise_factor` when the
/// caller has it) and `c = predicted + noise`.
///
/// `R` enters the covariance through its factor
/// ([`joseph_factored_noise`](crate::linalg::joseph_factored_noise)):
/// through `C`, the rounding of `K C Kᵀ` can make the posterior indefinite
/// when `C` is badly conditioned (an estimated `R` in `f32`). An `R`
/// without a semi-definite factor is not a covariance; it keeps
/// [`joseph_expanded`] with `C`.
#[allow(clippy::too_many_arguments)]
#[inline]
fn joseph_with_gain<T: Real, const N: usize, const M: usize>(
    covariance: &mut SMatrix<T, N, N>,
    prior: &SMatrix<T, N, N>,
    negated_k: &SMatrix<T, N, M>,
    b: &SMatrix<T, N, M>,
    predicted: &SMatrix<T, M, M>,
    noise: &SMatrix<T, M, M>,
    noise_factor: Option<&SMatrix<T, M, M>>,
    c: &SMatrix<T, M, M>,
) -> Result<(), FilterError> {
    match noise_factor {
        Some(l) => joseph_factored_noise_negated(covariance, prior, negated_k, b, predicted, l),
        // An R an adapter set: factor it here.
        None => match cholesky_semidefinite(noise) {
            Ok(l) => joseph_factored_noise_negated(covariance, prior, negated_k, b, predicted, &l),
            Err(_) => *covariance = joseph_expanded(prior, &-negated_k, b, c),
        },
    }
    ensure_finite(covariance, Quantity::UpdatedCovariance)
}

/// The update without adapters, for the cross covariance `B = P⁻ Hᵀ` (or
/// `P_xz`), the predicted measurement covariance
/// `predicted` (`H P⁻ Hᵀ` or `P_zz`), `R` with its lower Cholesky factor
/// and the innovation: the Joseph update of `prior` into the spare buffer
/// of `cov`, made current once it and the updated `x` are checked, and the
/// report (nothing adapted).
///
/// No adapter reads a factor of `C` here, so `C` is factored without square
/// roots ([`Ldl`]): on the chain from one covariance to the next they
/// would set the pace at small sizes.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn unadapted_update<T, const N: usize, const M: usize, R: Default, S, O>(
    cov: &mut PendingCovariance<T, N>,
    x: &mut SVector<T, N>,
    space: &S,
    prior: &SMatrix<T, N, N>,
    cross: &SMatrix<T, N, M>,
    predicted: &SMatrix<T, M, M>,
    (noise, noise_factor): (SMatrix<T, M, M>, &SMatrix<T, M, M>),
    innovation: SVector<T, M>,
) -> Result<O, FilterError>
where
    T: Real,
    S: StateSpace<T, N>,
    O: UpdateOutcome<T, M, R>,
{
    let c = predicted + noise;
    let ldl = Ldl::new(&c).map_err(|e| not_pd(e.index))?;
    let nis = ldl.quadratic_form(&innovation);
    let negated_k = negated_gain_on_ldl(&ldl, cross);
    // Written out, not through a helper shared with `joseph_gain_on_ldl`:
    // through one the compiler inlines the Joseph update differently, and
    // at 15 states its tile loops spill their accumulators to the stack
    // (docs/notes/forms-driver.md).
    let spare = cov.spare();
    joseph_with_gain(
        spare,
        prior,
        &negated_k,
        cross,
        predicted,
        &noise,
        Some(noise_factor),
        &c,
    )?;
    let x_new = space.add(x, &correction(&negated_k, &innovation));
    ensure_finite(&x_new, Quantity::UpdatedState)?;
    *x = x_new;
    let fade = cov.total_fade(T::one());
    cov.commit_spare();
    Ok(unadapted_report(innovation, &c, &noise, nis, fade))
}

/// `−K = −B C⁻¹` on the `L D Lᵀ` of `C`, for `B = P⁻ Hᵀ`: the gain of the
/// update without adapters.
#[inline(always)]
fn negated_gain_on_ldl<T: Real, const N: usize, const M: usize>(
    ldl: &Ldl<T, M>,
    cross: &SMatrix<T, N, M>,
) -> SMatrix<T, N, M> {
    // The same gain bit for bit either way. The right-hand solves work down
    // the columns of `K`, which vectorises when they are longer than its
    // rows; where `N = M` the solves down the rows of `Kᵀ` are the
    // cheaper.
    if const { N > M } {
        let mut negated_k = SMatrix::from_fn(|i, j| -cross[(i, j)]);
        ldl.solve_right_in_place(&mut negated_k);
        negated_k
    } else {
        let mut kt = cross.transpose();
        ldl.solve_in_place(&mut kt);
        SMatrix::from_fn(|i, j| -kt[(j, i)])
    }
}

/// The update after the adapters: the gain `K = B C⁻¹` on the `L D Lᵀ`
/// of `C` and the Joseph update of `prior` into `covariance` (see
/// [`joseph_with_gain`]) for the cross covariance `B`, the predicted
/// measurement covariance, the noise used (with its factor when known) and
/// `C`. Returns the state correction `K ν` for the innovation used: the
/// gain itself stays here (moved out by value, its `N M` elements would be
/// copied twice a step). In an epoch the adapters left as they were, this
/// is the arithmetic of the update without them on the same factorisation,
/// so its result bit for bit.
///
/// Not inlined: a second copy of the Joseph update in every adapted update
/// would change how the compiler inlines the update without adapters, and
/// make that update the slower.
#[inline(never)]
pub(crate) fn joseph_gain_on_ldl<T: Real, const N: usize, const M: usize>(
    covariance: &mut SMatrix<T, N, N>,
    (prior, cross, predicted): (&SMatrix<T, N, N>, &SMatrix<T, N, M>, &SMatrix<T, M, M>),
    (noise, noise_factor, c): (
        &SMatrix<T, M, M>,
        Option<&SMatrix<T, M, M>>,
        &SMatrix<T, M, M>,
    ),
    ldl: &Ldl<T, M>,
    innovation: &SVector<T, M>,
) -> Result<SVector<T, N>, FilterError> {
    let negated_k = negated_gain_on_ldl(ldl, cross);
    joseph_with_gain(
        covariance,
        prior,
        &negated_k,
        cross,
        predicted,
        noise,
        noise_factor,
        c,
    )?;
    Ok(correction(&negated_k, innovation))
}

/// The outcome of an update without adapters: nothing adapted, so the
/// innovation and its covariance are the nominal ones.
#[inline(always)]
pub(crate) fn unadapted_report<T: Real, const M: usize, R: Default, O: UpdateOutcome<T, M, R>>(
    innovation: SVector<T, M>,
    c: &SMatrix<T, M, M>,
    noise: &SMatrix<T, M, M>,
    nis: T,
    fade: T,
) -> O {
    let report = UpdateReport {
        innovation,
        innovation_used: innovation,
        nis,
        adapted_nis: nis,
        fade,
        rejected: false,
        sequential: false,
        adapters: R::default(),
    };
    O::assemble(report, c, c, noise)
}

/// The `L D Lᵀ` of `C` the gain takes after the adapters and the NIS of
/// the innovation used: the view's when nothing faded (the nominal one if
/// the adapters kept `R`), else that of `c` (the form's `C` from the faded
/// prior), factored into `fresh`.
#[inline(always)]
pub(crate) fn used_factorisation<'f, T: Real, const M: usize>(
    step: &'f GainStep<'_, T, M>,
    fade: T,
    c: &SMatrix<T, M, M>,
    fresh: &'f mut Option<Ldl<T, M>>,
) -> Result<(&'f Ldl<T, M>, T), FilterError> {
    if let Some(used) = step.used_factorisation(fade) {
        return Ok(used);
    }
    let ldl = fresh.insert(Ldl::new(c).map_err(|e| not_pd(e.index))?);
    Ok((ldl, ldl.quadratic_form(step.innovation())))
}

/// The state of an update after the adapters' `before_gain`.
pub(crate) struct AdaptedStep<'s, 'a, T: Real, const M: usize, R> {
    /// The view the adapters left, where the form built it.
    pub step: &'s mut GainStep<'a, T, M>,
    pub nis: T,
    pub adapters: R,
}

pub(crate) fn not_pd(index: usize) -> FilterError {
    FilterError::NotPositiveDefinite {
        what: Quantity::InnovationCovariance,
        index,
    }
}

/// The `L D Lᵀ` factorisation of `H P⁻ Hᵀ + R` as the model gives them:
/// the check that the nominal innovation covariance is positive definite,
/// before any adapter runs, failing with the pivot index (that of
/// [`cholesky`]). The view takes its NIS from it, and derives the Cholesky
/// factor from it only if an adapter asks before replacing `R`.
#[inline(always)]
pub(crate) fn nominal_ldl<T: Real, const M: usize>(
    predicted: &SMatrix<T, M, M>,
    noise: &SMatrix<T, M, M>,
) -> Result<Ldl<T, M>, FilterError> {
    Ldl::new(&(predicted + noise)).map_err(|e| not_pd(e.index))
}

/// Runs the adapters on a freshly built view, in place (the view is a few
/// KB: it stays where the form built it).
#[inline(always)]
pub(crate) fn adapt<'s, 'a, T: Real, const M: usize, A: NoiseAdapter<T, M>>(
    adapter: &mut A,
    step: &'s mut GainStep<'a, T, M>,
) -> AdaptedStep<'s, 'a, T, M, A::Report> {
    let nis = step.mahalanobis().unwrap_or_else(T::zero);
    let mut adapters = A::Report::default();
    adapter.before_gain(step, &mut adapters);
    AdaptedStep {
        step,
        nis,
        adapters,
    }
}

impl<T: Real, const M: usize, R> AdaptedStep<'_, '_, T, M, R> {
    /// The noise and innovation the adapters settled on, checked finite.
    #[inline(always)]
    pub fn used(&self) -> Result<(SMatrix<T, M, M>, SVector<T, M>), FilterError> {
        self.check_used()?;
        Ok((*self.step.noise(), *self.step.innovation()))
    }

    /// The lower factor of the `R` the adapters settled on, when one is
    /// known: the model's (`model`) if no adapter replaced `R`, else the one
    /// an adapter gave with it ([`GainStep::set_noise_factor`]).
    #[inline(always)]
    pub fn noise_factor<'f>(
        &'f self,
        model: Option<&'f SMatrix<T, M, M>>,
    ) -> Option<&'f SMatrix<T, M, M>> {
        if self.step.noise_changed() {
            self.step.noise_factor()
        } else {
            model
        }
    }

    /// Checks that the noise and innovation the adapters settled on
    /// (`step.noise()`, `step.innovation()`, read by reference) are finite.
    /// The model's `R` the form has checked already.
    #[inline(always)]
    pub fn check_used(&self) -> Result<(), FilterError> {
        if self.step.noise_changed() {
            ensure_finite(self.step.noise(), Quantity::MeasurementNoise)?;
        }
        ensure_finite(self.step.innovation(), Quantity::Measurement)
    }

    /// The outcome of a measurement an adapter rejected.
    #[inline(always)]
    pub fn rejected<O: UpdateOutcome<T, M, R>>(self, innovation: SVector<T, M>) -> O {
        let report = UpdateReport {
            innovation,
            innovation_used: *self.step.innovation(),
            nis: self.nis,
            adapted_nis: self.step.mahalanobis().unwrap_or_else(T::zero),
            fade: T::one(),
            rejected: true,
            sequential: false,
            adapters: self.adapters,
        };
        O::assemble(
            report,
            &self.step.nominal_innovation_covariance(),
            self.step.innovation_covariance(),
            self.step.noise(),
        )
    }

    /// `L⁻¹ ν` of the innovation used, for `C = L Lᵀ`: the view's own when
    /// the view holds `l` already (the square-root form's factor, `C` left
    /// as it was), so the solve an adapter's test made is not made again.
    #[inline(always)]
    pub fn whitened(&self, l: &SMatrix<T, M, M>) -> SVector<T, M> {
        if self.step.formed_factor() == Some(l)
            && let Some(w) = self.step.whitened_innovation()
        {
            return w;
        }
        let mut white = *self.step.innovation();
        solve_lower(l, &mut white);
        white
    }

    /// The outcome of an accepted update with innovation covariance `c`,
    /// the adapted NIS (`|L⁻¹ ν|²`, see [`whitened`](Self::whitened)) and
    /// total fade `fade`.
    #[inline(always)]
    pub fn accepted<O: UpdateOutcome<T, M, R>>(
        self,
        innovation: SVector<T, M>,
        c: &SMatrix<T, M, M>,
        adapted_nis: T,
        fade: T,
    ) -> O {
        let report = UpdateReport {
            innovation,
            innovation_used: *self.step.innovation(),
            nis: self.nis,
            adapted_nis,
            fade,
            rejected: false,
            sequential: false,
            adapters: self.adapters,
        };
        O::assemble(
            report,
            &self.step.nominal_innovation_covariance(),
            c,
            self.step.noise(),
        )
    }
}
