//! The per-epoch inputs of the fuzzy odometer gain.

use kestrel_core::nalgebra::SVector;
use kestrel_core::Real;

/// One epoch's inputs of [`FuzzyGain`](super::FuzzyGain), supplied by the
/// caller before the update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OdometerInputs<T: Real, const M: usize> {
    /// The match factor `dm₁ = |v_SINS| / |v_OD|` (see [`match_factor`]).
    pub match_factor: T,
    /// The heading change rate `ΔH`, deg/s (its magnitude is used).
    pub heading_rate: T,
    /// The odometer velocity in the navigation frame `v_ODⁿ`, as used in
    /// the measurement `z = v_SINS − v_ODⁿ`.
    pub odometer_velocity: SVector<T, M>,
}

impl<T: Real, const M: usize> OdometerInputs<T, M> {
    /// The inputs from their values.
    ///
    /// ```
    /// use kestrel_adaptive::OdometerInputs;
    /// use kestrel_core::nalgebra::Vector2;
    /// let i = OdometerInputs::new(1.02, -3.0, Vector2::new(9.8, 0.1));
    /// assert_eq!(i.heading_rate, -3.0);
    /// ```
    pub fn new(match_factor: T, heading_rate: T, odometer_velocity: SVector<T, M>) -> Self {
        Self {
            match_factor,
            heading_rate,
            odometer_velocity,
        }
    }

    /// The inputs from the SINS and odometer velocities in the navigation
    /// frame, with `dm₁` from [`match_factor`] of their norms.
    ///
    /// ```
    /// use kestrel_adaptive::OdometerInputs;
    /// use kestrel_core::nalgebra::Vector2;
    /// let i = OdometerInputs::from_velocities(
    ///     &Vector2::new(6.0, 8.0), &Vector2::new(0.0, 8.0), 2.0, 0.5);
    /// assert_eq!(i.match_factor, 1.25);
    /// assert_eq!(i.odometer_velocity, Vector2::new(0.0, 8.0));
    /// ```
    pub fn from_velocities(
        sins_velocity: &SVector<T, M>,
        odometer_velocity: &SVector<T, M>,
        heading_rate: T,
        min_speed: T,
    ) -> Self {
        Self::new(
            match_factor(sins_velocity.norm(), odometer_velocity.norm(), min_speed),
            heading_rate,
            *odometer_velocity,
        )
    }

    /// Whether every input is finite.
    pub fn is_finite(&self) -> bool {
        self.match_factor.is_finite()
            && self.heading_rate.is_finite()
            && self.odometer_velocity.iter().all(|v| v.is_finite())
    }
}

/// `dm₁ = v_SINS / v_OD` for speeds `≥ 0`, defined at standstill: 1 when
/// both speeds are below `min_speed`, `v_SINS / min_speed` when only the
/// odometer's is (so a stopped wheel under a moving vehicle reads large).
///
/// ```
/// use kestrel_adaptive::match_factor;
/// assert_eq!(match_factor(10.0, 8.0, 0.1), 1.25);
/// assert_eq!(match_factor(0.01, 0.0, 0.1), 1.0);
/// assert_eq!(match_factor(2.0, 0.0, 0.1), 20.0);
/// ```
pub fn match_factor<T: Real>(sins_speed: T, odometer_speed: T, min_speed: T) -> T {
    if odometer_speed >= min_speed && odometer_speed > T::zero() {
        sins_speed / odometer_speed
    } else if sins_speed < min_speed || min_speed <= T::zero() {
        T::one()
    } else {
        sins_speed / min_speed
    }
}
