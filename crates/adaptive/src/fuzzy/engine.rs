//! Mamdani inference: fire the rules (minimum for AND), aggregate per output
//! set (maximum), defuzzify.

use kestrel_core::nalgebra::SVector;
use kestrel_core::{FilterError, Real};

use super::{Consequent, Defuzzifier, InputVariable, OutputVariable, Rule, Term};

/// The firing strengths of one inference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inference<T: Real, const O: usize, const R: usize> {
    /// Each rule's strength: the minimum of its terms' memberships.
    pub rules: SVector<T, R>,
    /// Each output set's strength: the maximum over the rules concluding it.
    pub sets: SVector<T, O>,
    /// The maximum strength of the [`Consequent::Veto`] rules.
    pub veto: T,
}

impl<T: Real, const O: usize, const R: usize> Default for Inference<T, O, R> {
    fn default() -> Self {
        Self {
            rules: SVector::zeros(),
            sets: SVector::zeros(),
            veto: T::zero(),
        }
    }
}

/// A Mamdani fuzzy inference engine with `I` inputs of up to `S` sets each,
/// `O` output sets and `R` rules, sized at compile time: no allocation, no
/// `std`.
///
/// Inference: the strength of a rule is the minimum (AND) of its inputs'
/// memberships in the sets it names ([`Term::Any`] counts as 1); the
/// strength of an output set is the maximum over the rules concluding it;
/// the crisp output comes from the [`Defuzzifier`].
///
/// ```
/// use kestrel_adaptive::fuzzy::{
///     Consequent::Set, Defuzzifier, Engine, InputVariable, Membership, OutputVariable, Rule,
///     Term::Is,
/// };
/// // One input (error e) with sets negative / positive, output (correction u)
/// // with sets up / down: if e is negative then u is up, and vice versa.
/// let e = InputVariable::<f64, 2>::new(&[
///     Membership::left_shoulder(-1.0, 1.0).unwrap(),
///     Membership::right_shoulder(-1.0, 1.0).unwrap(),
/// ]).unwrap();
/// let u = OutputVariable::new([
///     Membership::triangle(0.0, 1.0, 2.0).unwrap(),
///     Membership::triangle(-2.0, -1.0, 0.0).unwrap(),
/// ], -2.0, 2.0).unwrap();
/// let rules = [Rule::new([Is(0)], Set(0)), Rule::new([Is(1)], Set(1))];
/// let engine = Engine::new([e], u, rules, Defuzzifier::WeightedAverage).unwrap();
/// // e = 0.5: negative ¼, positive ¾ → u = (¼·1 − ¾·1) / 1.
/// let (inference, u) = engine.evaluate(&[0.5]);
/// assert_eq!(inference.rules.as_slice(), &[0.25, 0.75]);
/// assert_eq!(u, Some(-0.5));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Engine<T: Real, const I: usize, const S: usize, const O: usize, const R: usize> {
    inputs: [InputVariable<T, S>; I],
    output: OutputVariable<T, O>,
    rules: [Rule<I>; R],
    defuzzifier: Defuzzifier,
}

impl<T: Real, const I: usize, const S: usize, const O: usize, const R: usize>
    Engine<T, I, S, O, R>
{
    /// An engine from its variables, rule base and defuzzifier.
    ///
    /// # Errors
    /// `InvalidParameter { name: "rules", valid: "rules naming only sets that exist, with at least one rule" }` if a rule names a set an input
    /// or the output does not have, or if there are no rules.
    pub fn new(
        inputs: [InputVariable<T, S>; I],
        output: OutputVariable<T, O>,
        rules: [Rule<I>; R],
        defuzzifier: Defuzzifier,
    ) -> Result<Self, FilterError> {
        let bad = FilterError::InvalidParameter {
            name: "rules",
            valid: "rules naming only sets that exist, with at least one rule",
        };
        if R == 0 {
            return Err(bad);
        }
        for rule in &rules {
            for (term, input) in rule.antecedent().iter().zip(&inputs) {
                if let Term::Is(k) = *term
                    && k >= input.len()
                {
                    return Err(bad);
                }
            }
            if let Consequent::Set(k) = rule.consequent()
                && k >= O
            {
                return Err(bad);
            }
        }
        Ok(Self {
            inputs,
            output,
            rules,
            defuzzifier,
        })
    }

    /// The input variables.
    pub fn inputs(&self) -> &[InputVariable<T, S>; I] {
        &self.inputs
    }

    /// The output variable.
    pub fn output(&self) -> &OutputVariable<T, O> {
        &self.output
    }

    /// The rule base.
    pub fn rules(&self) -> &[Rule<I>; R] {
        &self.rules
    }

    /// The defuzzification method.
    pub fn defuzzifier(&self) -> Defuzzifier {
        self.defuzzifier
    }

    /// Changes the defuzzification method.
    pub fn set_defuzzifier(&mut self, defuzzifier: Defuzzifier) {
        self.defuzzifier = defuzzifier;
    }

    /// Fires the rules for inputs `x`.
    pub fn infer(&self, x: &[T; I]) -> Inference<T, O, R> {
        let mut out = Inference::default();
        for (k, rule) in self.rules.iter().enumerate() {
            let mut strength = T::one();
            for ((term, input), &xi) in rule.antecedent().iter().zip(&self.inputs).zip(x) {
                if let Term::Is(set) = *term {
                    strength = strength.min(input.degree(set, xi));
                }
            }
            out.rules[k] = strength;
            match rule.consequent() {
                Consequent::Set(set) => out.sets[set] = out.sets[set].max(strength),
                Consequent::Veto => out.veto = out.veto.max(strength),
            }
        }
        out
    }

    /// Defuzzifies output-set strengths with the engine's method (`None` if
    /// none fires).
    pub fn defuzzify(&self, sets: &SVector<T, O>) -> Option<T> {
        self.defuzzifier.defuzzify(&self.output, sets)
    }

    /// Fires the rules and defuzzifies all output sets.
    pub fn evaluate(&self, x: &[T; I]) -> (Inference<T, O, R>, Option<T>) {
        let inference = self.infer(x);
        let y = self.defuzzify(&inference.sets);
        (inference, y)
    }
}
