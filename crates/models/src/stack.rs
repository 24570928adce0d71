//! Block composition of process models.

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{LinearizedProcess, ProcessModel, Real};

use crate::sizes::{Size, SumOf};

/// Two independent process models side by side: the state is the
/// concatenation `[x_A; x_B]` of an `NA`-state model `A` and an `NB`-state
/// model `B`, and `Φ`, `Q` are block diagonal. `Stack` implements
/// [`ProcessModel`]`<T, N>` (and [`LinearizedProcess`] when both parts do)
/// for `N = NA + NB` up to 48 states ([`SumOf`](crate::SumOf)); any other
/// `N` is a type error that `cargo check` reports, naming both parts'
/// sizes. Stacks nest:
/// `Stack<Stack<A, B, 2, 2>, C, 4, 1>` is a 5-state model.
///
/// ```
/// use kestrel_models::{ConstantVelocity1d, GaussMarkov, RandomWalk, Stack};
/// use kestrel_core::{LinearizedProcess, ProcessModel, nalgebra::{SVector, Vector1}};
/// // Position/velocity, a random-walk clock bias and a Gauss-Markov drift
/// // whose correlation time halves it every 0.5 s.
/// let cv = ConstantVelocity1d::new(0.1).unwrap();
/// let bias = RandomWalk::new(Vector1::new(4.0)).unwrap();
/// let drift = GaussMarkov::<f64, 1>::uniform(0.5 / core::f64::consts::LN_2, 1.0).unwrap();
/// let model = Stack::<_, _, 3, 1>::new(Stack::new(cv, bias), drift);
/// let x = SVector::<f64, 4>::new(1.0, 2.0, 5.0, 8.0);
/// let want = SVector::<f64, 4>::new(2.0, 2.0, 5.0, 4.0);
/// assert!((model.propagate(&x, 0.5) - want).norm() < 1e-14);
/// let q = model.noise(&x, 0.5);
/// assert_eq!((q[(1, 1)], q[(2, 2)], q[(1, 2)], q[(2, 3)]), (0.05, 2.0, 0.0, 0.0));
/// assert!((q[(3, 3)] - 0.75).abs() < 1e-15);
/// assert_eq!(model.transition(&x, 0.5)[(0, 1)], 0.5);
/// ```
///
/// A size that is not `NA + NB` does not build:
///
/// ```compile_fail,E0277
/// use kestrel_models::{RandomWalk, Stack};
/// use kestrel_core::{ProcessModel, nalgebra::SVector};
/// let s = Stack::<_, _, 2, 1>::new(RandomWalk::<f64, 2>::uniform(1.0).unwrap(), RandomWalk::<f64, 1>::uniform(1.0).unwrap());
/// let x = SVector::<f64, 4>::zeros(); // 2 + 1 ≠ 4
/// let _ = s.propagate(&x, 1.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stack<A, B, const NA: usize, const NB: usize> {
    /// The model of the leading `NA` states.
    pub first: A,
    /// The model of the trailing `NB` states.
    pub second: B,
}

impl<A, B, const NA: usize, const NB: usize> Stack<A, B, NA, NB> {
    /// `first` on states `0..NA`, `second` on `NA..NA + NB`. The sizes are
    /// inferred when each part implements [`ProcessModel`] for a single size
    /// (all models of this crate, but not a nested `Stack`: write those as
    /// `Stack::<_, _, NA, NB>::new`).
    pub fn new<T: Real>(first: A, second: B) -> Self
    where
        A: ProcessModel<T, NA>,
        B: ProcessModel<T, NB>,
    {
        Self { first, second }
    }
}

/// `[a; b]`.
fn concat<T: Real, const NA: usize, const NB: usize, const N: usize>(
    a: &SVector<T, NA>,
    b: &SVector<T, NB>,
) -> SVector<T, N> {
    let mut out = SVector::<T, N>::zeros();
    out.fixed_rows_mut::<NA>(0).copy_from(a);
    out.fixed_rows_mut::<NB>(NA).copy_from(b);
    out
}

/// `diag(a, b)`.
fn block_diag<T: Real, const NA: usize, const NB: usize, const N: usize>(
    a: &SMatrix<T, NA, NA>,
    b: &SMatrix<T, NB, NB>,
) -> SMatrix<T, N, N> {
    let mut out = SMatrix::<T, N, N>::zeros();
    out.fixed_view_mut::<NA, NA>(0, 0).copy_from(a);
    out.fixed_view_mut::<NB, NB>(NA, NA).copy_from(b);
    out
}

impl<A, B, const NA: usize, const NB: usize> Stack<A, B, NA, NB> {
    /// The parts of `x`: `(x[..NA], x[NA..])`.
    fn split<T: Real, const N: usize>(x: &SVector<T, N>) -> (SVector<T, NA>, SVector<T, NB>) {
        (
            x.fixed_rows::<NA>(0).into_owned(),
            x.fixed_rows::<NB>(NA).into_owned(),
        )
    }
}

impl<T, A, B, const NA: usize, const NB: usize, const N: usize> ProcessModel<T, N>
    for Stack<A, B, NA, NB>
where
    T: Real,
    A: ProcessModel<T, NA>,
    B: ProcessModel<T, NB>,
    Size<N>: SumOf<NA, NB>,
{
    fn propagate(&self, x: &SVector<T, N>, dt: T) -> SVector<T, N> {
        let (xa, xb) = Self::split(x);
        concat(
            &self.first.propagate(&xa, dt),
            &self.second.propagate(&xb, dt),
        )
    }

    fn noise(&self, x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        let (xa, xb) = Self::split(x);
        block_diag(&self.first.noise(&xa, dt), &self.second.noise(&xb, dt))
    }
}

impl<T, A, B, const NA: usize, const NB: usize, const N: usize> LinearizedProcess<T, N>
    for Stack<A, B, NA, NB>
where
    T: Real,
    A: LinearizedProcess<T, NA>,
    B: LinearizedProcess<T, NB>,
    Size<N>: SumOf<NA, NB>,
{
    fn transition(&self, x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        let (xa, xb) = Self::split(x);
        block_diag(
            &self.first.transition(&xa, dt),
            &self.second.transition(&xb, dt),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ConstantAcceleration1d, ConstantVelocity2d, GaussMarkov, RandomWalk};
    use kestrel_core::nalgebra::{Matrix3, SVector, Vector1, Vector2};

    /// CV (2 axes) + GM (2 states) + RW (1): a 7-state nested stack.
    #[test]
    fn nested_blocks() {
        let cv = ConstantVelocity2d::new(2.0).unwrap();
        let gm = GaussMarkov::new(Vector2::new(1.0, 2.0), Vector2::new(0.5, 1.5)).unwrap();
        let rw = RandomWalk::new(Vector1::new(3.0)).unwrap();
        let m = Stack::<_, _, 6, 1>::new(Stack::new(cv, gm), rw);
        let x = SVector::<f64, 7>::from_fn(|i, _| i as f64 + 1.0);
        let dt = 0.4;
        let (xa, xb) = (
            x.fixed_rows::<4>(0).into_owned(),
            x.fixed_rows::<2>(4).into_owned(),
        );
        let want: SVector<f64, 7> = concat(
            &concat::<f64, 4, 2, 6>(&cv.propagate(&xa, dt), &gm.propagate(&xb, dt)),
            &Vector1::new(7.0),
        );
        assert_eq!(m.propagate(&x, dt), want);
        let q = m.noise(&x, dt);
        let phi = m.transition(&x, dt);
        assert_eq!(q.fixed_view::<4, 4>(0, 0), cv.noise(&xa, dt));
        assert_eq!(q.fixed_view::<2, 2>(4, 4), gm.noise(&xb, dt));
        assert_eq!(q[(6, 6)], 3.0 * dt);
        assert_eq!(phi.fixed_view::<4, 4>(0, 0), cv.transition(&xa, dt));
        assert_eq!(phi.fixed_view::<2, 2>(4, 4), gm.transition(&xb, dt));
        assert_eq!(phi[(6, 6)], 1.0);
        // Nothing outside the diagonal blocks.
        for (i, j) in [(0, 4), (5, 0), (3, 6), (6, 5), (4, 5)] {
            assert_eq!((q[(i, j)], phi[(i, j)]), (0.0, 0.0), "({i}, {j})");
        }
        assert_eq!(phi * x, m.propagate(&x, dt));
    }

    #[test]
    fn inferred_sizes_and_f32() {
        let m = Stack::new(
            ConstantAcceleration1d::new(1.0_f32).unwrap(),
            RandomWalk::<f32, 1>::uniform(2.0).unwrap(),
        );
        let x = SVector::<f32, 4>::new(0.0, 1.0, 2.0, 3.0);
        assert_eq!(
            m.propagate(&x, 1.0),
            SVector::<f32, 4>::new(2.0, 3.0, 2.0, 3.0)
        );
        let q = m.noise(&x, 1.0);
        assert_eq!(
            q.fixed_view::<3, 3>(0, 0),
            ConstantAcceleration1d::new(1.0_f32)
                .unwrap()
                .noise(&x.fixed_rows::<3>(0).into_owned(), 1.0)
        );
        assert_eq!(q[(3, 3)], 2.0);
        assert_eq!(
            q.fixed_view::<3, 1>(0, 3),
            Matrix3::<f32>::zeros().fixed_view::<3, 1>(0, 0)
        );
    }
}
