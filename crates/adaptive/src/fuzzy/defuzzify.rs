//! Defuzzification: from the firing strength of each output set to one crisp
//! output value.

use kestrel_core::nalgebra::SVector;
use kestrel_core::real::{epsilon, lit};
use kestrel_core::Real;

use super::OutputVariable;

/// How the aggregated output is turned into a number. Every method returns
/// `None` when no output set fires (all strengths zero).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Defuzzifier {
    /// The exact centroid `∫ y μ(y) dy / ∫ μ(y) dy` over the output range
    /// of the Mamdani aggregate `μ(y) = maxₖ min(wₖ, μₖ(y))`, integrated
    /// piece by piece: `μ` is piecewise linear, with corners at the sets'
    /// breakpoints, where an edge crosses its clip level `wₖ`, and where two
    /// clipped sets cross.
    #[default]
    Centroid,
    /// The centroid sampled at `points` equally spaced values over the
    /// output range, ends included (`Σ yᵢ μ(yᵢ) / Σ μ(yᵢ)`); fewer than 2
    /// points are taken as 2.
    SampledCentroid {
        /// Number of samples.
        points: usize,
    },
    /// The weighted average of singleton outputs
    /// `Σ wₖ cₖ / Σ wₖ`, `cₖ` the [`center`](super::Membership::center) of
    /// output set `k`.
    WeightedAverage,
}

impl Defuzzifier {
    /// The crisp output for output-set strengths `strengths` (each in
    /// `[0, 1]`).
    ///
    /// ```
    /// use kestrel_adaptive::fuzzy::{Defuzzifier, Membership, OutputVariable};
    /// use kestrel_core::nalgebra::Vector2;
    /// let out = OutputVariable::new([
    ///     Membership::triangle(0.0_f64, 1.0, 2.0).unwrap(),
    ///     Membership::triangle(2.0, 3.0, 4.0).unwrap(),
    /// ], 0.0, 4.0).unwrap();
    /// let w = Vector2::new(1.0, 0.5);
    /// // Singletons 1 and 3: (1 + 1.5) / 1.5.
    /// let avg = Defuzzifier::WeightedAverage.defuzzify(&out, &w).unwrap();
    /// assert!((avg - 2.5 / 1.5).abs() < 1e-15);
    /// // Areas 1 and 0.75 (triangle clipped at ½), centroids 1 and 3.
    /// let c = Defuzzifier::Centroid.defuzzify(&out, &w).unwrap();
    /// assert!((c - (1.0 + 0.75 * 3.0) / 1.75).abs() < 1e-14);
    /// ```
    pub fn defuzzify<T: Real, const O: usize>(
        &self,
        output: &OutputVariable<T, O>,
        strengths: &SVector<T, O>,
    ) -> Option<T> {
        match *self {
            Defuzzifier::Centroid => exact_centroid(output, strengths),
            Defuzzifier::SampledCentroid { points } => {
                sampled_centroid(output, strengths, points.max(2))
            }
            Defuzzifier::WeightedAverage => weighted_average(output, strengths),
        }
    }
}

/// The Mamdani aggregate `maxₖ min(wₖ, μₖ(y))` at `y`.
///
/// ```
/// use kestrel_adaptive::fuzzy::{aggregate, Membership, OutputVariable};
/// use kestrel_core::nalgebra::Vector1;
/// let out = OutputVariable::new([Membership::triangle(0.0, 1.0, 2.0).unwrap()], 0.0, 2.0)
///     .unwrap();
/// assert_eq!(aggregate(&out, &Vector1::new(0.5), 0.25), 0.25);
/// assert_eq!(aggregate(&out, &Vector1::new(0.5), 1.0), 0.5);
/// ```
pub fn aggregate<T: Real, const O: usize>(
    output: &OutputVariable<T, O>,
    strengths: &SVector<T, O>,
    y: T,
) -> T {
    let mut mu = T::zero();
    for (set, &w) in output.sets().iter().zip(strengths.iter()) {
        if w > T::zero() {
            mu = mu.max(w.min(set.degree(y)));
        }
    }
    mu
}

fn weighted_average<T: Real, const O: usize>(
    output: &OutputVariable<T, O>,
    strengths: &SVector<T, O>,
) -> Option<T> {
    let (mut num, mut den) = (T::zero(), T::zero());
    for (set, &w) in output.sets().iter().zip(strengths.iter()) {
        if w > T::zero() {
            num += w * set.center();
            den += w;
        }
    }
    (den > T::zero()).then(|| num / den)
}

fn sampled_centroid<T: Real, const O: usize>(
    output: &OutputVariable<T, O>,
    strengths: &SVector<T, O>,
    points: usize,
) -> Option<T> {
    let (low, high) = output.range();
    let step = (high - low) / lit::<T>((points - 1) as f64);
    let (mut num, mut den) = (T::zero(), T::zero());
    for i in 0..points {
        // Relative to `low`, so a range far from zero loses no digits.
        let dy = step * lit::<T>(i as f64);
        let mu = aggregate(output, strengths, low + dy);
        num += dy * mu;
        den += mu;
    }
    (den > T::zero()).then(|| low + num / den)
}

/// Area and first moment (about the range's low end) of the aggregate.
struct Integral<T> {
    area: T,
    moment: T,
}

impl<T: Real> Integral<T> {
    /// Adds the linear segment from `(x0, y0)` to `(x1, y1)`, `x` measured
    /// from the low end.
    fn segment(&mut self, x0: T, y0: T, x1: T, y1: T) {
        let h = x1 - x0;
        self.area += h * (y0 + y1) * lit::<T>(0.5);
        self.moment += h * (x0 * (y0 + y0 + y1) + x1 * (y0 + y1 + y1)) / lit::<T>(6.0);
    }
}

fn exact_centroid<T: Real, const O: usize>(
    output: &OutputVariable<T, O>,
    strengths: &SVector<T, O>,
) -> Option<T> {
    let (low, high) = output.range();
    let mut sum = Integral {
        area: T::zero(),
        moment: T::zero(),
    };
    let mut x = low;
    // Each set has at most six corners: the loop ends after at most 6·O + 1
    // intervals; the bound only guards against a logic error.
    for _ in 0..=6 * O + 1 {
        if x >= high {
            break;
        }
        let next = next_corner(output, strengths, x).min(high);
        envelope(output, strengths, low, x, next, &mut sum);
        x = next;
    }
    (sum.area > T::zero()).then(|| low + sum.moment / sum.area)
}

/// The smallest corner of any firing clipped set above `x` (`+∞` is never
/// returned: the caller clips to the range, so `x` itself stands for none).
fn next_corner<T: Real, const O: usize>(
    output: &OutputVariable<T, O>,
    strengths: &SVector<T, O>,
    x: T,
) -> T {
    let mut best: Option<T> = None;
    for (set, &w) in output.sets().iter().zip(strengths.iter()) {
        if w <= T::zero() {
            continue;
        }
        let [a, b, c, d] = set.breakpoints();
        let [up, down] = set.level_points(w.min(T::one()));
        for p in [a, b, c, d, up, down] {
            if p > x && best.is_none_or(|q| p < q) {
                best = Some(p);
            }
        }
    }
    best.unwrap_or(x + x.abs() + T::one())
}

/// Integrates the upper envelope of the clipped sets over `[l, r]`, an
/// interval without corners, where each clipped set is linear: the
/// envelope is the maximum of lines, followed from the top line at the left
/// end to the first crossing by a steeper line, and so on.
fn envelope<T: Real, const O: usize>(
    output: &OutputVariable<T, O>,
    strengths: &SVector<T, O>,
    low: T,
    l: T,
    r: T,
    sum: &mut Integral<T>,
) {
    let h = r - l;
    if h <= T::zero() {
        return;
    }
    // Each firing clipped set as a line v + s (x − l), from two interior
    // samples (the ends may sit on a vertical edge, where only the limit
    // counts).
    let (q1, q3) = (l + h * lit::<T>(0.25), l + h * lit::<T>(0.75));
    let mut lines = [(T::zero(), T::zero()); O];
    let mut count = 0;
    for (set, &w) in output.sets().iter().zip(strengths.iter()) {
        if w > T::zero() {
            let (g1, g3) = (w.min(set.degree(q1)), w.min(set.degree(q3)));
            let s = (g3 - g1) / (h * lit::<T>(0.5));
            lines[count] = (g1 - s * h * lit::<T>(0.25), s);
            count += 1;
        }
    }
    let lines = &lines[..count];
    let at = |(v, s): (T, T), x: T| v + s * (x - l);
    // Values within a few roundings of each other are ties, resolved to the
    // steeper line, so rounding cannot invent crossings.
    let tie = lit::<T>(8.0) * epsilon::<T>();
    let mut x = l;
    // The envelope of `count` lines has at most `count` pieces; the spare
    // rounds absorb crossings split by rounding, and the last one always
    // reaches `r`.
    let rounds = 2 * count;
    for round in 0..=rounds {
        let Some(&first) = lines.first() else {
            return;
        };
        let mut top = first;
        for &line in &lines[1..] {
            let (yt, yl) = (at(top, x), at(line, x));
            if yl > yt + tie || ((yl - yt).abs() <= tie && line.1 > top.1) {
                top = line;
            }
        }
        let mut next = r;
        if round < rounds {
            for &line in lines {
                if line.1 > top.1 {
                    let cross = x + (at(top, x) - at(line, x)) / (line.1 - top.1);
                    if cross > x && cross < next {
                        next = cross;
                    }
                }
            }
        }
        sum.segment(x - low, at(top, x), next - low, at(top, next));
        x = next;
        if x >= r {
            break;
        }
    }
}
