//! Rules: `if x₁ is A and x₂ is B … then y is C`.

/// One antecedent term: which set of an input the rule requires.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Term {
    /// The input does not matter (membership 1).
    Any,
    /// The input must be in the set with this index.
    Is(usize),
}

/// What a rule concludes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Consequent {
    /// The output is in the output set with this index.
    Set(usize),
    /// No output value: the rule vetoes the use of the output (its firing
    /// strength is reported separately as the veto strength, and takes no
    /// part in defuzzification).
    Veto,
}

/// A rule over `I` inputs: the AND (minimum) of its terms implies its
/// consequent.
///
/// ```
/// use kestrel_adaptive::fuzzy::{Consequent, Rule, Term};
/// // if x₀ is set 2 (x₁ anything) then y is set 1
/// let rule = Rule::new([Term::Is(2), Term::Any], Consequent::Set(1));
/// assert_eq!(rule.antecedent()[1], Term::Any);
/// assert_eq!(rule.consequent(), Consequent::Set(1));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rule<const I: usize> {
    antecedent: [Term; I],
    consequent: Consequent,
}

impl<const I: usize> Rule<I> {
    /// The rule `antecedent ⇒ consequent` (indices are checked when the
    /// rule base is given to an [`Engine`](super::Engine)).
    pub const fn new(antecedent: [Term; I], consequent: Consequent) -> Self {
        Self {
            antecedent,
            consequent,
        }
    }

    /// The terms, one per input.
    pub fn antecedent(&self) -> &[Term; I] {
        &self.antecedent
    }

    /// The consequent.
    pub fn consequent(&self) -> Consequent {
        self.consequent
    }
}
