//! Linguistic variables (seed 000 §3.1; DESIGN.md §2): crisp inputs and outputs with their
//! named membership functions, and how an output is defuzzified. Plain data, below the rules
//! that name them ([`super::rule`]) and the engines that hold both ([`super::engine`]).

use super::norm::{SNorm, key};
use super::term::Term;

/// A term with its name within a variable.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedTerm {
    /// Name used in rules.
    pub name: String,
    /// The membership function.
    pub term: Term,
}

/// A crisp input with its linguistic terms.
#[derive(Debug, Clone, PartialEq)]
pub struct InputVariable {
    /// Name used in rules and data files.
    pub name: String,
    /// Free text.
    pub description: String,
    /// A disabled input makes every proposition on it 0.
    pub enabled: bool,
    /// Lower end of the range (may be `-inf`).
    pub minimum: f64,
    /// Upper end of the range (may be `+inf`).
    pub maximum: f64,
    /// Clamp input values into the range before fuzzifying.
    pub lock_range: bool,
    /// The terms.
    pub terms: Vec<NamedTerm>,
}

impl InputVariable {
    /// A new enabled input with no terms.
    pub fn new(name: &str, minimum: f64, maximum: f64) -> Self {
        InputVariable {
            name: name.to_string(),
            description: String::new(),
            enabled: true,
            minimum,
            maximum,
            lock_range: false,
            terms: Vec::new(),
        }
    }

    /// Adds a term (builder style).
    pub fn term(mut self, name: &str, term: Term) -> Self {
        self.terms.push(NamedTerm { name: name.to_string(), term });
        self
    }
}

/// A crisp output with its terms and how it is computed.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputVariable {
    /// Name used in rules and data files.
    pub name: String,
    /// Free text.
    pub description: String,
    /// A disabled output keeps its value and receives no activations.
    pub enabled: bool,
    /// Lower end of the range.
    pub minimum: f64,
    /// Upper end of the range.
    pub maximum: f64,
    /// Clamp the defuzzified value into the range.
    pub lock_range: bool,
    /// How activated terms are aggregated (`None`: at most one activation is allowed).
    pub aggregation: Option<SNorm>,
    /// How the aggregate becomes a crisp value (`None`: the output always takes its default).
    pub defuzzifier: Option<Defuzzifier>,
    /// Value when no rule fires or the result is undefined (a number or NaN).
    pub default_value: f64,
    /// When no rule fires or the result is undefined, keep the previous value (if it is a
    /// number) instead of taking the default.
    pub lock_previous: bool,
    /// The terms.
    pub terms: Vec<NamedTerm>,
}

/// How an output is defuzzified.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Defuzzifier {
    /// Centre of area of the aggregated set, sampled at `resolution` midpoints.
    Centroid {
        /// Number of samples over the output range.
        resolution: usize,
    },
    /// The value splitting the area in two halves.
    Bisector {
        /// Number of samples over the output range.
        resolution: usize,
    },
    /// Smallest value of maximal membership.
    SmallestOfMaximum {
        /// Number of samples over the output range.
        resolution: usize,
    },
    /// Largest value of maximal membership.
    LargestOfMaximum {
        /// Number of samples over the output range.
        resolution: usize,
    },
    /// Mean of the first plateau of maximal membership.
    MeanOfMaximum {
        /// Number of samples over the output range.
        resolution: usize,
    },
    /// `Σ wᵢ·zᵢ / Σ wᵢ` over activated terms (Takagi-Sugeno or Tsukamoto).
    WeightedAverage {
        /// Which value `zᵢ` a term contributes.
        kind: WeightedKind,
    },
    /// `Σ wᵢ·zᵢ` over activated terms.
    WeightedSum {
        /// Which value `zᵢ` a term contributes.
        kind: WeightedKind,
    },
}

/// Which value a term contributes to a weighted defuzzifier.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WeightedKind {
    /// Takagi-Sugeno for constant/linear terms, Tsukamoto for monotonic ones.
    Automatic,
    /// `z` is the term's value (constant, linear function of the inputs).
    TakagiSugeno,
    /// `z` is the crisp value where the monotonic term reaches the activation degree.
    Tsukamoto,
}

/// Default number of samples of integral defuzzifiers (as in current fuzzylite).
pub const DEFAULT_RESOLUTION: usize = 1000;

impl Defuzzifier {
    /// The FLL class name.
    pub fn name(&self) -> &'static str {
        match self {
            Defuzzifier::Centroid { .. } => "Centroid",
            Defuzzifier::Bisector { .. } => "Bisector",
            Defuzzifier::SmallestOfMaximum { .. } => "SmallestOfMaximum",
            Defuzzifier::LargestOfMaximum { .. } => "LargestOfMaximum",
            Defuzzifier::MeanOfMaximum { .. } => "MeanOfMaximum",
            Defuzzifier::WeightedAverage { .. } => "WeightedAverage",
            Defuzzifier::WeightedSum { .. } => "WeightedSum",
        }
    }

    /// The resolution of an integral defuzzifier, `None` for weighted ones.
    pub fn resolution(&self) -> Option<usize> {
        match *self {
            Defuzzifier::Centroid { resolution }
            | Defuzzifier::Bisector { resolution }
            | Defuzzifier::SmallestOfMaximum { resolution }
            | Defuzzifier::LargestOfMaximum { resolution }
            | Defuzzifier::MeanOfMaximum { resolution } => Some(resolution),
            _ => None,
        }
    }

    /// Builds a defuzzifier from its FLL class name and optional parameter (resolution for
    /// integral ones; `Automatic`, `TakagiSugeno` or `Tsukamoto` for weighted ones).
    pub fn from_name(name: &str, parameter: Option<&str>) -> Result<Defuzzifier, String> {
        let k = key(name);
        let resolution = || -> Result<usize, String> {
            match parameter {
                None => Ok(DEFAULT_RESOLUTION),
                Some(p) => p
                    .parse::<f64>()
                    .ok()
                    .filter(|r| r.fract() == 0.0 && *r >= 1.0 && *r <= 1e7)
                    .map(|r| r as usize)
                    .ok_or_else(|| format!("resolution must be a whole number from 1 to 10000000, found '{p}'")),
            }
        };
        let kind = || -> Result<WeightedKind, String> {
            match parameter.map(key).as_deref() {
                None | Some("automatic") => Ok(WeightedKind::Automatic),
                Some("takagisugeno") => Ok(WeightedKind::TakagiSugeno),
                Some("tsukamoto") => Ok(WeightedKind::Tsukamoto),
                Some(_) => Err(format!(
                    "weighted defuzzifier type must be Automatic, TakagiSugeno or Tsukamoto, found '{}'",
                    parameter.unwrap_or_default()
                )),
            }
        };
        Ok(match k.as_str() {
            "centroid" => Defuzzifier::Centroid { resolution: resolution()? },
            "bisector" => Defuzzifier::Bisector { resolution: resolution()? },
            "smallestofmaximum" | "som" => Defuzzifier::SmallestOfMaximum { resolution: resolution()? },
            "largestofmaximum" | "lom" => Defuzzifier::LargestOfMaximum { resolution: resolution()? },
            "meanofmaximum" | "mom" => Defuzzifier::MeanOfMaximum { resolution: resolution()? },
            "weightedaverage" => Defuzzifier::WeightedAverage { kind: kind()? },
            "weightedsum" => Defuzzifier::WeightedSum { kind: kind()? },
            _ => return Err(format!("unknown defuzzifier '{name}'")),
        })
    }
}

/// Why a finite range `[min, max]` cannot be computed with: its width is beyond the largest
/// number (`None` when it is not).
pub fn range_overflow(min: f64, max: f64) -> Option<String> {
    (min.is_finite() && max.is_finite() && !(max - min).is_finite())
        .then(|| format!("the range [{min:?}, {max:?}] is wider than the largest number"))
}

impl OutputVariable {
    /// Why this output's integral defuzzifier cannot be computed over its finite range: it sums
    /// `resolution` samples of `x` (and of `x` times a degree), which would pass the largest
    /// number (`None` when it would not).
    pub fn sum_overflow(&self) -> Option<String> {
        let d = self.defuzzifier?;
        let n = d.resolution()?;
        let (min, max) = (self.minimum, self.maximum);
        (min.is_finite() && max.is_finite() && !(n as f64 * min.abs().max(max.abs())).is_finite()).then(|| {
            format!("{} sums {n} samples over [{min:?}, {max:?}], which overflows; use a smaller range", d.name())
        })
    }

    /// A new enabled output: maximum aggregation, centroid at the default resolution,
    /// default value NaN.
    pub fn new(name: &str, minimum: f64, maximum: f64) -> Self {
        OutputVariable {
            name: name.to_string(),
            description: String::new(),
            enabled: true,
            minimum,
            maximum,
            lock_range: false,
            aggregation: Some(SNorm::Maximum),
            defuzzifier: Some(Defuzzifier::Centroid { resolution: DEFAULT_RESOLUTION }),
            default_value: f64::NAN,
            lock_previous: false,
            terms: Vec::new(),
        }
    }

    /// Adds a term (builder style).
    pub fn term(mut self, name: &str, term: Term) -> Self {
        self.terms.push(NamedTerm { name: name.to_string(), term });
        self
    }
}
