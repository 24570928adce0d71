use nalgebra::{SMatrix, SVector};

use super::checked_noise::CheckedNoise;
use super::outcome::{adapt, not_pd, unadapted_report};
use super::pending_factor::PendingFactor;
use super::unscented::effective_jacobian;
use super::{FadeStates, Form, PredictForm, UpdateForm};
use crate::adapter::{GainStep, NoiseAdapter, Posterior, PriorAdapter, PriorStep};
use crate::contract::check_covariance;
use crate::error::ensure_finite;
use crate::linalg::{
    add_columns_by_rows, cholesky_semidefinite, downdate_columns_in_place, downdate_in_place,
    lower_times_transpose, mirror_lower, mul_lower, mul_vector, solve_lower, solve_right_cholesky,
    update_in_place, weighted_rank_one_in_place,
};
use crate::real::finite;
use crate::sigma::{self, MeasuredSigma, MerweParams, Pairs, SigmaWeights};
use crate::{
    FilterError, MeasurementModel, ProcessModel, Quantity, Real, StateSpace, UpdateOutcome,
};

/// How the square-root form folds the weighted sigma-point deviations into
/// the covariance factor in its time update.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TimeUpdate {
    /// Householder triangularisation of `[S_Q | √W d₁ … √W d₂ₙ]` (a QR
    /// factorisation exploiting the triangle): about `2N³` multiply-adds.
    #[default]
    Householder,
    /// `2N` Givens rank-one updates of `S_Q`: about `4N³` multiplications.
    RankOne,
}

/// The square-root unscented form (SR-UKF, van der Merwe): carries the lower
/// Cholesky factor `S` of the covariance (`P = S Sᵀ`), so the covariance it
/// represents is positive semi-definite by construction.
///
/// - Time update: sigma points from `S`, the weighted deviations folded into
///   `chol(Q)` by [`TimeUpdate`], the centre point added or (negative
///   weight) removed by a checked rank-one update.
/// - Measurement update: `S_z` from `chol(R)` and the measurement deviations
///   the same way; `K = P_xz S_z⁻ᵀ S_z⁻¹` by two triangular solves;
///   `S⁺` from `S⁻` by one checked rank-one downdate per column of
///   `U = K S_z`. A downdate that would lose positive definiteness returns
///   [`FilterError::DowndateFailed`] and leaves the filter unchanged.
///
/// When the adapter needs the propagated covariance apart from `Q`
/// ([`PriorAdapter::NEEDS_SPLIT`]), the factor of `Q` is kept separately and
/// merged at the update, after any fade `λ` scaled the propagated factor by
/// `√λ`.
///
/// ```
/// use kestrel_core::form::{Form, SquareRootForm};
/// use kestrel_core::nalgebra::Matrix2;
/// let form = SquareRootForm::new(&Matrix2::new(4.0, 2.0, 2.0, 5.0)).unwrap();
/// assert_eq!(form.factor(), Matrix2::new(2.0, 0.0, 1.0, 2.0));
/// ```
///
/// Sources: see the [references](crate::references).
#[derive(Debug, Clone, PartialEq)]
pub struct SquareRootForm<T: Real, const N: usize> {
    /// The factor, with any pending process noise; a step writes the next
    /// one into its spare buffer and makes it current once checked.
    factor: PendingFactor<T, N>,
    /// The after-predict fade already folded into the factor, for the
    /// report.
    predict_fade: T,
    params: MerweParams<T>,
    weights: SigmaWeights<T>,
    time_update: TimeUpdate,
    /// The last `Q` and its factor.
    process_noise: CheckedNoise<T, N>,
    /// The last `R` and its factor.
    measurement_noise: CheckedNoise<T, N>,
}

impl<T: Real, const N: usize> SquareRootForm<T, N> {
    /// A form holding the factor of `p0` (lower triangle used; must be
    /// positive semi-definite) with the default sigma points.
    pub fn new(p0: &SMatrix<T, N, N>) -> Result<Self, FilterError> {
        let params = MerweParams::default();
        let weights = params.weights(N).ok_or(FilterError::InvalidParameter {
            name: "N",
            valid: "at least 1 (a state of dimension 0 has no sigma points)",
        })?;
        let mut form = Self {
            factor: PendingFactor::new(SMatrix::zeros()),
            predict_fade: T::one(),
            params,
            weights,
            time_update: TimeUpdate::default(),
            process_noise: CheckedNoise::new(),
            measurement_noise: CheckedNoise::new(),
        };
        form.set_covariance(p0)?;
        Ok(form)
    }

    /// A form from a lower-triangular factor `s` directly (`P = S Sᵀ`; the
    /// strict upper triangle is ignored).
    pub fn from_factor(s: &SMatrix<T, N, N>) -> Result<Self, FilterError> {
        ensure_finite(s, Quantity::StateCovariance)?;
        let mut form = Self::new(&SMatrix::zeros())?;
        form.commit(s.lower_triangle());
        Ok(form)
    }

    /// The same form with sigma-point parameters `params`.
    pub fn with_params(mut self, params: MerweParams<T>) -> Result<Self, FilterError> {
        self.weights = params.weights(N).ok_or(MerweParams::<T>::INVALID)?;
        self.params = params;
        Ok(self)
    }

    /// The same form with time-update method `method`.
    pub fn with_time_update(mut self, method: TimeUpdate) -> Self {
        self.time_update = method;
        self
    }

    /// The sigma-point parameters.
    pub fn params(&self) -> &MerweParams<T> {
        &self.params
    }

    /// Selects the states an adapter's fade scales (default: all, the
    /// scalar fade): the rows of the selected states of the propagated
    /// factor are scaled by `√λ` (`D S` stays lower-triangular and
    /// `D S Sᵀ D` is the covariance form's `D Φ P Φᵀ D`). See [`FadeStates`].
    ///
    /// ```
    /// use kestrel_core::form::{FadeStates, SquareRootForm};
    /// use kestrel_core::nalgebra::Matrix2;
    /// let mut form = SquareRootForm::new(&Matrix2::<f64>::identity()).unwrap();
    /// form.set_fade_states(FadeStates::range(1..2));
    /// assert!(!form.fade_states().is_all());
    /// ```
    pub fn set_fade_states(&mut self, states: FadeStates<N>) {
        self.factor.set_fade_states(states);
    }

    /// The states a fade scales.
    pub fn fade_states(&self) -> FadeStates<N> {
        self.factor.fade_states()
    }

    /// The lower Cholesky factor `S` of the covariance (with any pending
    /// process noise merged in).
    pub fn factor(&self) -> SMatrix<T, N, N> {
        self.factor.view().merged(T::one())
    }

    /// Makes `s` the factor of the posterior.
    fn commit(&mut self, s: SMatrix<T, N, N>) {
        self.factor.commit(s);
        self.predict_fade = T::one();
    }

    /// Makes the spare buffer, which holds the factor of the posterior,
    /// current.
    fn commit_spare(&mut self) {
        self.factor.commit_spare();
        self.predict_fade = T::one();
    }

    /// Folds `Σ w dᵢ dᵢᵀ` over the pairs into `start`, by the configured method.
    fn fold<const D: usize>(
        method: TimeUpdate,
        start: &mut SMatrix<T, D, D>,
        pairs: &Pairs<T, D, N>,
        sqrt_w: T,
    ) {
        match method {
            TimeUpdate::Householder => {
                // Gathered by rows, scaled on the way (see
                // `add_columns_by_rows`), through plain slices (nalgebra's
                // element iterators are strided and general, an index
                // computation per element).
                let mut rows = [[[T::zero(); N]; 2]; D];
                for (i, [plus, minus]) in pairs.iter().enumerate() {
                    let columns = plus.as_slice().iter().zip(minus.as_slice());
                    for (row, (&plus, &minus)) in rows.iter_mut().zip(columns) {
                        row[0][i] = plus * sqrt_w;
                        row[1][i] = minus * sqrt_w;
                    }
                }
                add_columns_by_rows(start, &mut rows);
            }
            TimeUpdate::RankOne => {
                let mut pairs = *pairs;
                let cols = pairs.as_flattened_mut();
                for c in cols.iter_mut() {
                    *c *= sqrt_w;
                }
                for c in cols.iter_mut() {
                    // Adding a finite PSD term cannot fail; non-finite input
                    // was rejected before.
                    let _ = update_in_place(start, c);
                }
            }
        }
    }

    /// `S_z` with `S_z S_zᵀ = Σ Wc dzⱼ dzⱼᵀ + R`, from `sr = chol(R)`.
    /// (An associated function, so that a step can hold the spare buffer
    /// while it calls it.)
    fn innovation_factor<const M: usize>(
        method: TimeUpdate,
        weights: &SigmaWeights<T>,
        measured: &MeasuredSigma<T, N, M>,
        sr: &SMatrix<T, M, M>,
    ) -> Result<SMatrix<T, M, M>, FilterError> {
        // R may be singular (a perfect measurement) as long as C is not.
        let mut sz = *sr;
        Self::fold(method, &mut sz, &measured.pairs, weights.other.sqrt());
        weighted_rank_one_in_place(&mut sz, &measured.center, weights.cov0)
            .map_err(|e| not_pd(e.index))?;
        // The same singularity test as `cholesky`: a pivot at or below
        // `M·ε` of its column's scale means C is singular to working precision.
        let tol = crate::real::epsilon::<T>() * crate::real::lit::<T>(M as f64);
        for i in 0..M {
            let d = sz[(i, i)];
            let scale = sz.row(i).norm();
            let regular = finite(d) && d > T::zero() && d * d > tol * scale * scale;
            if !regular {
                return Err(not_pd(i));
            }
        }
        Ok(sz)
    }
}

/// The factor of an `R` an adapter set (it may be singular, not indefinite).
fn noise_factor<T: Real, const M: usize>(
    r: &SMatrix<T, M, M>,
) -> Result<SMatrix<T, M, M>, FilterError> {
    cholesky_semidefinite(r).map_err(|e| FilterError::NotPositiveDefinite {
        what: Quantity::MeasurementNoise,
        index: e.index,
    })
}

impl<T: Real, const N: usize> Form<T, N> for SquareRootForm<T, N> {
    fn covariance(&self) -> SMatrix<T, N, N> {
        let s = self.factor();
        let mut p = s * s.transpose();
        mirror_lower(&mut p);
        p
    }

    fn set_covariance(&mut self, p: &SMatrix<T, N, N>) -> Result<(), FilterError> {
        let s = check_covariance(p, Quantity::StateCovariance)?;
        self.commit(s);
        Ok(())
    }
}

impl<T: Real, const N: usize, P: ProcessModel<T, N>> PredictForm<T, N, P> for SquareRootForm<T, N> {
    fn predict<A: PriorAdapter<T>, S: StateSpace<T, N>>(
        &mut self,
        x: &mut SVector<T, N>,
        model: &P,
        dt: T,
        adapter: &mut A,
        space: &S,
    ) -> Result<(), FilterError> {
        let q = model.noise(x, dt);
        // Borrowed from the check's cache: the time update starts from a
        // copy in the spare buffer, where the propagated factor is written
        // and checked before it is made current.
        let sq = self.process_noise.check_full(&q, Quantity::ProcessNoise)?;
        let states = self.factor.fade_states();
        let (view, factor) = self.factor.view_and_spare();
        let mut merged = None;
        let s = view.current(&mut merged);
        let mut propagated = sigma::propagate(x, s, &self.weights, model, dt, space)?;

        let mut step = PriorStep::new(dt);
        adapter.after_predict(&mut step);
        let lambda = step.fade_factor();
        if A::NEEDS_SPLIT {
            factor.fill(T::zero());
        } else {
            *factor = *sq;
        }
        // A block fade scales the selected rows of every deviation; the
        // scalar fade (every state) scales the weights, as it always has.
        let weight = if states.is_all() || lambda == T::one() {
            lambda
        } else {
            let root = lambda.sqrt();
            for d in propagated.pairs.as_flattened_mut() {
                states.scale_vector(d, root);
            }
            states.scale_vector(&mut propagated.center, root);
            T::one()
        };
        Self::fold(
            self.time_update,
            factor,
            &propagated.pairs,
            (self.weights.other * weight).sqrt(),
        );
        weighted_rank_one_in_place(factor, &propagated.center, self.weights.cov0 * weight)
            .map_err(|e| FilterError::DowndateFailed {
                column: 0,
                index: e.index,
            })?;
        ensure_finite(factor, Quantity::PropagatedCovariance)?;

        *x = propagated.mean;
        if A::NEEDS_SPLIT {
            self.factor.predicted_spare(sq);
        } else {
            self.commit_spare();
        }
        self.predict_fade = lambda;
        Ok(())
    }
}

impl<T: Real, const N: usize, H: MeasurementModel<T, N, M>, const M: usize> UpdateForm<T, N, H, M>
    for SquareRootForm<T, N>
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
        let sr = self
            .measurement_noise
            .check(&r, Quantity::MeasurementNoise)?;
        mirror_lower(&mut r);
        let (w, method) = (self.weights, self.time_update);

        let (view, spare) = self.factor.view_and_spare();
        let mut merged = None;
        let prior = view.current(&mut merged);
        let measured = sigma::measure(x, prior, &w, model, space)?;
        let sz = Self::innovation_factor(method, &w, &measured, &sr)?;
        let c = lower_times_transpose(&sz);
        let nu = model.residual(z, &measured.z_hat);
        ensure_finite(&nu, Quantity::Measurement)?;

        if A::IS_IDENTITY {
            // Nothing to adapt: the adapter round left out (equal to it to
            // rounding, as a test checks).
            let x_new = Self::downdate_into(spare, prior, &measured.cross, &sz, &nu, x, space)?;
            let mut white = nu;
            solve_lower(&sz, &mut white);
            *x = x_new;
            let total_fade = self.predict_fade;
            self.commit_spare();
            return Ok(unadapted_report(
                nu,
                &c,
                &r,
                white.norm_squared(),
                total_fade,
            ));
        }

        let prior = *prior;
        let split = A::NEEDS_SPLIT.then(|| {
            effective_jacobian(&prior, &measured.cross)
                .and_then(|h| self.factor.split(&h))
                .unwrap_or((c - r, SMatrix::zeros()))
        });
        let mut step = GainStep::with_factor(nu, c - r, split, r, sz);
        let mut done = adapt(adapter, &mut step);
        let fade = done.step.fade_factor();
        if done.step.is_rejected() {
            self.commit(prior);
            return Ok(done.rejected(nu));
        }

        let (r_used, nu_used) = done.used()?;
        // The factor of the `R` used: the model's, the one an adapter gave
        // with its `R`, or one computed here.
        let used_factor = || {
            done.noise_factor(Some(&sr))
                .map_or_else(|| noise_factor(&r_used), |l| Ok(*l))
        };
        let (prior, measured, sz) = if fade != T::one() {
            let prior = self.factor.view().merged(fade);
            let measured = sigma::measure(x, &prior, &w, model, space)?;
            let sz = Self::innovation_factor(method, &w, &measured, &used_factor()?)?;
            (prior, measured, sz)
        } else if done.step.noise_changed() {
            let sz = Self::innovation_factor(method, &w, &measured, &used_factor()?)?;
            (prior, measured, sz)
        } else {
            (prior, measured, sz)
        };
        let c = lower_times_transpose(&sz);
        let x_new = Self::downdate_into(
            self.factor.spare(),
            &prior,
            &measured.cross,
            &sz,
            &nu_used,
            x,
            space,
        )?;

        *x = x_new;
        let total_fade = self.predict_fade * fade;
        self.commit_spare();
        let predicted = c - r_used;
        let white = done.whitened(&sz);
        adapter.after_update(
            &Posterior::with_whitened(&nu_used, &white, &predicted, &r_used, &sz),
            &mut done.adapters,
        );
        Ok(done.accepted(nu, &c, white.norm_squared(), total_fade))
    }
}

impl<T: Real, const N: usize> SquareRootForm<T, N> {
    /// The measurement update of the factor `prior` and of the state `x`
    /// (not written): `K = P_xz S_z⁻ᵀ S_z⁻¹`, `x⁺ = x ⊞ K ν` (returned) and
    /// `S⁺` (written into `s_new`, garbage on failure) from `S` downdated by
    /// the columns of `K S_z`, each checked.
    fn downdate_into<const M: usize, S: StateSpace<T, N>>(
        s_new: &mut SMatrix<T, N, N>,
        prior: &SMatrix<T, N, N>,
        cross: &SMatrix<T, N, M>,
        sz: &SMatrix<T, M, M>,
        nu_used: &SVector<T, M>,
        x: &SVector<T, N>,
        space: &S,
    ) -> Result<SVector<T, N>, FilterError> {
        // K = P_xz S_z⁻ᵀ S_z⁻¹.
        let mut k = *cross;
        solve_right_cholesky(sz, &mut k);
        let x_new = space.add(x, &mul_vector(&k, nu_used));
        ensure_finite(&x_new, Quantity::UpdatedState)?;
        let u = mul_lower(&k, sz);
        *s_new = *prior;
        let mut work = u;
        if downdate_columns_in_place(s_new, &mut work).is_err() {
            // Which column and pivot failed, as the downdates one after
            // the other report it (the same arithmetic, so they fail too).
            *s_new = *prior;
            for j in 0..M {
                let mut col = u.column(j).into_owned();
                downdate_in_place(s_new, &mut col)
                    .map_err(|index| FilterError::DowndateFailed { column: j, index })?;
            }
        }
        ensure_finite(s_new, Quantity::UpdatedCovariance)?;
        Ok(x_new)
    }
}
