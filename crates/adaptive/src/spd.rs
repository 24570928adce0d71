//! Symmetric eigen-decomposition (cyclic Jacobi) and the projection of a
//! symmetric matrix onto the positive-definite cone, for noise estimates that
//! can come out indefinite (a sample covariance minus a predicted one).
//!
//! Jacobi rotations are used rather than nalgebra's `SymmetricEigen`: that
//! one builds without `std`, but needs `Const<M>: DimSub<U1>`, which holds
//! only through typenum conversions for each concrete size, so it would add
//! that bound to every generic adapter using it. Jacobi is also
//! unconditionally stable and, for the small matrices of measurement noise,
//! fast enough.

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::real::{epsilon, lit};
use kestrel_core::Real;

/// Sweeps after which the Jacobi iteration gives up. Convergence is
/// quadratic; six to ten sweeps suffice for the sizes used here.
const MAX_SWEEPS: usize = 64;

/// Eigenvalues and orthonormal eigenvectors (columns) of a symmetric matrix,
/// reading only its lower triangle: `A = V diag(λ) Vᵀ`.
///
/// Returns `None` if `a` is not finite or the iteration does not converge
/// within its sweep limit (neither happens for finite input in practice).
///
/// ```
/// use kestrel_adaptive::symmetric_eigen;
/// use kestrel_core::nalgebra::Matrix2;
/// let (values, vectors) = symmetric_eigen(&Matrix2::new(2.0_f64, 1.0, 1.0, 2.0)).unwrap();
/// let mut sorted = [values[0], values[1]];
/// sorted.sort_by(|a, b| a.partial_cmp(b).unwrap());
/// assert!((sorted[0] - 1.0).abs() < 1e-14 && (sorted[1] - 3.0).abs() < 1e-14);
/// let back = vectors * Matrix2::from_diagonal(&values) * vectors.transpose();
/// assert!((back - Matrix2::new(2.0, 1.0, 1.0, 2.0)).abs().max() < 1e-14);
/// ```
pub fn symmetric_eigen<T: Real, const M: usize>(
    a: &SMatrix<T, M, M>,
) -> Option<(SVector<T, M>, SMatrix<T, M, M>)> {
    let mut a = *a;
    for j in 0..M {
        for i in 0..j {
            a[(i, j)] = a[(j, i)];
        }
    }
    if !a.iter().all(|v| v.is_finite()) {
        return None;
    }
    let mut v = SMatrix::<T, M, M>::identity();
    let total: T = a.iter().fold(T::zero(), |s, &x| s + x * x);
    // Stop when the off-diagonal mass is negligible against the whole.
    let tol = total * epsilon::<T>() * epsilon::<T>();
    let mut previous: Option<T> = None;
    for _ in 0..MAX_SWEEPS {
        let mut off = T::zero();
        for q in 1..M {
            for p in 0..q {
                off += a[(p, q)] * a[(p, q)];
            }
        }
        // Each sweep removes off-diagonal mass; once rounding stops it from
        // shrinking, the diagonal is as accurate as it will get.
        if off <= tol || previous.is_some_and(|prev| off >= prev) {
            return Some((a.diagonal(), v));
        }
        previous = Some(off);
        for q in 1..M {
            for p in 0..q {
                rotate(&mut a, &mut v, p, q);
            }
        }
    }
    None
}

/// One Jacobi rotation in the `(p, q)` plane that zeroes `a[(p, q)]`:
/// `A ← Jᵀ A J`, `V ← V J`.
fn rotate<T: Real, const M: usize>(
    a: &mut SMatrix<T, M, M>,
    v: &mut SMatrix<T, M, M>,
    p: usize,
    q: usize,
) {
    let apq = a[(p, q)];
    if apq == T::zero() {
        return;
    }
    let theta = (a[(q, q)] - a[(p, p)]) / (apq + apq);
    // t = sgn θ / (|θ| + √(θ² + 1)), written so a huge θ cannot overflow.
    let abs = theta.abs();
    let root = if abs > T::one() {
        abs * (T::one() + (T::one() / abs) * (T::one() / abs)).sqrt()
    } else {
        (abs * abs + T::one()).sqrt()
    };
    let mut t = T::one() / (abs + root);
    if theta < T::zero() {
        t = -t;
    }
    let c = T::one() / (t * t + T::one()).sqrt();
    let s = t * c;
    for k in 0..M {
        let (akp, akq) = (a[(k, p)], a[(k, q)]);
        a[(k, p)] = c * akp - s * akq;
        a[(k, q)] = s * akp + c * akq;
    }
    for k in 0..M {
        let (apk, aqk) = (a[(p, k)], a[(q, k)]);
        a[(p, k)] = c * apk - s * aqk;
        a[(q, k)] = s * apk + c * aqk;
    }
    // Exact zero and exact symmetry of the rotated pair.
    a[(p, q)] = T::zero();
    a[(q, p)] = T::zero();
    for k in 0..M {
        let (vkp, vkq) = (v[(k, p)], v[(k, q)]);
        v[(k, p)] = c * vkp - s * vkq;
        v[(k, q)] = s * vkp + c * vkq;
    }
}

/// The result of [`project_spd`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpdProjection<T: Real, const M: usize> {
    /// The projected matrix `V diag(max(λᵢ, floor)) Vᵀ`, exactly symmetric.
    pub matrix: SMatrix<T, M, M>,
    /// The smallest eigenvalue of the input.
    pub min_eigenvalue: T,
    /// The floor actually applied (see [`project_spd`]).
    pub floor: T,
    /// How many eigenvalues were raised to the floor.
    pub raised: usize,
}

/// Projects a symmetric matrix (lower triangle read) onto the positive
/// definite matrices by raising every eigenvalue below a floor to it:
/// `A⁺ = V diag(max(λᵢ, f)) Vᵀ`, the nearest matrix in the Frobenius norm
/// with eigenvalues `≥ f`.
///
/// The floor is `f = max(min_eigenvalue, 16 M ε max|λ|)`: the relative term
/// keeps the result positive definite to working precision (a Cholesky
/// factorisation succeeds) even when `min_eigenvalue` is below the rounding
/// of the largest eigenvalue. Returns `None` for non-finite input or a
/// non-positive `min_eigenvalue`.
///
/// ```
/// use kestrel_adaptive::project_spd;
/// use kestrel_core::nalgebra::Matrix2;
/// // Eigenvalues 3 and −1 along (1, 1)/√2 and (1, −1)/√2.
/// let p = project_spd(&Matrix2::new(1.0_f64, 2.0, 2.0, 1.0), 0.5).unwrap();
/// // 3·½[1 1; 1 1] + 0.5·½[1 −1; −1 1]
/// assert!((p.matrix - Matrix2::new(1.75, 1.25, 1.25, 1.75)).abs().max() < 1e-14);
/// assert_eq!(p.raised, 1);
/// assert!((p.min_eigenvalue + 1.0).abs() < 1e-14);
/// ```
pub fn project_spd<T: Real, const M: usize>(
    a: &SMatrix<T, M, M>,
    min_eigenvalue: T,
) -> Option<SpdProjection<T, M>> {
    if !(min_eigenvalue.is_finite() && min_eigenvalue > T::zero()) {
        return None;
    }
    let (values, vectors) = symmetric_eigen(a)?;
    let mut largest = T::zero();
    let mut smallest = values[0];
    for &l in values.iter() {
        largest = largest.max(l.abs());
        smallest = smallest.min(l);
    }
    let relative = lit::<T>(16.0 * M as f64) * epsilon::<T>() * largest;
    let floor = min_eigenvalue.max(relative);
    let mut raised = 0;
    let mut matrix = SMatrix::<T, M, M>::zeros();
    for (k, &l) in values.iter().enumerate() {
        let l = if l < floor {
            raised += 1;
            floor
        } else {
            l
        };
        // Lower triangle of l · v vᵀ.
        for j in 0..M {
            let w = l * vectors[(j, k)];
            for i in j..M {
                matrix[(i, j)] += w * vectors[(i, k)];
            }
        }
    }
    for j in 1..M {
        for i in 0..j {
            matrix[(i, j)] = matrix[(j, i)];
        }
    }
    if !matrix.iter().all(|v| v.is_finite()) {
        return None;
    }
    Some(SpdProjection {
        matrix,
        min_eigenvalue: smallest,
        floor,
        raised,
    })
}
