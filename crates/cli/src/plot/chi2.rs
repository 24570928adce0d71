//! The χ² quantile for the NIS bound line.

/// The `probability` quantile of the χ² distribution with `dof` degrees of
/// freedom: the NIS bound a consistent filter stays under that often.
/// `None` for `dof == 0` or a probability outside (0, 1).
///
/// ```
/// use kestrel_cli::plot::chi2_quantile;
/// let q = chi2_quantile(3, 0.99).unwrap();
/// assert!((q - 11.345).abs() < 1e-3);
/// assert_eq!(chi2_quantile(0, 0.99), None);
/// ```
pub fn chi2_quantile(dof: usize, probability: f64) -> Option<f64> {
    if dof == 0 || !(probability > 0.0 && probability < 1.0) {
        return None;
    }
    let a = dof as f64 / 2.0;
    let cdf = |x: f64| lower_gamma_regularized(a, x / 2.0);
    let mut hi = dof as f64 + 10.0;
    while cdf(hi) < probability {
        hi *= 2.0;
    }
    let mut lo = 0.0;
    // Bisection to the last representable digit: the cdf is monotone.
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if cdf(mid) < probability {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// ln Γ(a) for a positive multiple of ½, exactly by the recursion
/// Γ(a + 1) = a Γ(a) from Γ(1) = 1 and Γ(½) = √π.
fn ln_gamma_half(a: f64) -> f64 {
    let mut x = if a.fract() == 0.0 { 1.0 } else { 0.5 };
    let mut ln = if x == 1.0 {
        0.0
    } else {
        0.5 * std::f64::consts::PI.ln()
    };
    while x < a {
        ln += x.ln();
        x += 1.0;
    }
    ln
}

/// The regularised lower incomplete gamma function P(a, x), by its series
/// below a + 1 and by the continued fraction of 1 − P above (both converge
/// fast there).
fn lower_gamma_regularized(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let prefactor = (-x + a * x.ln() - ln_gamma_half(a)).exp();
    if x < a + 1.0 {
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..1000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        sum * prefactor
    } else {
        // Modified Lentz evaluation of the continued fraction.
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        1.0 - prefactor * h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_match_the_tables() {
        // Closed forms: dof 2 is exponential, q = −2 ln(1 − p).
        let q = chi2_quantile(2, 0.99).unwrap();
        assert!((q - (-2.0 * 0.01_f64.ln())).abs() < 1e-9, "{q}");
        // dof 1: q = z², z the normal 0.995 quantile 2.5758293035489.
        let q = chi2_quantile(1, 0.99).unwrap();
        assert!((q - 2.575_829_303_548_9_f64.powi(2)).abs() < 1e-9, "{q}");
        // Printed tables (3 decimals).
        for (dof, p, table) in [(3, 0.99, 11.345), (9, 0.99, 21.666), (6, 0.95, 12.592)] {
            let q = chi2_quantile(dof, p).unwrap();
            assert!((q - table).abs() < 5e-4, "dof {dof}: {q}");
        }
        assert_eq!(chi2_quantile(3, 1.0), None);
        assert_eq!(chi2_quantile(3, f64::NAN), None);
    }
}
