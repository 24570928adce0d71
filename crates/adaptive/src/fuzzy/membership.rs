//! Piecewise-linear membership functions.

use kestrel_core::real::lit;
use kestrel_core::{FilterError, Real};

/// A piecewise-linear membership function: a trapezoid `a ≤ b ≤ c ≤ d`
/// (0 outside `[a, d]`, rising linearly on `[a, b]`, 1 on `[b, c]`, falling
/// on `[c, d]`), of which triangles (`b = c`) and shoulders (one side open,
/// membership 1 to infinity) are special cases.
///
/// A vertical edge (`a = b` or `c = d`) is allowed: the edge point then has
/// membership 1. Membership of NaN is 0.
///
/// ```
/// use kestrel_adaptive::fuzzy::Membership;
/// let normal = Membership::triangle(0.85_f64, 1.0, 1.15).unwrap();
/// assert_eq!(normal.degree(1.0), 1.0);
/// assert!((normal.degree(0.9) - 1.0 / 3.0).abs() < 1e-12);
/// assert_eq!(normal.degree(1.2), 0.0);
/// let low = Membership::left_shoulder(0.7_f64, 0.85).unwrap();
/// assert_eq!(low.degree(-5.0), 1.0);
/// assert!((low.degree(0.8) - 1.0 / 3.0).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Membership<T: Real> {
    a: T,
    b: T,
    c: T,
    d: T,
    open_left: bool,
    open_right: bool,
}

impl<T: Real> Membership<T> {
    fn checked(
        [a, b, c, d]: [T; 4],
        open_left: bool,
        open_right: bool,
    ) -> Result<Self, FilterError> {
        let finite = a.is_finite() && b.is_finite() && c.is_finite() && d.is_finite();
        if !(finite && a <= b && b <= c && c <= d && a < d) {
            return Err(FilterError::InvalidParameter {
                name: "membership",
                valid: "finite break points a ≤ b ≤ c ≤ d with a < d",
            });
        }
        Ok(Self {
            a,
            b,
            c,
            d,
            open_left,
            open_right,
        })
    }

    /// Triangle: 0 at `left`, 1 at `peak`, 0 at `right`.
    ///
    /// # Errors
    /// `InvalidParameter { name: "membership", valid: "finite break points a ≤ b ≤ c ≤ d with a < d" }` unless the points are
    /// finite with `left ≤ peak ≤ right` and `left < right`.
    pub fn triangle(left: T, peak: T, right: T) -> Result<Self, FilterError> {
        Self::checked([left, peak, peak, right], false, false)
    }

    /// Trapezoid: 0 at `left`, 1 on `[left_top, right_top]`, 0 at `right`.
    ///
    /// # Errors
    /// `InvalidParameter { name: "membership", valid: "finite break points a ≤ b ≤ c ≤ d with a < d" }` unless the points are
    /// finite, non-decreasing and `left < right`.
    pub fn trapezoid(left: T, left_top: T, right_top: T, right: T) -> Result<Self, FilterError> {
        Self::checked([left, left_top, right_top, right], false, false)
    }

    /// Left shoulder: 1 up to `top`, falling linearly to 0 at `zero`.
    ///
    /// # Errors
    /// `InvalidParameter { name: "membership", valid: "finite break points a ≤ b ≤ c ≤ d with a < d" }` unless both are finite and
    /// `top < zero`.
    pub fn left_shoulder(top: T, zero: T) -> Result<Self, FilterError> {
        Self::checked([top, top, top, zero], true, false)
    }

    /// Right shoulder: 0 up to `zero`, rising linearly to 1 at `top`, 1
    /// beyond.
    ///
    /// # Errors
    /// `InvalidParameter { name: "membership", valid: "finite break points a ≤ b ≤ c ≤ d with a < d" }` unless both are finite and
    /// `zero < top`.
    pub fn right_shoulder(zero: T, top: T) -> Result<Self, FilterError> {
        Self::checked([zero, top, top, top], false, true)
    }

    /// The membership degree of `x`, in `[0, 1]`.
    pub fn degree(&self, x: T) -> T {
        if x >= self.b && x <= self.c {
            T::one()
        } else if x < self.b {
            if self.open_left {
                T::one()
            } else if x > self.a {
                (x - self.a) / (self.b - self.a)
            } else {
                T::zero()
            }
        } else if x > self.c {
            if self.open_right {
                T::one()
            } else if x < self.d {
                (self.d - x) / (self.d - self.c)
            } else {
                T::zero()
            }
        } else {
            // NaN.
            T::zero()
        }
    }

    /// The largest slope `|dμ/dx|` (the reciprocal of the narrowest sloped
    /// edge; 0 for a set with only vertical edges): the Lipschitz constant
    /// of [`degree`](Self::degree) away from vertical edges.
    pub fn max_slope(&self) -> T {
        let mut s = T::zero();
        if !self.open_left && self.b > self.a {
            s = s.max(T::one() / (self.b - self.a));
        }
        if !self.open_right && self.d > self.c {
            s = s.max(T::one() / (self.d - self.c));
        }
        s
    }

    /// The representative value used by the weighted-average
    /// defuzzification: the peak of a triangle, the middle of a trapezoid's
    /// top, the end of a shoulder's top.
    pub fn center(&self) -> T {
        if self.open_left {
            self.b
        } else if self.open_right {
            self.c
        } else {
            (self.b + self.c) * lit::<T>(0.5)
        }
    }

    /// The points where the function changes slope, `[a, b, c, d]`; a
    /// shoulder repeats its top point in place of the open side's.
    pub fn breakpoints(&self) -> [T; 4] {
        [self.a, self.b, self.c, self.d]
    }

    /// The points where a linear edge crosses the level `w ∈ (0, 1)` (where
    /// the set clipped at `w` has a corner); the edge's lower end where there
    /// is no such edge.
    pub fn level_points(&self, w: T) -> [T; 2] {
        let rising = if self.open_left {
            self.b
        } else {
            self.a + w * (self.b - self.a)
        };
        let falling = if self.open_right {
            self.c
        } else {
            self.d - w * (self.d - self.c)
        };
        [rising, falling]
    }
}
