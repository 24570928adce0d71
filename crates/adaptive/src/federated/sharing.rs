//! Information-sharing factors `β_i`: fixed, adaptive by EDOP, or no reset.

use kestrel_core::nalgebra::SMatrix;
use kestrel_core::real::{epsilon, lit};
use kestrel_core::{FilterError, Real};

use super::FusionError;

/// How a federated filter shares the fused information among its locals.
///
/// ```
/// use kestrel_adaptive::federated::{Policy, Sharing};
/// assert_eq!(Sharing::no_reset([0.5, 0.5]).unwrap().policy(), Policy::NoReset);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Policy {
    /// Fixed shares, reset after every fusion.
    Fixed,
    /// Shares `β_i ∝ 1 / EDOP_i`, recomputed at every fusion, then reset.
    Edop,
    /// The locals are never reset; the shares only scale their initial
    /// covariance and process noise.
    NoReset,
}

/// The information-sharing factors of a federated filter with `L` locals
/// (paper 001, Carlson's federated filter): after fusion local `i` is reset
/// to `x_i = x_g`, `P_i = β_i⁻¹ P_g` and predicts with `Q_i = β_i⁻¹ Q`.
///
/// - [`fixed`](Self::fixed): given shares, each in `(0, 1]`, summing to at
///   most 1. A master filter is a local that is only predicted, its share
///   `β_m` one of the `L`. A sum below 1 discards the rest of the
///   information (a conservative fusion). When locals are isolated, the
///   admitted ones' shares are scaled up to the same sum.
/// - [`edop`](Self::edop): the paper's adaptive sharing (eq. 25),
///   `EDOP_i = sqrt(tr(P_i P_iᵀ))` of each local's covariance before fusion,
///   generalised to `β_i = EDOP_i⁻¹ / Σ_j EDOP_j⁻¹` over the admitted locals:
///   the more precise a local, the larger its share. For two locals this is
///   the paper's `β_1 = EDOP_2 / (EDOP_1 + EDOP_2)`.
/// - [`no_reset`](Self::no_reset): the locals run independently from
///   `P_i(0) = β_i⁻¹ P(0)` with `Q_i = β_i⁻¹ Q`; fusion only combines them.
///
/// ```
/// use kestrel_adaptive::federated::{Policy, Sharing};
/// let s = Sharing::fixed([0.25, 0.75]).unwrap();
/// assert_eq!(s.shares(), &[0.25, 0.75]);
/// assert!(Sharing::fixed([0.5, 0.75]).is_err()); // sums to more than 1
/// assert_eq!(Sharing::<f64, 4>::edop().shares(), &[0.25; 4]);
/// assert_eq!(Sharing::<f64, 2>::equal().policy(), Policy::Fixed);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sharing<T: Real, const L: usize> {
    policy: Policy,
    shares: [T; L],
}

impl<T: Real, const L: usize> Sharing<T, L> {
    /// Fixed shares `β_i`.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] (`"shares"`) unless every share is
    /// in `(0, 1]` and their sum is at most 1 (to `L` rounding errors).
    pub fn fixed(shares: [T; L]) -> Result<Self, FilterError> {
        validate(&shares)?;
        Ok(Self {
            policy: Policy::Fixed,
            shares,
        })
    }

    /// Fixed equal shares `β_i = 1 / L`.
    pub fn equal() -> Self {
        Self {
            policy: Policy::Fixed,
            shares: equal(),
        }
    }

    /// Adaptive shares from the locals' EDOP (the first reset, before any
    /// covariance is known, uses `1 / L`).
    pub fn edop() -> Self {
        Self {
            policy: Policy::Edop,
            shares: equal(),
        }
    }

    /// Shares for a federated filter whose locals are never reset.
    ///
    /// # Errors
    /// As [`fixed`](Self::fixed).
    pub fn no_reset(shares: [T; L]) -> Result<Self, FilterError> {
        validate(&shares)?;
        Ok(Self {
            policy: Policy::NoReset,
            shares,
        })
    }

    /// The policy.
    pub fn policy(&self) -> Policy {
        self.policy
    }

    /// The configured (for [`Policy::Edop`], the initial) shares.
    pub fn shares(&self) -> &[T; L] {
        &self.shares
    }

    /// The shares of the locals flagged in `admitted` after a fusion, given
    /// every local's EDOP; the others get 0.
    pub(crate) fn distribute(
        &self,
        admitted: &[bool; L],
        edops: &[T; L],
    ) -> Result<[T; L], FusionError> {
        match self.policy {
            Policy::NoReset => Ok(self.shares),
            Policy::Edop => edop_shares(edops, admitted),
            Policy::Fixed => {
                let total = self.shares.iter().fold(T::zero(), |s, &b| s + b);
                let kept = (0..L)
                    .filter(|&i| admitted[i])
                    .fold(T::zero(), |s, i| s + self.shares[i]);
                // Exactly 1 when every local is admitted (the same sum).
                let scale = total / kept;
                Ok(core::array::from_fn(|i| {
                    if admitted[i] {
                        self.shares[i] * scale
                    } else {
                        T::zero()
                    }
                }))
            }
        }
    }
}

fn equal<T: Real, const L: usize>() -> [T; L] {
    [T::one() / lit(L.max(1) as f64); L]
}

fn validate<T: Real, const L: usize>(shares: &[T; L]) -> Result<(), FilterError> {
    let invalid = FilterError::InvalidParameter {
        name: "shares",
        valid: "L finite shares, each in (0, 1], summing to 1",
    };
    let mut sum = T::zero();
    for &b in shares {
        // Also refuses NaN.
        if !(b > T::zero() && b <= T::one()) {
            return Err(invalid);
        }
        sum += b;
    }
    if sum <= T::one() + epsilon::<T>() * lit(L as f64) {
        Ok(())
    } else {
        Err(invalid)
    }
}

/// The paper's `EDOP = sqrt(tr(P Pᵀ))` of a covariance: its Frobenius norm,
/// a scalar measure of how uncertain an estimate is.
///
/// ```
/// use kestrel_adaptive::federated::edop;
/// use kestrel_core::nalgebra::Matrix2;
/// // tr(P Pᵀ) = 3² + 1² + 1² + 1² = 12.
/// assert_eq!(edop(&Matrix2::new(3.0, 1.0, 1.0, 1.0)), 12f64.sqrt());
/// ```
pub fn edop<T: Real, const N: usize>(p: &SMatrix<T, N, N>) -> T {
    p.iter().fold(T::zero(), |s, &v| s + v * v).sqrt()
}

/// Adaptive shares `β_i = EDOP_i⁻¹ / Σ_j EDOP_j⁻¹` over the locals flagged
/// in `admitted` (the others get 0); they sum to 1.
///
/// # Errors
/// [`FusionError::NonFinite`] naming an admitted local whose EDOP is not
/// finite or has no finite reciprocal, [`FusionError::FusedNonFinite`] if
/// the reciprocals overflow in sum; [`FusionError::AllIsolated`] if none is
/// admitted.
///
/// ```
/// use kestrel_adaptive::federated::edop_shares;
/// let b = edop_shares(&[1.0_f64, 3.0, 2.0], &[true, true, false]).unwrap();
/// // EDOP₂ / (EDOP₁ + EDOP₂) and EDOP₁ / (EDOP₁ + EDOP₂).
/// assert!((b[0] - 0.75).abs() < 1e-15 && (b[1] - 0.25).abs() < 1e-15);
/// assert_eq!(b[2], 0.0);
/// ```
pub fn edop_shares<T: Real, const L: usize>(
    edops: &[T; L],
    admitted: &[bool; L],
) -> Result<[T; L], FusionError> {
    let mut inverse = [T::zero(); L];
    let mut sum = T::zero();
    for i in (0..L).filter(|&i| admitted[i]) {
        let v = edops[i].recip();
        if !(edops[i].is_finite() && v.is_finite() && v > T::zero()) {
            return Err(FusionError::NonFinite { local: i });
        }
        inverse[i] = v;
        sum += v;
    }
    if sum == T::zero() {
        return Err(FusionError::AllIsolated);
    }
    if !sum.is_finite() {
        return Err(FusionError::FusedNonFinite);
    }
    Ok(inverse.map(|v| v / sum))
}
