use crate::Real;

/// What an adapter sees and controls right after a predict: the time step and
/// a fade factor applied to the propagated covariance before `Q` is added.
///
/// ```
/// use kestrel_core::adapter::PriorStep;
/// let mut step = PriorStep::new(0.1_f64);
/// step.fade(1.5);
/// step.fade(2.0);
/// assert_eq!(step.fade_factor(), 3.0);
/// assert_eq!(step.dt(), 0.1);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PriorStep<T: Real> {
    dt: T,
    fade: T,
}

impl<T: Real> PriorStep<T> {
    /// A step of `dt` seconds with no fading.
    pub fn new(dt: T) -> Self {
        Self { dt, fade: T::one() }
    }

    /// The time step of the predict, as given to it.
    pub fn dt(&self) -> T {
        self.dt
    }

    /// Multiplies the propagated covariance by `lambda` (fading memory,
    /// `λ ≥ 1` discounts old information). Non-finite or non-positive values
    /// are ignored.
    pub fn fade(&mut self, lambda: T) {
        if lambda.is_finite() && lambda > T::zero() {
            self.fade *= lambda;
        }
    }

    /// The product of the fades requested so far.
    pub fn fade_factor(&self) -> T {
        self.fade
    }
}
