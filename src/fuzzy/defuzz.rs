//! Defuzzification: turning an aggregated fuzzy set into a crisp output (seed 000 §3.1,
//! the turn and speed outputs of Fig 1).
//!
//! Integral defuzzifiers work on the aggregated membership sampled at the midpoints
//! `xᵢ = min + (i + ½)·(max − min)/resolution`, `i = 0..resolution`; both the compiled engine
//! and the reference evaluation produce those samples and share these functions.
//! Weighted defuzzifiers work on the list of activated terms, one entry per term (activations
//! of the same term grouped by the output's aggregation, or summed without one).
//! Invariant: no function here panics; an empty or all-zero set gives NaN.

use super::engine::{Defuzzifier, WeightedKind};
use super::term::Term;

/// The sample points of an integral defuzzifier.
#[inline]
pub fn sample_x(minimum: f64, maximum: f64, resolution: usize, i: usize) -> f64 {
    let dx = (maximum - minimum) / resolution as f64;
    minimum + (i as f64 + 0.5) * dx
}

/// Defuzzifies sampled memberships `mu` (length = resolution) over `[minimum, maximum]` with
/// an integral defuzzifier. Returns NaN when there is no area. Weighted defuzzifiers return NaN
/// here (they are not integral).
#[inline(always)]
pub fn integral(defuzzifier: &Defuzzifier, minimum: f64, maximum: f64, mu: &[f64]) -> f64 {
    let n = mu.len();
    if n == 0 {
        return f64::NAN;
    }
    let x = |i: usize| sample_x(minimum, maximum, n, i);
    match defuzzifier {
        Defuzzifier::Centroid { .. } => centroid(minimum, maximum, mu),
        Defuzzifier::Bisector { .. } => {
            // The sample(s) where the running area is closest to half the total; ties averaged.
            let total: f64 = mu.iter().filter(|y| !y.is_nan()).sum();
            if !(total > 0.0) || !total.is_finite() {
                return f64::NAN;
            }
            let mut running = 0.0;
            let (mut best, mut sum_x, mut count) = (f64::INFINITY, 0.0, 0usize);
            for (i, &y) in mu.iter().enumerate() {
                if !y.is_nan() {
                    running += y;
                }
                let e = (running / total - 0.5).abs();
                if e < best {
                    (best, sum_x, count) = (e, x(i), 1);
                } else if e == best {
                    sum_x += x(i);
                    count += 1;
                }
            }
            sum_x / count as f64
        }
        Defuzzifier::SmallestOfMaximum { .. }
        | Defuzzifier::LargestOfMaximum { .. }
        | Defuzzifier::MeanOfMaximum { .. } => {
            // Candidates: every sample at the (exact) global maximum, which must be positive.
            let Some(y_max) = largest(mu) else {
                return f64::NAN;
            };
            if !(y_max > 0.0) {
                return f64::NAN;
            }
            let (mut first, mut last, mut sum_x, mut count) = (f64::NAN, f64::NAN, 0.0, 0usize);
            for (i, &y) in mu.iter().enumerate() {
                if y == y_max {
                    if count == 0 {
                        first = x(i);
                    }
                    last = x(i);
                    sum_x += x(i);
                    count += 1;
                }
            }
            match defuzzifier {
                Defuzzifier::SmallestOfMaximum { .. } => first,
                Defuzzifier::LargestOfMaximum { .. } => last,
                _ => sum_x / count as f64,
            }
        }
        Defuzzifier::WeightedAverage { .. } | Defuzzifier::WeightedSum { .. } => f64::NAN,
    }
}

/// The largest of `ys`, or `None` when one is NaN. Searched in four independent lanes (the
/// maximum of numbers does not depend on their order; `±0` may come out either way, which the
/// callers, looking for a positive maximum, do not see).
#[inline(always)]
fn largest(ys: &[f64]) -> Option<f64> {
    let (chunks, tail) = ys.as_chunks::<4>();
    let mut top = [f64::NEG_INFINITY; 4];
    let mut nan = false;
    for chunk in chunks {
        for j in 0..4 {
            nan |= chunk[j].is_nan();
            top[j] = if chunk[j] > top[j] { chunk[j] } else { top[j] };
        }
    }
    for &y in tail {
        nan |= y.is_nan();
        top[0] = if y > top[0] { y } else { top[0] };
    }
    let best = top.into_iter().fold(f64::NEG_INFINITY, |a, b| if b > a { b } else { a });
    if nan { None } else { Some(best) }
}

/// Centre of area of the samples: `Σ μᵢ·xᵢ / Σ μᵢ`.
#[inline(always)]
pub fn centroid(minimum: f64, maximum: f64, mu: &[f64]) -> f64 {
    let n = mu.len();
    let dx = (maximum - minimum) / n as f64;
    let (mut area, mut moment) = (0.0, 0.0);
    for (i, &y) in mu.iter().enumerate() {
        let x = minimum + (i as f64 + 0.5) * dx;
        area += y;
        moment += y * x;
    }
    moment / area
}

/// One activated term as seen by a weighted defuzzifier.
#[derive(Debug, Clone, Copy)]
pub struct Weighted<'a> {
    /// The term.
    pub term: &'a Term,
    /// Its activation degree.
    pub degree: f64,
}

/// Weighted average (`sum_only = false`) or weighted sum of activated terms. `inputs` and
/// `outputs` are the engine's current input and output values, for linear and function terms.
pub fn weighted(kind: WeightedKind, terms: &[Weighted<'_>], inputs: &[f64], outputs: &[f64], sum_only: bool) -> f64 {
    weighted_result(weighted_fold(kind, terms, inputs, outputs, (0.0, 0.0)), sum_only)
}

/// Adds `terms` to the running `(Σ degree · value, Σ degree)` of a weighted defuzzifier, in
/// order (so a list folded in pieces gives the same sums as folded whole).
pub fn weighted_fold(
    kind: WeightedKind,
    terms: &[Weighted<'_>],
    inputs: &[f64],
    outputs: &[f64],
    (mut sum, mut weights): (f64, f64),
) -> (f64, f64) {
    for w in terms {
        let tsukamoto = match kind {
            WeightedKind::Tsukamoto => true,
            WeightedKind::TakagiSugeno => false,
            WeightedKind::Automatic => w.term.is_monotonic(),
        };
        let z = if tsukamoto {
            w.term.tsukamoto(w.degree).unwrap_or(f64::NAN)
        } else {
            // A Takagi-Sugeno term at the degree: constants and linear functions ignore it, a
            // formula reads it as `x`.
            w.term.membership_in(w.degree, inputs, outputs)
        };
        sum += w.degree * z;
        weights += w.degree;
    }
    (sum, weights)
}

/// The weighted average (or, with `sum_only`, the weighted sum) from the sums of
/// [`weighted_fold`]; NaN when no weight is positive (no term activated).
pub fn weighted_result((sum, weights): (f64, f64), sum_only: bool) -> f64 {
    if !(weights > 0.0) {
        return f64::NAN;
    }
    if sum_only { sum } else { sum / weights }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centroid_of_symmetric_samples_is_the_middle() {
        let mu = [0.0, 0.5, 1.0, 1.0, 0.5, 0.0];
        assert!((integral(&Defuzzifier::Centroid { resolution: 6 }, 0.0, 6.0, &mu) - 3.0).abs() < 1e-15);
        // Running area 0, 0.5, 1.5 (exactly half of 3 at x = 2.5), 2.5, …
        assert_eq!(integral(&Defuzzifier::Bisector { resolution: 6 }, 0.0, 6.0, &mu), 2.5);
        // Maximum plateau covers samples 2 and 3 at x = 2.5 and 3.5.
        assert_eq!(integral(&Defuzzifier::SmallestOfMaximum { resolution: 6 }, 0.0, 6.0, &mu), 2.5);
        assert_eq!(integral(&Defuzzifier::LargestOfMaximum { resolution: 6 }, 0.0, 6.0, &mu), 3.5);
        assert_eq!(integral(&Defuzzifier::MeanOfMaximum { resolution: 6 }, 0.0, 6.0, &mu), 3.0);
    }

    #[test]
    fn centroid_by_hand() {
        // Samples at x = 0.5, 1.5, 2.5, 3.5 with weights 1, 0, 0, 3 → (0.5 + 10.5) / 4.
        let mu = [1.0, 0.0, 0.0, 3.0];
        assert_eq!(centroid(0.0, 4.0, &mu), 11.0 / 4.0);
        assert!(centroid(0.0, 4.0, &[0.0; 4]).is_nan());
        assert!(integral(&Defuzzifier::MeanOfMaximum { resolution: 4 }, 0.0, 4.0, &[0.0; 4]).is_nan());
    }

    #[test]
    fn weighted_average_and_sum() {
        let a = Term::Constant { value: 10.0 };
        let b = Term::Linear { coefficients: vec![2.0, 1.0] };
        let terms = [Weighted { term: &a, degree: 0.25 }, Weighted { term: &b, degree: 0.75 }];
        // b = 2·3 + 1 = 7; average = (2.5 + 5.25) / 1.0.
        assert_eq!(weighted(WeightedKind::Automatic, &terms, &[3.0], &[], false), 7.75);
        assert_eq!(weighted(WeightedKind::Automatic, &terms, &[3.0], &[], true), 7.75);
        let ramp = Term::Ramp { start: 0.0, end: 10.0, height: 1.0 };
        let terms = [Weighted { term: &ramp, degree: 0.5 }];
        assert_eq!(weighted(WeightedKind::Automatic, &terms, &[], &[], false), 5.0);
    }
}
