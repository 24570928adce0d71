//! The default odometer rule base and membership breakpoints (paper 003,
//! section 3.3; the membership functions are in figures the text lacks, so
//! the breakpoints are the project's choice).

use kestrel_core::real::lit;
use kestrel_core::{FilterError, Real};

use crate::fuzzy::Consequent::{Set, Veto};
use crate::fuzzy::Term::{Any, Is};
use crate::fuzzy::{Defuzzifier, Engine, InputVariable, Membership, OutputVariable, Rule};

/// The engine type of [`odometer_engine`]: 3 inputs (match factor, heading
/// rate, innovation mean), up to 5 sets each, 5 output sets, 14 rules.
pub type OdometerEngine<T> = Engine<T, 3, 5, 5, 14>;

// Set indices.
const T_: usize = 0; // tiny
const S_: usize = 1; // small
const Z_: usize = 2; // normal
const B_: usize = 3; // big
const L_: usize = 4; // large
const LOW: usize = 0; // ΔH and r: small
const MID: usize = 1; // medium
const HIGH: usize = 2; // big

/// The odometer rule base over `[dm₁, |ΔH|, r]` with output `α₁`. Sets:
/// dm₁ and α₁ `T S Z B L` (0–4), |ΔH| and r `S M B` (0–2).
///
/// | dm₁ \ r | S | M | B |
/// |---|---|---|---|
/// | T | S | T ✗ | veto (outage) |
/// | S | S | S* | — |
/// | Z | Z | S | — |
/// | B | B | B* | — |
/// | L | B | L ✗ | veto (outage) |
///
/// plus: dm₁ B and |ΔH| B → veto (side-slip); dm₁ L and |ΔH| B → veto*.
/// ✗ marks output sets the paper calls unusable (`α₁` tiny / large);
/// entries with * are the project's completion of the paper's list; —
/// marks where the paper has no rule and none is added: a big innovation
/// mean with a match factor that is not extreme fires no rule, and the
/// odometer is unusable for that epoch (the paper's "large innovation:
/// use the SINS velocity", which it states for extreme ratios).
///
/// The — cells were once completed as "r big behaves as r medium" (α₁
/// small for dm₁ S or Z, big for B). On a sustained slip that made the
/// gain lock: the slip's innovations are big, α₁ = 0.85 is applied, the
/// closed loop pulls the INS speed to 0.85 × the odometer's, so dm₁
/// falls to 0.85 — "small" — and keeps α₁ small for the rest of the drive
/// (rule trace in `docs/reproduction.md`; a ×1.05 slip for 300 s on paper
/// 003's drive: worst error 2.5 km, against 19–37 m without those rules).
pub const ODOMETER_RULES: [Rule<3>; 14] = [
    // The paper's list.
    Rule::new([Is(B_), Is(HIGH), Any], Veto),
    Rule::new([Is(T_), Any, Is(LOW)], Set(S_)),
    Rule::new([Is(T_), Any, Is(MID)], Set(T_)),
    Rule::new([Is(L_), Any, Is(LOW)], Set(B_)),
    Rule::new([Is(L_), Any, Is(MID)], Set(L_)),
    Rule::new([Is(Z_), Any, Is(LOW)], Set(Z_)),
    Rule::new([Is(Z_), Any, Is(MID)], Set(S_)),
    Rule::new([Is(S_), Any, Is(LOW)], Set(S_)),
    Rule::new([Is(B_), Any, Is(LOW)], Set(B_)),
    Rule::new([Is(T_), Any, Is(HIGH)], Veto),
    Rule::new([Is(L_), Any, Is(HIGH)], Veto),
    // Completion.
    Rule::new([Is(L_), Is(HIGH), Any], Veto),
    Rule::new([Is(S_), Any, Is(MID)], Set(S_)),
    Rule::new([Is(B_), Any, Is(MID)], Set(B_)),
];

/// Which output sets of [`odometer_engine`] mean "odometer unusable":
/// `α₁` tiny and large.
pub const ODOMETER_UNUSABLE: [bool; 5] = [true, false, false, false, true];

/// The default odometer engine: [`ODOMETER_RULES`], exact centroid, and
/// membership functions that leave a healthy odometer alone: the "normal"
/// match factor is a plateau, so `α₁ = 1` exactly for `0.95 ≤ dm₁ ≤ 1.05`.
///
/// Why the plateau: the gain rescales the odometer speed to `α₁ ŝ`, and the
/// rules map `dm₁` to an `α₁` near it. With overlapping triangles at 1
/// (S 0.85 / Z 1.0) any small disagreement gives `α₁ ≈ dm₁`, i.e. the
/// odometer speed is replaced by the INS speed; in closed-loop dead
/// reckoning the filter then loses its only speed reference (a 1 h run of
/// paper 003's scenario ended about 30 km off, against 24 m with the
/// plateau). Disagreements within ±5 % are what the filter corrects itself
/// (scale error, noise at low speed); the fuzzy gain acts beyond them.
///
/// Membership functions (shoulders open to ±∞):
///
/// - dm₁ = |v_SINS| / |v_OD|: T ≤ 0.7 ↘ 0.8; S 0.7 / 0.8–0.9 / 0.95;
///   Z 0.9 / 0.95–1.05 / 1.1; B 1.05 / 1.1–1.2 / 1.3; L 1.2 ↗ 1.3.
/// - |ΔH|, heading rate in deg/s: S ≤ 5 ↘ 15; M 5 / 15 / 25; B 15 ↗ 25.
/// - r, innovation mean in units of its predicted standard deviation:
///   S ≤ 1 ↘ 2; M 1 / 2 / 3; B 2 ↗ 3.
/// - α₁ over [0.55, 1.45]: triangles of half-width 0.15 centred on
///   T 0.7, S 0.85, Z 1.0, B 1.15, L 1.3.
///
/// Each input's sets sum to 1 everywhere; every combination of sets but
/// a big `r` with dm₁ small, normal or big has a rule (those three fire
/// none: the odometer is unusable).
///
/// ```
/// use kestrel_adaptive::odometer_engine;
/// let engine = odometer_engine::<f64>().unwrap();
/// // A 3 % disagreement on a straight road: the odometer is used as is.
/// let (_, alpha) = engine.evaluate(&[0.97, 0.0, 0.8]);
/// assert_eq!(alpha, Some(1.0));
/// // The odometer reads 15 % fast (dm₁ = 0.87) with small innovations.
/// let (_, alpha) = engine.evaluate(&[0.87, 0.0, 0.8]);
/// assert!((alpha.unwrap() - 0.85).abs() < 1e-12);
/// ```
///
/// # Errors
/// None for the built-in values; the `Result` is that of the constructors.
pub fn odometer_engine<T: Real>() -> Result<OdometerEngine<T>, FilterError> {
    let l = |v: f64| lit::<T>(v);
    let tri = |a: f64, b: f64, c: f64| Membership::triangle(l(a), l(b), l(c));
    let trap = |a: f64, b: f64, c: f64, d: f64| Membership::trapezoid(l(a), l(b), l(c), l(d));
    let dm1 = InputVariable::new(&[
        Membership::left_shoulder(l(0.7), l(0.8))?,
        trap(0.7, 0.8, 0.9, 0.95)?,
        trap(0.9, 0.95, 1.05, 1.1)?,
        trap(1.05, 1.1, 1.2, 1.3)?,
        Membership::right_shoulder(l(1.2), l(1.3))?,
    ])?;
    let heading = InputVariable::new(&[
        Membership::left_shoulder(l(5.0), l(15.0))?,
        tri(5.0, 15.0, 25.0)?,
        Membership::right_shoulder(l(15.0), l(25.0))?,
    ])?;
    let innovation = InputVariable::new(&[
        Membership::left_shoulder(l(1.0), l(2.0))?,
        tri(1.0, 2.0, 3.0)?,
        Membership::right_shoulder(l(2.0), l(3.0))?,
    ])?;
    let alpha = OutputVariable::new(
        [
            tri(0.55, 0.7, 0.85)?,
            tri(0.7, 0.85, 1.0)?,
            tri(0.85, 1.0, 1.15)?,
            tri(1.0, 1.15, 1.3)?,
            tri(1.15, 1.3, 1.45)?,
        ],
        l(0.55),
        l(1.45),
    )?;
    Engine::new(
        [dm1, heading, innovation],
        alpha,
        ODOMETER_RULES,
        Defuzzifier::Centroid,
    )
}
