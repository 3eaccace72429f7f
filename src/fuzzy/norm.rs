//! Fuzzy operators: T-norms (conjunction, implication), S-norms (disjunction, aggregation)
//! and hedges — the connectives of the rule base in seed 000 §3.1.
//!
//! Invariants: for degrees in `[0, 1]` every T-norm has 1 as identity and 0 as absorbing
//! element (`T(a, 0) = 0`), every S-norm has 0 as identity (`S(a, 0) = a`); the compiled
//! engine relies on both to skip samples where a term is zero (only for degrees in `[0, 1]`:
//! weights and unbounded sums can push a degree above 1, where `T(d, 0)` may be positive).

/// A triangular norm (fuzzy AND).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TNorm {
    /// `min(a, b)`.
    Minimum,
    /// `a · b`.
    AlgebraicProduct,
    /// `max(0, a + b − 1)`.
    BoundedDifference,
    /// `min(a, b)` if `max(a, b) = 1`, else 0.
    DrasticProduct,
    /// `a·b / (2 − (a + b − a·b))`.
    EinsteinProduct,
    /// `a·b / (a + b − a·b)`, 0 when `a + b = 0`.
    HamacherProduct,
    /// `min(a, b)` if `a + b > 1`, else 0.
    NilpotentMinimum,
}

/// A triangular conorm (fuzzy OR).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SNorm {
    /// `max(a, b)`.
    Maximum,
    /// `a + b − a·b`.
    AlgebraicSum,
    /// `min(1, a + b)`.
    BoundedSum,
    /// `max(a, b)` if `min(a, b) = 0`, else 1.
    DrasticSum,
    /// `(a + b) / (1 + a·b)`.
    EinsteinSum,
    /// `(a + b − 2·a·b) / (1 − a·b)`, 1 when `a·b = 1`.
    HamacherSum,
    /// `max(a, b)` if `a + b < 1`, else 1.
    NilpotentMaximum,
    /// `(a + b) / max(1, a + b)`.
    NormalizedSum,
    /// `a + b`.
    UnboundedSum,
}

/// A linguistic hedge modifying a membership degree.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Hedge {
    /// `1 − x`.
    Not,
    /// `x²`.
    Very,
    /// `√x`.
    Somewhat,
    /// `2x²` below one half, `1 − 2(1−x)²` above.
    Extremely,
    /// `√(x/2)` below one half, `1 − √((1−x)/2)` above.
    Seldom,
    /// Always 1: `x is any` holds for every value.
    Any,
}

/// Canonical lookup key: lower case, `_`, `-` and spaces removed.
pub(crate) fn key(name: &str) -> String {
    name.chars().filter(|c| !matches!(c, '_' | '-' | ' ')).flat_map(char::to_lowercase).collect()
}

impl TNorm {
    /// Every T-norm, in FLL order.
    pub const ALL: [TNorm; 7] = [
        TNorm::Minimum,
        TNorm::AlgebraicProduct,
        TNorm::BoundedDifference,
        TNorm::DrasticProduct,
        TNorm::EinsteinProduct,
        TNorm::HamacherProduct,
        TNorm::NilpotentMinimum,
    ];

    /// Combines two degrees.
    #[inline]
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            TNorm::Minimum => {
                if a < b {
                    a
                } else {
                    b
                }
            }
            TNorm::AlgebraicProduct => a * b,
            TNorm::BoundedDifference => (a + b - 1.0).max(0.0),
            TNorm::DrasticProduct => {
                if a.max(b) == 1.0 {
                    a.min(b)
                } else {
                    0.0
                }
            }
            TNorm::EinsteinProduct => (a * b) / (2.0 - (a + b - a * b)),
            TNorm::HamacherProduct => {
                if a + b == 0.0 {
                    0.0
                } else {
                    (a * b) / (a + b - a * b)
                }
            }
            TNorm::NilpotentMinimum => {
                if a + b > 1.0 {
                    a.min(b)
                } else {
                    0.0
                }
            }
        }
    }

    /// The FLL class name.
    pub fn name(self) -> &'static str {
        match self {
            TNorm::Minimum => "Minimum",
            TNorm::AlgebraicProduct => "AlgebraicProduct",
            TNorm::BoundedDifference => "BoundedDifference",
            TNorm::DrasticProduct => "DrasticProduct",
            TNorm::EinsteinProduct => "EinsteinProduct",
            TNorm::HamacherProduct => "HamacherProduct",
            TNorm::NilpotentMinimum => "NilpotentMinimum",
        }
    }

    /// Looks a T-norm up by FLL class name (case, `_` and `-` ignored; `min` and `product`
    /// accepted as short forms).
    pub fn from_name(name: &str) -> Option<TNorm> {
        let k = key(name);
        match k.as_str() {
            "min" => return Some(TNorm::Minimum),
            "product" | "prod" => return Some(TNorm::AlgebraicProduct),
            _ => {}
        }
        TNorm::ALL.into_iter().find(|t| key(t.name()) == k)
    }
}

impl SNorm {
    /// Every S-norm, in FLL order.
    pub const ALL: [SNorm; 9] = [
        SNorm::Maximum,
        SNorm::AlgebraicSum,
        SNorm::BoundedSum,
        SNorm::DrasticSum,
        SNorm::EinsteinSum,
        SNorm::HamacherSum,
        SNorm::NilpotentMaximum,
        SNorm::NormalizedSum,
        SNorm::UnboundedSum,
    ];

    /// Combines two degrees.
    #[inline]
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            SNorm::Maximum => {
                if a > b {
                    a
                } else {
                    b
                }
            }
            SNorm::AlgebraicSum => a + b - a * b,
            SNorm::BoundedSum => (a + b).min(1.0),
            SNorm::DrasticSum => {
                if a.min(b) == 0.0 {
                    a.max(b)
                } else {
                    1.0
                }
            }
            SNorm::EinsteinSum => (a + b) / (1.0 + a * b),
            SNorm::HamacherSum => {
                if a * b == 1.0 {
                    1.0
                } else {
                    (a + b - 2.0 * a * b) / (1.0 - a * b)
                }
            }
            SNorm::NilpotentMaximum => {
                if a + b < 1.0 {
                    a.max(b)
                } else {
                    1.0
                }
            }
            SNorm::NormalizedSum => (a + b) / (a + b).max(1.0),
            SNorm::UnboundedSum => a + b,
        }
    }

    /// The FLL class name.
    pub fn name(self) -> &'static str {
        match self {
            SNorm::Maximum => "Maximum",
            SNorm::AlgebraicSum => "AlgebraicSum",
            SNorm::BoundedSum => "BoundedSum",
            SNorm::DrasticSum => "DrasticSum",
            SNorm::EinsteinSum => "EinsteinSum",
            SNorm::HamacherSum => "HamacherSum",
            SNorm::NilpotentMaximum => "NilpotentMaximum",
            SNorm::NormalizedSum => "NormalizedSum",
            SNorm::UnboundedSum => "UnboundedSum",
        }
    }

    /// Looks an S-norm up by FLL class name (case, `_` and `-` ignored; `max` and `sum`
    /// accepted as short forms).
    pub fn from_name(name: &str) -> Option<SNorm> {
        let k = key(name);
        match k.as_str() {
            "max" => return Some(SNorm::Maximum),
            "sum" | "probor" => return Some(SNorm::AlgebraicSum),
            _ => {}
        }
        SNorm::ALL.into_iter().find(|s| key(s.name()) == k)
    }
}

impl Hedge {
    /// Every hedge.
    pub const ALL: [Hedge; 6] = [Hedge::Not, Hedge::Very, Hedge::Somewhat, Hedge::Extremely, Hedge::Seldom, Hedge::Any];

    /// Modifies a degree.
    #[inline]
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Hedge::Not => 1.0 - x,
            Hedge::Very => x * x,
            Hedge::Somewhat => x.sqrt(),
            Hedge::Extremely => {
                if x <= 0.5 {
                    2.0 * x * x
                } else {
                    1.0 - 2.0 * (1.0 - x) * (1.0 - x)
                }
            }
            Hedge::Seldom => {
                if x <= 0.5 {
                    (x / 2.0).sqrt()
                } else {
                    1.0 - ((1.0 - x) / 2.0).sqrt()
                }
            }
            Hedge::Any => 1.0,
        }
    }

    /// The word used in rules.
    pub fn name(self) -> &'static str {
        match self {
            Hedge::Not => "not",
            Hedge::Very => "very",
            Hedge::Somewhat => "somewhat",
            Hedge::Extremely => "extremely",
            Hedge::Seldom => "seldom",
            Hedge::Any => "any",
        }
    }

    /// Looks a hedge up by its rule word.
    pub fn from_name(word: &str) -> Option<Hedge> {
        Hedge::ALL.into_iter().find(|h| h.name() == word)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GRID: [f64; 6] = [0.0, 0.1, 0.35, 0.5, 0.8, 1.0];

    #[test]
    fn identities_and_absorbing_elements() {
        for a in GRID {
            for t in TNorm::ALL {
                assert!((t.apply(a, 1.0) - a).abs() < 1e-15, "{t:?}({a},1)");
                assert_eq!(t.apply(a, 0.0), 0.0, "{t:?}({a},0)");
            }
            for s in SNorm::ALL {
                assert!((s.apply(a, 0.0) - a).abs() < 1e-15, "{s:?}({a},0)");
            }
        }
    }

    #[test]
    fn commutative_and_bounded() {
        for a in GRID {
            for b in GRID {
                for t in TNorm::ALL {
                    assert!((t.apply(a, b) - t.apply(b, a)).abs() < 1e-15);
                    assert!(t.apply(a, b) <= a.min(b) + 1e-15, "{t:?}");
                }
                for s in SNorm::ALL {
                    assert!((s.apply(a, b) - s.apply(b, a)).abs() < 1e-15);
                    assert!(s.apply(a, b) >= a.max(b) - 1e-15, "{s:?}");
                }
            }
        }
    }

    #[test]
    fn hand_values() {
        assert_eq!(TNorm::BoundedDifference.apply(0.7, 0.6), 0.7 + 0.6 - 1.0);
        assert_eq!(TNorm::NilpotentMinimum.apply(0.4, 0.5), 0.0);
        assert_eq!(TNorm::DrasticProduct.apply(0.4, 0.5), 0.0);
        assert_eq!(SNorm::DrasticSum.apply(0.4, 0.5), 1.0);
        assert_eq!(SNorm::NilpotentMaximum.apply(0.4, 0.5), 0.5);
        assert_eq!(SNorm::BoundedSum.apply(0.7, 0.6), 1.0);
        assert_eq!(Hedge::Very.apply(0.5), 0.25);
        assert_eq!(Hedge::Extremely.apply(0.25), 0.125);
        assert_eq!(Hedge::Seldom.apply(0.5), 0.5);
        assert_eq!(Hedge::Any.apply(0.0), 1.0);
    }

    #[test]
    fn names_round_trip() {
        for t in TNorm::ALL {
            assert_eq!(TNorm::from_name(t.name()), Some(t));
        }
        for s in SNorm::ALL {
            assert_eq!(SNorm::from_name(s.name()), Some(s));
        }
        assert_eq!(SNorm::from_name("algebraic_sum"), Some(SNorm::AlgebraicSum));
        assert_eq!(TNorm::from_name("nope"), None);
    }
}
