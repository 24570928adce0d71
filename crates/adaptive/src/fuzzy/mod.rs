//! A small Mamdani fuzzy inference engine: piecewise-linear membership
//! functions ([`Membership`]), linguistic variables ([`InputVariable`],
//! [`OutputVariable`]), a rule base of ANDed terms ([`Rule`]), min / max
//! inference ([`Engine`]) and centroid or weighted-average defuzzification
//! ([`Defuzzifier`]). Everything is sized by const generics: `no_std`, no
//! allocation, generic over `f32` / `f64`.

mod defuzzify;
mod engine;
mod membership;
mod rule;
mod variable;

pub use defuzzify::{aggregate, Defuzzifier};
pub use engine::{Engine, Inference};
pub use membership::Membership;
pub use rule::{Consequent, Rule, Term};
pub use variable::{InputVariable, OutputVariable};
