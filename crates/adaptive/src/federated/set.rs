//! Collections of local filters: tuples of different filter types (2 to 6)
//! and arrays of one type, reached by index without dynamic dispatch.

use kestrel_core::adapter::PriorAdapter;
use kestrel_core::form::PredictForm;
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{Filter, FilterError, Real, StateSpace};

use super::{FusionError, LocalFilter, SharedNoise};

/// `L` local filters of the common `N`-state, by index `0..L`. Implemented
/// for tuples of two to six [`LocalFilter`]s of any types and for arrays
/// `[F; L]`. Indices at or beyond `L` give `None` or
/// [`FusionError::NoSuchLocal`].
///
/// ```
/// use kestrel_adaptive::federated::LocalSet;
/// use kestrel_core::{Ekf, SrUkf, nalgebra::{Matrix1, Vector1}};
/// let set = (
///     Ekf::new(Vector1::new(1.0), Matrix1::new(2.0)).unwrap(),
///     SrUkf::new(Vector1::new(3.0), Matrix1::new(4.0)).unwrap(),
/// );
/// let (x, p) = LocalSet::<f64, 1, 2>::estimate(&set, 1).unwrap();
/// assert_eq!((x[0], p[0]), (3.0, 4.0));
/// assert!(LocalSet::<f64, 1, 2>::estimate(&set, 2).is_none());
/// ```
pub trait LocalSet<T: Real, const N: usize, const L: usize> {
    /// Local `local`'s estimate and covariance.
    fn estimate(&self, local: usize) -> Option<(SVector<T, N>, SMatrix<T, N, N>)>;

    /// `x ⊟ reference` in local `local`'s state arithmetic.
    fn deviation(
        &self,
        local: usize,
        x: &SVector<T, N>,
        reference: &SVector<T, N>,
    ) -> Option<SVector<T, N>>;

    /// `x ⊞ dx` in local `local`'s state arithmetic.
    fn moved(&self, local: usize, x: &SVector<T, N>, dx: &SVector<T, N>) -> Option<SVector<T, N>>;

    /// Resets local `local` to `x` with covariance `p`.
    fn reset(
        &mut self,
        local: usize,
        x: &SVector<T, N>,
        p: &SMatrix<T, N, N>,
    ) -> Result<(), FusionError>;
}

/// A local filter that can predict with process model `P` under its share
/// of the process noise ([`SharedNoise`]). Implemented for every [`Filter`]
/// whose form predicts with `SharedNoise<P>` (the covariance form needs a
/// [`LinearizedProcess`](kestrel_core::LinearizedProcess) `P`).
///
/// ```
/// use kestrel_adaptive::federated::{PredictLocal, SharedNoise};
/// use kestrel_core::{Ukf, nalgebra::{Matrix1, Vector1}};
/// use kestrel_models::LinearProcess;
/// let model = LinearProcess::new(Matrix1::new(1.0_f64), Matrix1::new(0.5));
/// let mut f = Ukf::new(Vector1::new(0.0), Matrix1::new(1.0)).unwrap();
/// f.predict_shared(&SharedNoise::new(&model, 0.5).unwrap(), 1.0).unwrap();
/// assert!((f.covariance()[0] - 2.0).abs() < 1e-12); // 1 + 0.5 / 0.5
/// ```
pub trait PredictLocal<'m, T: Real, const N: usize, P> {
    /// Predicts over `dt` with `model` (noise `Q / β`).
    fn predict_shared(&mut self, model: &SharedNoise<'m, T, P>, dt: T) -> Result<(), FilterError>;
}

impl<'m, T, const N: usize, F, A, S, P> PredictLocal<'m, T, N, P> for Filter<T, N, F, A, S>
where
    T: Real,
    P: 'm,
    F: PredictForm<T, N, SharedNoise<'m, T, P>>,
    A: PriorAdapter<T>,
    S: StateSpace<T, N>,
{
    fn predict_shared(&mut self, model: &SharedNoise<'m, T, P>, dt: T) -> Result<(), FilterError> {
        self.predict(model, dt)
    }
}

/// A [`LocalSet`] whose every local predicts with process model `P`.
///
/// ```
/// use kestrel_adaptive::federated::PredictSet;
/// use kestrel_core::{Ekf, SrUkf, nalgebra::{Matrix1, Vector1}};
/// use kestrel_models::LinearProcess;
/// let model = LinearProcess::new(Matrix1::new(1.0_f64), Matrix1::new(0.5));
/// let mut set = (
///     Ekf::new(Vector1::new(0.0), Matrix1::new(1.0)).unwrap(),
///     SrUkf::new(Vector1::new(0.0), Matrix1::new(1.0)).unwrap(),
/// );
/// set.predict_each(&model, &[0.25, 1.0], 1.0).unwrap();
/// assert!((set.0.covariance()[0] - 3.0).abs() < 1e-12); // 1 + 0.5 / 0.25
/// assert!((set.1.covariance()[0] - 1.5).abs() < 1e-12); // 1 + 0.5
/// ```
pub trait PredictSet<'m, T: Real, const N: usize, const L: usize, P>: LocalSet<T, N, L> {
    /// Predicts local `i` over `dt` with `model`, its noise divided by
    /// `shares[i]`, in index order. Stops at the first failure, naming the
    /// local (the locals before it have been predicted).
    fn predict_each(&mut self, model: &'m P, shares: &[T; L], dt: T) -> Result<(), FusionError>;
}

fn shared<'m, T: Real, P>(
    model: &'m P,
    local: usize,
    share: T,
) -> Result<SharedNoise<'m, T, P>, FusionError> {
    SharedNoise::new(model, share).map_err(|error| FusionError::Local { local, error })
}

fn local_error(local: usize) -> impl Fn(FilterError) -> FusionError {
    move |error| FusionError::Local { local, error }
}

/// `Some` of `$call` on tuple element `local` (bound to `$f`), `None` past
/// the last of the indices `$idx`: a tuple's elements differ in type, so
/// each index is its own match arm.
macro_rules! at_index {
    ($tuple:expr, $local:expr, |$f:ident| $call:expr; $($idx:tt)+) => {
        match $local {
            $($idx => {
                let $f = &$tuple.$idx;
                Some($call)
            })+
            _ => None,
        }
    };
}

macro_rules! tuple_set {
    ($count:literal; $($name:ident $idx:tt),+) => {
        impl<T: Real, const N: usize, $($name: LocalFilter<T, N>),+> LocalSet<T, N, $count>
            for ($($name,)+)
        {
            fn estimate(&self, local: usize) -> Option<(SVector<T, N>, SMatrix<T, N, N>)> {
                at_index!(self, local, |f| f.estimate(); $($idx)+)
            }

            fn deviation(
                &self,
                local: usize,
                x: &SVector<T, N>,
                reference: &SVector<T, N>,
            ) -> Option<SVector<T, N>> {
                at_index!(self, local, |f| f.deviation(x, reference); $($idx)+)
            }

            fn moved(
                &self,
                local: usize,
                x: &SVector<T, N>,
                dx: &SVector<T, N>,
            ) -> Option<SVector<T, N>> {
                at_index!(self, local, |f| f.moved(x, dx); $($idx)+)
            }

            fn reset(
                &mut self,
                local: usize,
                x: &SVector<T, N>,
                p: &SMatrix<T, N, N>,
            ) -> Result<(), FusionError> {
                match local {
                    $($idx => self.$idx.reset(x, p).map_err(local_error(local)),)+
                    _ => Err(FusionError::NoSuchLocal { local }),
                }
            }
        }

        impl<'m, T: Real, const N: usize, P, $($name),+> PredictSet<'m, T, N, $count, P>
            for ($($name,)+)
        where
            $($name: LocalFilter<T, N> + PredictLocal<'m, T, N, P>),+
        {
            fn predict_each(
                &mut self,
                model: &'m P,
                shares: &[T; $count],
                dt: T,
            ) -> Result<(), FusionError> {
                $(
                    self.$idx
                        .predict_shared(&shared(model, $idx, shares[$idx])?, dt)
                        .map_err(local_error($idx))?;
                )+
                Ok(())
            }
        }
    };
}

tuple_set!(2; A 0, B 1);
tuple_set!(3; A 0, B 1, C 2);
tuple_set!(4; A 0, B 1, C 2, D 3);
tuple_set!(5; A 0, B 1, C 2, D 3, E 4);
tuple_set!(6; A 0, B 1, C 2, D 3, E 4, F 5);

impl<T: Real, const N: usize, F: LocalFilter<T, N>, const L: usize> LocalSet<T, N, L> for [F; L] {
    fn estimate(&self, local: usize) -> Option<(SVector<T, N>, SMatrix<T, N, N>)> {
        self.get(local).map(LocalFilter::estimate)
    }

    fn deviation(
        &self,
        local: usize,
        x: &SVector<T, N>,
        reference: &SVector<T, N>,
    ) -> Option<SVector<T, N>> {
        self.get(local).map(|f| f.deviation(x, reference))
    }

    fn moved(&self, local: usize, x: &SVector<T, N>, dx: &SVector<T, N>) -> Option<SVector<T, N>> {
        self.get(local).map(|f| f.moved(x, dx))
    }

    fn reset(
        &mut self,
        local: usize,
        x: &SVector<T, N>,
        p: &SMatrix<T, N, N>,
    ) -> Result<(), FusionError> {
        match self.get_mut(local) {
            Some(f) => f.reset(x, p).map_err(local_error(local)),
            None => Err(FusionError::NoSuchLocal { local }),
        }
    }
}

impl<'m, T: Real, const N: usize, P, F, const L: usize> PredictSet<'m, T, N, L, P> for [F; L]
where
    F: LocalFilter<T, N> + PredictLocal<'m, T, N, P>,
{
    fn predict_each(&mut self, model: &'m P, shares: &[T; L], dt: T) -> Result<(), FusionError> {
        for (i, (f, &share)) in self.iter_mut().zip(shares).enumerate() {
            f.predict_shared(&shared(model, i, share)?, dt)
                .map_err(local_error(i))?;
        }
        Ok(())
    }
}
