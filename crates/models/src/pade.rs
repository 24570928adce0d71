//! Padé approximants of the exponential with scaling (Higham 2005), generic
//! over the matrix algebra so the same code serves full `N × N` matrices and
//! the block upper-triangular matrices of Van Loan's method.

use core::ops::{Add, Mul, Sub};

use kestrel_core::nalgebra::SMatrix;
use kestrel_core::real::{epsilon, lit};
use kestrel_core::Real;

use crate::lu::Lu;

/// A unital algebra of square matrices with what the Padé evaluation needs.
pub(crate) trait SquareAlgebra<T: Real>:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Mul<T, Output = Self>
{
    /// The multiplicative identity.
    fn identity() -> Self;
    /// The induced 1-norm (largest absolute column sum).
    fn norm1(&self) -> T;
    /// Whether every element is finite.
    fn is_finite(&self) -> bool;
    /// `self⁻¹ rhs`, or `None` if `self` is singular.
    fn solve(&self, rhs: &Self) -> Option<Self>;
}

impl<T: Real, const N: usize> SquareAlgebra<T> for SMatrix<T, N, N> {
    fn identity() -> Self {
        SMatrix::identity()
    }
    fn norm1(&self) -> T {
        column_sums(self).iter().fold(T::zero(), |m, &s| m.max(s))
    }
    fn is_finite(&self) -> bool {
        self.iter().all(|v| v.is_finite())
    }
    fn solve(&self, rhs: &Self) -> Option<Self> {
        Some(Lu::new(self)?.solve(rhs))
    }
}

/// The absolute column sums of `a`.
pub(crate) fn column_sums<T: Real, const N: usize>(a: &SMatrix<T, N, N>) -> [T; N] {
    core::array::from_fn(|j| a.column(j).iter().fold(T::zero(), |s, v| s + v.abs()))
}

/// Numerator coefficients `b₀ … b_m` of the diagonal Padé approximants.
const B3: [f64; 4] = [120.0, 60.0, 12.0, 1.0];
const B5: [f64; 6] = [30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0];
const B7: [f64; 8] = [
    17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0,
];
const B9: [f64; 10] = [
    17643225600.0,
    8821612800.0,
    2075673600.0,
    302702400.0,
    30270240.0,
    2162160.0,
    110880.0,
    3960.0,
    90.0,
    1.0,
];
const B13: [f64; 14] = [
    64764752532480000.0,
    32382376266240000.0,
    7771770303897600.0,
    1187353796428800.0,
    129060195264000.0,
    10559470521600.0,
    670442572800.0,
    33522128640.0,
    1323241920.0,
    40840800.0,
    960960.0,
    16380.0,
    182.0,
    1.0,
];

/// Largest 1-norms for which degree 3, 5, 7, 9, 13 keeps the backward error
/// below the unit roundoff of `f64` (Higham 2005, table 2.3).
const THETA_DOUBLE: [(usize, f64); 5] = [
    (3, 1.495585217958292e-2),
    (5, 2.53939833006323e-1),
    (7, 9.504178996162932e-1),
    (9, 2.097847961257068),
    (13, 5.371920351148152),
];
/// The same for `f32`, where degree 7 is the most economical top degree.
const THETA_SINGLE: [(usize, f64); 3] = [
    (3, 4.258730016922831e-1),
    (5, 1.880152677804762),
    (7, 3.92572478313866),
];

/// The Padé approximant `r_m(A / 2ˢ)` and the number of squarings `s` that
/// recover `e^A`, or `None` if `a` is not finite or the denominator is
/// singular (impossible in exact arithmetic within the θ bounds).
pub(crate) fn scaled_pade<T: Real, A: SquareAlgebra<T>>(a: &A) -> Option<(A, u32)> {
    if !a.is_finite() {
        return None;
    }
    let norm = a.norm1();
    let table: &[(usize, f64)] = if epsilon::<T>() > lit(1e-10) {
        &THETA_SINGLE
    } else {
        &THETA_DOUBLE
    };
    if let Some(&(m, _)) = table.iter().find(|(_, theta)| norm <= lit(*theta)) {
        return pade(a, m).map(|r| (r, 0));
    }
    let (m, theta) = table[table.len() - 1];
    // Halve until within θ; finite norms stop after at most ~1030 steps.
    let (mut scaled_norm, mut factor, mut s) = (norm, T::one(), 0u32);
    let half: T = lit(0.5);
    while scaled_norm > lit(theta) {
        scaled_norm *= half;
        factor *= half;
        s += 1;
    }
    pade(&(*a * factor), m).map(|r| (r, s))
}

/// `r_m(a) = (V − U)⁻¹ (V + U)` with `U` the odd and `V` the even part.
fn pade<T: Real, A: SquareAlgebra<T>>(a: &A, m: usize) -> Option<A> {
    let id = A::identity();
    let a2 = *a * *a;
    let c = |b: f64| -> T { lit(b) };
    let (u, v) = if m == 13 {
        let b = &B13;
        let a4 = a2 * a2;
        let a6 = a4 * a2;
        let inner_u = a6 * (a6 * c(b[13]) + a4 * c(b[11]) + a2 * c(b[9]));
        let u = *a * (inner_u + a6 * c(b[7]) + a4 * c(b[5]) + a2 * c(b[3]) + id * c(b[1]));
        let inner_v = a6 * (a6 * c(b[12]) + a4 * c(b[10]) + a2 * c(b[8]));
        let v = inner_v + a6 * c(b[6]) + a4 * c(b[4]) + a2 * c(b[2]) + id * c(b[0]);
        (u, v)
    } else {
        let b: &[f64] = match m {
            3 => &B3,
            5 => &B5,
            7 => &B7,
            _ => &B9,
        };
        let (mut odd, mut even, mut power) = (id * c(b[1]), id * c(b[0]), a2);
        for j in 1..=m / 2 {
            if j > 1 {
                power = power * a2;
            }
            odd = odd + power * c(b[2 * j + 1]);
            even = even + power * c(b[2 * j]);
        }
        (*a * odd, even)
    };
    (v - u).solve(&(v + u))
}

/// NaN of type `T` (`RealField` has no constant for it).
pub(crate) fn nan<T: Real>() -> T {
    T::zero() / T::zero()
}
