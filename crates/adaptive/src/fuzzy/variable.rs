//! Linguistic variables: the fuzzy sets of one input, and the output's sets
//! with the range its centroid is taken over.

use kestrel_core::{FilterError, Real};

use super::Membership;

/// The fuzzy sets of one input variable: up to `S` sets (variables with
/// fewer sets than the engine's `S` leave the rest unused).
///
/// ```
/// use kestrel_adaptive::fuzzy::{InputVariable, Membership};
/// let small = Membership::left_shoulder(1.0, 2.0).unwrap();
/// let big = Membership::right_shoulder(1.0, 2.0).unwrap();
/// let v = InputVariable::<f64, 5>::new(&[small, big]).unwrap();
/// assert_eq!(v.len(), 2);
/// assert_eq!(v.degree(1, 1.5), 0.5);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputVariable<T: Real, const S: usize> {
    sets: [Membership<T>; S],
    len: usize,
}

impl<T: Real, const S: usize> InputVariable<T, S> {
    /// A variable with the given sets, in the order rules refer to them.
    ///
    /// # Errors
    /// `InvalidParameter { name: "sets", valid: "between 1 and the variable's capacity of sets" }` if `sets` is empty or longer
    /// than `S`.
    pub fn new(sets: &[Membership<T>]) -> Result<Self, FilterError> {
        if sets.is_empty() || sets.len() > S {
            return Err(FilterError::InvalidParameter {
                name: "sets",
                valid: "between 1 and the variable's capacity of sets",
            });
        }
        let mut all = [sets[0]; S];
        all[..sets.len()].copy_from_slice(sets);
        Ok(Self {
            sets: all,
            len: sets.len(),
        })
    }

    /// The number of sets.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Always `false`: a variable has at least one set.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The sets.
    pub fn sets(&self) -> &[Membership<T>] {
        &self.sets[..self.len]
    }

    /// Membership of `x` in set `set` (0 for an index out of range).
    pub fn degree(&self, set: usize, x: T) -> T {
        self.sets().get(set).map_or_else(T::zero, |m| m.degree(x))
    }
}

/// The output variable: one fuzzy set per output class and the range
/// `[low, high]` its aggregated membership is integrated over (which also
/// bounds shoulders).
///
/// ```
/// use kestrel_adaptive::fuzzy::{Membership, OutputVariable};
/// let sets = [
///     Membership::triangle(0.0, 1.0, 2.0).unwrap(),
///     Membership::triangle(1.0, 2.0, 3.0).unwrap(),
/// ];
/// let out = OutputVariable::new(sets, 0.0, 3.0).unwrap();
/// assert_eq!(out.range(), (0.0, 3.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputVariable<T: Real, const O: usize> {
    sets: [Membership<T>; O],
    low: T,
    high: T,
}

impl<T: Real, const O: usize> OutputVariable<T, O> {
    /// The output with sets `sets` over `[low, high]`.
    ///
    /// # Errors
    /// `InvalidParameter { name: "output range", valid: "finite bounds with low < high" }` unless both bounds are
    /// finite and `low < high`, or `"sets"` for `O = 0`.
    pub fn new(sets: [Membership<T>; O], low: T, high: T) -> Result<Self, FilterError> {
        if O == 0 {
            return Err(FilterError::InvalidParameter {
                name: "sets",
                valid: "between 1 and the variable's capacity of sets",
            });
        }
        if !(low.is_finite() && high.is_finite() && low < high) {
            return Err(FilterError::InvalidParameter {
                name: "output range",
                valid: "finite bounds with low < high",
            });
        }
        Ok(Self { sets, low, high })
    }

    /// The sets, one per output class.
    pub fn sets(&self) -> &[Membership<T>; O] {
        &self.sets
    }

    /// `(low, high)`.
    pub fn range(&self) -> (T, T) {
        (self.low, self.high)
    }
}
