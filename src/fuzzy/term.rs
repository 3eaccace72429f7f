//! Membership functions (linguistic terms) of seed 000 §3.1, Fig 1, and the wider family the
//! FuzzyLite Language knows.
//!
//! Every term maps a crisp value `x` to a membership degree. Shapes are scaled by an optional
//! `height` (default 1), as in FLL where a term's last, optional parameter is its height.
//! Invariants: a `NaN` input gives a `NaN` membership (the caller decides what that means)
//! except for the input-independent [`Term::Constant`] and [`Term::Linear`] and the formulas of
//! [`Term::Function`] (IEEE arithmetic on whatever they compute),
//! every shape except [`Term::Constant`], [`Term::Linear`], [`Term::Discrete`] and
//! [`Term::Function`] stays within `[0, height]`, and evaluation never panics.

use std::f64::consts::PI;

use super::formula::{Formula, FormulaError};

/// A membership function. Parameters are in the units of the variable that owns the term.
#[derive(Debug, Clone, PartialEq)]
pub enum Term {
    /// Rises from `a` to a peak at `b`, falls to `c`. Infinite `a`/`c` make a shoulder.
    Triangle { a: f64, b: f64, c: f64, height: f64 },
    /// Rises from `a` to `b`, flat to `c`, falls to `d`. Infinite `a`/`d` make a shoulder.
    Trapezoid { a: f64, b: f64, c: f64, d: f64, height: f64 },
    /// `height` on `[start, end]`, 0 elsewhere.
    Rectangle { start: f64, end: f64, height: f64 },
    /// Linear from 0 at `start` to `height` at `end` (either direction).
    Ramp { start: f64, end: f64, height: f64 },
    /// Gaussian bell `exp(-(x-mean)²/(2·sd²))`.
    Gaussian { mean: f64, sd: f64, height: f64 },
    /// Left half-gaussian up to `mean_a`, flat to `mean_b`, right half-gaussian after.
    GaussianProduct { mean_a: f64, sd_a: f64, mean_b: f64, sd_b: f64, height: f64 },
    /// Generalised bell `1 / (1 + |(x-center)/width|^(2·slope))`.
    Bell { center: f64, width: f64, slope: f64, height: f64 },
    /// Logistic `1 / (1 + exp(-slope·(x-inflection)))`.
    Sigmoid { inflection: f64, slope: f64, height: f64 },
    /// `|sigmoid(left, rising) − sigmoid(right, falling)|`.
    SigmoidDifference { left: f64, rising: f64, falling: f64, right: f64, height: f64 },
    /// `sigmoid(left, rising) · sigmoid(right, falling)`.
    SigmoidProduct { left: f64, rising: f64, falling: f64, right: f64, height: f64 },
    /// Smooth quadratic step from 0 at `start` to 1 at `end`.
    SShape { start: f64, end: f64, height: f64 },
    /// Smooth quadratic step from 1 at `start` to 0 at `end`.
    ZShape { start: f64, end: f64, height: f64 },
    /// S-shape from `bottom_left` to `top_left` times Z-shape from `top_right` to `bottom_right`.
    PiShape { bottom_left: f64, top_left: f64, top_right: f64, bottom_right: f64, height: f64 },
    /// Sharp peak `exp(-|10/width·(x-center)|)`.
    Spike { center: f64, width: f64, height: f64 },
    /// Raised cosine of the given `width` around `center`, 0 outside.
    Cosine { center: f64, width: f64, height: f64 },
    /// Concave curve through `inflection` (half height) reaching `height` at `end`.
    Concave { inflection: f64, end: f64, height: f64 },
    /// A constant value (Takagi-Sugeno consequents).
    Constant { value: f64 },
    /// `Σ cᵢ·inputᵢ + c_n` over the engine's input values (Takagi-Sugeno consequents).
    Linear { coefficients: Vec<f64> },
    /// Piecewise-linear through `(x, y)` points sorted by `x`; clamped outside.
    Discrete { points: Vec<(f64, f64)>, height: f64 },
    /// Quarter circle from 0 at `start` to 1 at `end` (centred on `end`, radius
    /// `|end − start|`), 1 past `end`, 0 before `start`; either direction.
    Arc { start: f64, end: f64, height: f64 },
    /// Upper half of an ellipse over `[start, end]` (1 at the middle), 0 outside.
    SemiEllipse { start: f64, end: f64, height: f64 },
    /// 1 from `start` on toward `direction` (any number above `start`, usually +∞, or below
    /// it, usually −∞), 0 elsewhere.
    Binary { start: f64, direction: f64, height: f64 },
    /// A formula of `x` and the engine's variables (FLL's `Function`), parsed once; its
    /// variable names are bound to the engine's inputs and outputs when it is compiled.
    Function(Box<Formula>),
}

/// Sigmoid without height: `1 / (1 + exp(-slope·(x-inflection)))`.
fn logistic(x: f64, inflection: f64, slope: f64) -> f64 {
    1.0 / (1.0 + (-slope * (x - inflection)).exp())
}

fn s_shape(x: f64, start: f64, end: f64) -> f64 {
    if x <= start {
        0.0
    } else if x <= 0.5 * (start + end) {
        2.0 * ((x - start) / (end - start)).powi(2)
    } else if x < end {
        1.0 - 2.0 * ((x - end) / (end - start)).powi(2)
    } else {
        1.0
    }
}

fn z_shape(x: f64, start: f64, end: f64) -> f64 {
    if x <= start {
        1.0
    } else if x <= 0.5 * (start + end) {
        1.0 - 2.0 * ((x - start) / (end - start)).powi(2)
    } else if x < end {
        2.0 * ((x - end) / (end - start)).powi(2)
    } else {
        0.0
    }
}

impl Term {
    /// The FLL class name of this term (`Triangle`, `Trapezoid`, …).
    pub fn class_name(&self) -> &'static str {
        match self {
            Term::Triangle { .. } => "Triangle",
            Term::Trapezoid { .. } => "Trapezoid",
            Term::Rectangle { .. } => "Rectangle",
            Term::Ramp { .. } => "Ramp",
            Term::Gaussian { .. } => "Gaussian",
            Term::GaussianProduct { .. } => "GaussianProduct",
            Term::Bell { .. } => "Bell",
            Term::Sigmoid { .. } => "Sigmoid",
            Term::SigmoidDifference { .. } => "SigmoidDifference",
            Term::SigmoidProduct { .. } => "SigmoidProduct",
            Term::SShape { .. } => "SShape",
            Term::ZShape { .. } => "ZShape",
            Term::PiShape { .. } => "PiShape",
            Term::Spike { .. } => "Spike",
            Term::Cosine { .. } => "Cosine",
            Term::Concave { .. } => "Concave",
            Term::Constant { .. } => "Constant",
            Term::Linear { .. } => "Linear",
            Term::Discrete { .. } => "Discrete",
            Term::Arc { .. } => "Arc",
            Term::SemiEllipse { .. } => "SemiEllipse",
            Term::Binary { .. } => "Binary",
            Term::Function(_) => "Function",
        }
    }

    /// Builds a term from its class name (case-insensitive, `_`/`-` ignored, so `s_shape`,
    /// `SShape` and `sshape` are the same) and its FLL parameter list. Shape terms take one
    /// optional trailing parameter, their height.
    pub fn from_parameters(class: &str, p: &[f64]) -> Result<Term, String> {
        let key: String = class.chars().filter(|c| *c != '_' && *c != '-').flat_map(char::to_lowercase).collect();
        let fixed = |n: usize| -> Result<f64, String> {
            match p.len() {
                l if l == n => Ok(1.0),
                l if l == n + 1 => Ok(p[n]),
                l => Err(format!("term {class} takes {n} parameters (plus an optional height), got {l}")),
            }
        };
        if let Some(bad) = p.iter().position(|v| v.is_nan()) {
            return Err(format!("parameter {} of term {class} is NaN", bad + 1));
        }
        let term = match key.as_str() {
            "triangle" => {
                let height = fixed(3)?;
                Term::Triangle { a: p[0], b: p[1], c: p[2], height }
            }
            "trapezoid" => {
                let height = fixed(4)?;
                Term::Trapezoid { a: p[0], b: p[1], c: p[2], d: p[3], height }
            }
            "rectangle" => {
                let height = fixed(2)?;
                Term::Rectangle { start: p[0].min(p[1]), end: p[0].max(p[1]), height }
            }
            "ramp" => {
                let height = fixed(2)?;
                if p[0] == p[1] {
                    return Err(format!("term {class} needs different start and end, both are {}", p[0]));
                }
                Term::Ramp { start: p[0], end: p[1], height }
            }
            "gaussian" => {
                let height = fixed(2)?;
                Term::Gaussian { mean: p[0], sd: p[1], height }
            }
            "gaussianproduct" => {
                let height = fixed(4)?;
                Term::GaussianProduct { mean_a: p[0], sd_a: p[1], mean_b: p[2], sd_b: p[3], height }
            }
            "bell" => {
                let height = fixed(3)?;
                Term::Bell { center: p[0], width: p[1], slope: p[2], height }
            }
            "sigmoid" => {
                let height = fixed(2)?;
                Term::Sigmoid { inflection: p[0], slope: p[1], height }
            }
            "sigmoiddifference" => {
                let height = fixed(4)?;
                Term::SigmoidDifference { left: p[0], rising: p[1], falling: p[2], right: p[3], height }
            }
            "sigmoidproduct" => {
                let height = fixed(4)?;
                Term::SigmoidProduct { left: p[0], rising: p[1], falling: p[2], right: p[3], height }
            }
            "sshape" => {
                let height = fixed(2)?;
                Term::SShape { start: p[0], end: p[1], height }
            }
            "zshape" => {
                let height = fixed(2)?;
                Term::ZShape { start: p[0], end: p[1], height }
            }
            "pishape" => {
                let height = fixed(4)?;
                Term::PiShape { bottom_left: p[0], top_left: p[1], top_right: p[2], bottom_right: p[3], height }
            }
            "spike" => {
                let height = fixed(2)?;
                Term::Spike { center: p[0], width: p[1], height }
            }
            "cosine" => {
                let height = fixed(2)?;
                Term::Cosine { center: p[0], width: p[1], height }
            }
            "concave" => {
                let height = fixed(2)?;
                Term::Concave { inflection: p[0], end: p[1], height }
            }
            "arc" => {
                let height = fixed(2)?;
                Term::Arc { start: p[0], end: p[1], height }
            }
            "semiellipse" => {
                let height = fixed(2)?;
                Term::SemiEllipse { start: p[0].min(p[1]), end: p[0].max(p[1]), height }
            }
            "binary" => {
                let height = fixed(2)?;
                Term::Binary { start: p[0], direction: p[1], height }
            }
            "constant" => match p {
                [value] => Term::Constant { value: *value },
                _ => return Err(format!("term {class} takes 1 parameter, got {}", p.len())),
            },
            "linear" => Term::Linear { coefficients: p.to_vec() },
            "discrete" => {
                if p.len() < 2 {
                    return Err(format!("term {class} needs at least one x y pair"));
                }
                let (pairs, height) =
                    if p.len().is_multiple_of(2) { (p, 1.0) } else { (&p[..p.len() - 1], p[p.len() - 1]) };
                if !(0.0..=1.0).contains(&height) {
                    return Err(format!(
                        "term {class} has an odd number of values: the last, {height}, would be its height, \
                         which must be in [0, 1]; give x y pairs"
                    ));
                }
                let points: Vec<(f64, f64)> = pairs.chunks_exact(2).map(|c| (c[0], c[1])).collect();
                if points.windows(2).any(|w| w[1].0 < w[0].0) {
                    return Err(format!("term {class} needs its x values in ascending order"));
                }
                Term::Discrete { points, height }
            }
            "function" => {
                return Err(format!("term {class} takes a formula (Term::function), not a list of numbers"));
            }
            _ => return Err(format!("unknown term class '{class}'")),
        };
        Ok(term)
    }

    /// A [`Term::Function`] of the formula `text` (`x` is the value the membership is
    /// evaluated at; other names are the engine's variables).
    pub fn function(text: &str) -> Result<Term, FormulaError> {
        Ok(Term::Function(Box::new(Formula::parse(text)?)))
    }

    /// The formula of a [`Term::Function`].
    pub fn formula(&self) -> Option<&Formula> {
        match self {
            Term::Function(f) => Some(f),
            _ => None,
        }
    }

    /// The FLL parameter list of this term (height appended only when it is not 1; none for
    /// a [`Term::Function`], whose parameter is its formula).
    pub fn parameters(&self) -> Vec<f64> {
        let (mut v, height) = match self {
            Term::Triangle { a, b, c, height } => (vec![*a, *b, *c], *height),
            Term::Trapezoid { a, b, c, d, height } => (vec![*a, *b, *c, *d], *height),
            Term::Rectangle { start, end, height }
            | Term::Arc { start, end, height }
            | Term::SemiEllipse { start, end, height }
            | Term::Ramp { start, end, height }
            | Term::SShape { start, end, height }
            | Term::ZShape { start, end, height } => (vec![*start, *end], *height),
            Term::Gaussian { mean, sd, height } => (vec![*mean, *sd], *height),
            Term::GaussianProduct { mean_a, sd_a, mean_b, sd_b, height } => {
                (vec![*mean_a, *sd_a, *mean_b, *sd_b], *height)
            }
            Term::Bell { center, width, slope, height } => (vec![*center, *width, *slope], *height),
            Term::Sigmoid { inflection, slope, height } => (vec![*inflection, *slope], *height),
            Term::SigmoidDifference { left, rising, falling, right, height }
            | Term::SigmoidProduct { left, rising, falling, right, height } => {
                (vec![*left, *rising, *falling, *right], *height)
            }
            Term::PiShape { bottom_left, top_left, top_right, bottom_right, height } => {
                (vec![*bottom_left, *top_left, *top_right, *bottom_right], *height)
            }
            Term::Spike { center, width, height } | Term::Cosine { center, width, height } => {
                (vec![*center, *width], *height)
            }
            Term::Concave { inflection, end, height } => (vec![*inflection, *end], *height),
            Term::Binary { start, direction, height } => (vec![*start, *direction], *height),
            Term::Constant { value } => (vec![*value], 1.0),
            Term::Linear { coefficients } => (coefficients.clone(), 1.0),
            Term::Discrete { points, height } => (points.iter().flat_map(|(x, y)| [*x, *y]).collect(), *height),
            Term::Function(_) => (Vec::new(), 1.0),
        };
        if height != 1.0 {
            v.push(height);
        }
        v
    }

    /// Checks that the parameters describe a real membership function: every parameter
    /// finite (except one shoulder of a Triangle or Trapezoid: `a` = −∞ or the last = +∞, not
    /// both), the height in `[0, 1]`, positive widths where the shape divides by them.
    pub fn check(&self) -> Result<(), String> {
        if let Term::Function(_) = self {
            // Parsed when it was built; its names are checked against the engine's variables.
            return Ok(());
        }
        let params = self.parameters_with_height();
        let height = match self {
            Term::Constant { .. } | Term::Linear { .. } => 1.0,
            _ => params[params.len() - 1],
        };
        if !(0.0..=1.0).contains(&height) {
            return Err(format!("height must be in [0, 1], found {height}"));
        }
        let last = params.len().saturating_sub(2);
        for (i, p) in params.iter().enumerate() {
            let shoulder = match self {
                Term::Triangle { .. } | Term::Trapezoid { .. } => {
                    (i == 0 && *p == f64::NEG_INFINITY) || (i == last && *p == f64::INFINITY)
                }
                // Binary's direction is usually ±∞.
                Term::Binary { .. } => i == 1 && p.is_infinite(),
                _ => false,
            };
            if !p.is_finite() && !shoulder {
                return Err(format!("parameter {} is {p}; it must be a finite number", i + 1));
            }
        }
        if let Term::Triangle { a, c, .. } | Term::Trapezoid { a, d: c, .. } = *self
            && a.is_infinite()
            && c.is_infinite()
        {
            return Err("both ends are infinite: the term would be constant".into());
        }
        let width = match *self {
            Term::Gaussian { sd, .. } => Some(sd),
            Term::GaussianProduct { sd_a, sd_b, .. } => Some(sd_a.min(sd_b)),
            Term::Bell { width, .. } | Term::Spike { width, .. } | Term::Cosine { width, .. } => Some(width),
            _ => None,
        };
        if let Some(w) = width
            && w <= 0.0
        {
            return Err(format!("width {w} must be positive"));
        }
        if self.derived().iter().any(|d| !d.is_finite()) {
            return Err("its parameters overflow its arithmetic (a span between them, its square or a width's \
                        reciprocal is beyond the largest number), so it could only give NaN or infinity"
                .into());
        }
        match *self {
            Term::Arc { start, end, .. } | Term::SemiEllipse { start, end, .. } if start == end => {
                Err(format!("start and end are both {start}; the term needs a width"))
            }
            Term::Binary { start, direction, .. } if start == direction => {
                Err(format!("direction {direction} equals the start; it must lie above or below it"))
            }
            _ => Ok(()),
        }
    }

    /// What the membership function computes from its parameters alone before it reads `x`:
    /// the spans it divides by or squares, the reciprocals of its widths and the ends it
    /// compares `x` with (shoulders at ±∞ left out). [`Term::check`] refuses a term where one
    /// is not finite.
    fn derived(&self) -> Vec<f64> {
        // A span between two parameters, 0 when one is an infinite shoulder.
        let span = |p: f64, q: f64| if p.is_finite() && q.is_finite() { q - p } else { 0.0 };
        match *self {
            Term::Triangle { a, b, c, .. } => vec![span(a, b), span(b, c)],
            Term::Trapezoid { a, b, c, d, .. } => vec![span(a, b), span(b, c), span(c, d)],
            Term::Ramp { start, end, .. } | Term::SShape { start, end, .. } | Term::ZShape { start, end, .. } => {
                vec![end - start, 0.5 * (start + end)]
            }
            Term::PiShape { bottom_left, top_left, top_right, bottom_right, .. } => vec![
                top_left - bottom_left,
                0.5 * (bottom_left + top_left),
                bottom_right - top_right,
                0.5 * (top_right + bottom_right),
            ],
            Term::Gaussian { sd, .. } => vec![2.0 * (sd * sd), 1.0 / (2.0 * (sd * sd))],
            Term::GaussianProduct { sd_a, sd_b, .. } => {
                vec![2.0 * (sd_a * sd_a), 1.0 / (2.0 * (sd_a * sd_a)), 2.0 * (sd_b * sd_b), 1.0 / (2.0 * (sd_b * sd_b))]
            }
            Term::Spike { width, .. } => vec![10.0 / width],
            Term::Cosine { center, width, .. } => vec![2.0 / width * PI, center - 0.5 * width, center + 0.5 * width],
            Term::Concave { inflection, end, .. } => vec![end - inflection, 2.0 * end - inflection],
            Term::Discrete { ref points, .. } => points.windows(2).map(|w| w[1].0 - w[0].0).collect(),
            Term::Arc { start, end, .. } => vec![(end - start) * (end - start)],
            Term::SemiEllipse { start, end, .. } => {
                let r = 0.5 * (end - start);
                vec![r * r, start + r]
            }
            _ => Vec::new(),
        }
    }

    /// Every parameter, the height last (1 for terms without one).
    fn parameters_with_height(&self) -> Vec<f64> {
        let mut v = self.parameters();
        if v.len() == self.shape_parameter_count() {
            v.push(1.0);
        }
        v
    }

    /// Parameters of a shape term without its height.
    fn shape_parameter_count(&self) -> usize {
        match self {
            Term::Rectangle { .. }
            | Term::Ramp { .. }
            | Term::SShape { .. }
            | Term::ZShape { .. }
            | Term::Gaussian { .. }
            | Term::Sigmoid { .. }
            | Term::Spike { .. }
            | Term::Cosine { .. }
            | Term::Concave { .. }
            | Term::Arc { .. }
            | Term::SemiEllipse { .. }
            | Term::Binary { .. } => 2,
            Term::Triangle { .. } | Term::Bell { .. } => 3,
            Term::Trapezoid { .. }
            | Term::GaussianProduct { .. }
            | Term::SigmoidDifference { .. }
            | Term::SigmoidProduct { .. }
            | Term::PiShape { .. } => 4,
            Term::Constant { .. } => 1,
            Term::Linear { coefficients } => coefficients.len(),
            Term::Discrete { points, .. } => 2 * points.len(),
            Term::Function(_) => 0,
        }
    }

    /// True when the term's value depends on the engine's variables ([`Term::Linear`], a
    /// [`Term::Function`] that names some).
    pub fn depends_on_inputs(&self) -> bool {
        match self {
            Term::Linear { .. } => true,
            Term::Function(f) => f.reads_variables(),
            _ => false,
        }
    }

    /// Membership of `x`. `inputs` are the engine's current input values, used only by
    /// [`Term::Linear`], whose coefficient past the last input multiplies 1 (the constant),
    /// and by a [`Term::Function`] (which reads no output here: see [`Term::membership_in`]).
    pub fn membership_with(&self, x: f64, inputs: &[f64]) -> f64 {
        self.membership_in(x, inputs, &[])
    }

    /// Membership of `x` with the engine's current input and output values: a bound
    /// [`Term::Function`] reads both (a value missing from them reads as NaN).
    pub fn membership_in(&self, x: f64, inputs: &[f64], outputs: &[f64]) -> f64 {
        match self {
            Term::Function(f) => f.eval(x, inputs, outputs),
            Term::Linear { coefficients } => {
                // One coefficient per input, plus an optional constant last.
                let mut sum = 0.0;
                for (i, c) in coefficients.iter().enumerate() {
                    sum += c * inputs.get(i).copied().unwrap_or(1.0);
                }
                sum
            }
            _ => self.membership(x),
        }
    }

    /// `out[k] = self.membership(xs[k])` for every `k` (as many as the shorter of the two):
    /// the term's kind is matched once, then each kind runs its own loop of the same formula.
    /// On x86-64 processors with AVX2 the loops are compiled for it (chosen at run time; the
    /// same operations, so the same bits).
    pub fn membership_column(&self, xs: &[f64], out: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor runs AVX2 instructions, checked just above.
            return unsafe { self.membership_column_avx2(xs, out) };
        }
        self.membership_column_here(xs, out)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn membership_column_avx2(&self, xs: &[f64], out: &mut [f64]) {
        self.membership_column_here(xs, out)
    }

    #[inline(always)]
    fn membership_column_here(&self, xs: &[f64], out: &mut [f64]) {
        // One loop per kind, so that each inlines `membership` with its kind known.
        macro_rules! by_kind {
            ($($kind:ident),*) => {
                match self {
                    $(Term::$kind { .. } => {
                        for (y, &x) in out.iter_mut().zip(xs) {
                            *y = self.membership_inline(x);
                        }
                    })*
                    Term::Function(_) => {
                        for (y, &x) in out.iter_mut().zip(xs) {
                            *y = self.membership(x);
                        }
                    }
                }
            };
        }
        by_kind!(
            Triangle,
            Trapezoid,
            Rectangle,
            Ramp,
            Gaussian,
            GaussianProduct,
            Bell,
            Sigmoid,
            SigmoidDifference,
            SigmoidProduct,
            SShape,
            ZShape,
            PiShape,
            Spike,
            Cosine,
            Concave,
            Constant,
            Linear,
            Discrete,
            Arc,
            SemiEllipse,
            Binary
        )
    }

    /// Membership of `x` for every term that does not depend on inputs; [`Term::Linear`]
    /// evaluates with all inputs at 0 here (use [`Term::membership_with`]).
    pub fn membership(&self, x: f64) -> f64 {
        self.membership_inline(x)
    }

    #[inline(always)]
    fn membership_inline(&self, x: f64) -> f64 {
        match self {
            Term::Constant { value } => return *value,
            Term::Linear { .. } => return self.membership_with(x, &[]),
            Term::Function(f) => return f.eval(x, &[], &[]),
            _ if x.is_nan() => return f64::NAN,
            _ => {}
        }
        // Unit shape first, then the height, as `height · shape(x)`.
        let (shape, height) = match *self {
            Term::Triangle { a, b, c, height } => {
                let y = if x < a || x > c {
                    0.0
                } else if x == b || (a == f64::NEG_INFINITY && x < b) || (c == f64::INFINITY && x > b) {
                    1.0
                } else if x < b {
                    (x - a) / (b - a)
                } else {
                    (c - x) / (c - b)
                };
                (y, height)
            }
            Term::Trapezoid { a, b, c, d, height } => (trapezoid(x, a, b, c, d), height),
            Term::Rectangle { start, end, height } => (if start <= x && x <= end { 1.0 } else { 0.0 }, height),
            Term::Ramp { start, end, height } => {
                let y = if start < end {
                    if x <= start {
                        0.0
                    } else if x >= end {
                        1.0
                    } else {
                        (x - start) / (end - start)
                    }
                } else if x >= start {
                    0.0
                } else if x <= end {
                    1.0
                } else {
                    (start - x) / (start - end)
                };
                (y, height)
            }
            Term::Gaussian { mean, sd, height } => ((-(x - mean) * (x - mean) / (2.0 * (sd * sd))).exp(), height),
            Term::GaussianProduct { mean_a, sd_a, mean_b, sd_b, height } => {
                let a = if x < mean_a { (-(x - mean_a) * (x - mean_a) / (2.0 * (sd_a * sd_a))).exp() } else { 1.0 };
                let b = if x > mean_b { (-(x - mean_b) * (x - mean_b) / (2.0 * (sd_b * sd_b))).exp() } else { 1.0 };
                (a * b, height)
            }
            Term::Bell { center, width, slope, height } => {
                (1.0 / (1.0 + ((x - center) / width).abs().powf(2.0 * slope)), height)
            }
            Term::Sigmoid { inflection, slope, height } => (logistic(x, inflection, slope), height),
            Term::SigmoidDifference { left, rising, falling, right, height } => {
                ((logistic(x, left, rising) - logistic(x, right, falling)).abs(), height)
            }
            Term::SigmoidProduct { left, rising, falling, right, height } => {
                (logistic(x, left, rising) * logistic(x, right, falling), height)
            }
            Term::SShape { start, end, height } => (s_shape(x, start, end), height),
            Term::ZShape { start, end, height } => (z_shape(x, start, end), height),
            Term::PiShape { bottom_left, top_left, top_right, bottom_right, height } => {
                (s_shape(x, bottom_left, top_left) * z_shape(x, top_right, bottom_right), height)
            }
            Term::Spike { center, width, height } => ((-(10.0 / width * (x - center)).abs()).exp(), height),
            Term::Cosine { center, width, height } => {
                let y = if x < center - 0.5 * width || x > center + 0.5 * width {
                    0.0
                } else {
                    0.5 * (1.0 + (2.0 / width * PI * (x - center)).cos())
                };
                (y, height)
            }
            Term::Concave { inflection, end, height } => {
                let y = if inflection <= end && x < end {
                    (end - inflection) / (2.0 * end - inflection - x)
                } else if inflection > end && x > end {
                    (inflection - end) / (inflection - 2.0 * end + x)
                } else {
                    1.0
                };
                (y, height)
            }
            Term::Constant { .. } | Term::Linear { .. } | Term::Function(_) => return f64::NAN,
            Term::Discrete { ref points, height } => (interpolate(points, x), height),
            Term::Arc { start, end, height } => {
                let r = end - start;
                let inside = if r > 0.0 { start <= x && x <= end } else { end <= x && x <= start };
                let past = if r > 0.0 { x > end } else { x < end };
                let y = if inside {
                    (r * r - (x - end) * (x - end)).max(0.0).sqrt() / r.abs()
                } else if past {
                    1.0
                } else {
                    0.0
                };
                (y, height)
            }
            Term::SemiEllipse { start, end, height } => {
                let r = 0.5 * (end - start);
                let c = start + r;
                let y = if start <= x && x <= end { (r * r - (x - c) * (x - c)).max(0.0).sqrt() / r } else { 0.0 };
                (y, height)
            }
            Term::Binary { start, direction, height } => {
                let on = (direction > start && x >= start) || (direction < start && x <= start);
                (if on { 1.0 } else { 0.0 }, height)
            }
        };
        height * shape
    }

    /// `out[k] = self.tsukamoto(degrees[k])`, NaN for `None` (as many as the shorter of the
    /// two): the kind matched once, as [`Term::membership_column`] (and compiled for AVX2 as
    /// it is).
    pub fn tsukamoto_column(&self, degrees: &[f64], out: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor runs AVX2 instructions, checked just above.
            return unsafe { self.tsukamoto_column_avx2(degrees, out) };
        }
        self.tsukamoto_column_here(degrees, out)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn tsukamoto_column_avx2(&self, degrees: &[f64], out: &mut [f64]) {
        self.tsukamoto_column_here(degrees, out)
    }

    #[inline(always)]
    fn tsukamoto_column_here(&self, degrees: &[f64], out: &mut [f64]) {
        macro_rules! by_kind {
            ($($kind:ident),*) => {
                match self {
                    $(Term::$kind { .. } => {
                        for (z, &d) in out.iter_mut().zip(degrees) {
                            *z = self.tsukamoto_inline(d).unwrap_or(f64::NAN);
                        }
                    })*
                    _ => out.fill(f64::NAN),
                }
            };
        }
        by_kind!(Ramp, Sigmoid, SShape, ZShape, Concave, Arc)
    }

    /// The crisp value whose membership equals `degree`, for the monotonic terms used by
    /// Tsukamoto inference (`Ramp`, `Sigmoid`, `SShape`, `ZShape`, `Concave`, `Arc`); `None` for
    /// terms without a unique inverse.
    pub fn tsukamoto(&self, degree: f64) -> Option<f64> {
        self.tsukamoto_inline(degree)
    }

    #[inline(always)]
    fn tsukamoto_inline(&self, degree: f64) -> Option<f64> {
        let w = degree;
        Some(match *self {
            Term::Ramp { start, end, height } => start + (end - start) * (w / height),
            Term::Sigmoid { inflection, slope, height } => {
                inflection + ((w / height) / (1.0 - w / height)).ln() / slope
            }
            Term::SShape { start, end, height } => {
                let w = w / height;
                if w <= 0.5 {
                    start + (end - start) * (w / 2.0).sqrt()
                } else {
                    end + (start - end) * ((1.0 - w) / 2.0).sqrt()
                }
            }
            Term::ZShape { start, end, height } => {
                let w = w / height;
                if w <= 0.5 {
                    end + (start - end) * (w / 2.0).sqrt()
                } else {
                    start + (end - start) * ((1.0 - w) / 2.0).sqrt()
                }
            }
            Term::Concave { inflection, end, height } => 2.0 * end - inflection + height * (inflection - end) / w,
            Term::Arc { start, end, height } => {
                let r = end - start;
                let y = w * r / height;
                end - r.signum() * (r * r - y * y).max(0.0).sqrt()
            }
            _ => return None,
        })
    }

    /// True for the monotonic terms that [`Term::tsukamoto`] can invert.
    pub fn is_monotonic(&self) -> bool {
        matches!(
            self,
            Term::Ramp { .. }
                | Term::Sigmoid { .. }
                | Term::SShape { .. }
                | Term::ZShape { .. }
                | Term::Concave { .. }
                | Term::Arc { .. }
        )
    }
}

/// Linear interpolation through sorted points, clamped to the end values outside.
fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    let (first, last) = match (points.first(), points.last()) {
        (Some(f), Some(l)) => (*f, *l),
        _ => return 0.0,
    };
    if x <= first.0 {
        return first.1;
    }
    if x >= last.0 {
        return last.1;
    }
    // First point with p.x > x; it exists and is not the first point.
    let upper = points.partition_point(|p| p.0 <= x);
    let (x0, y0) = points[upper - 1];
    let (x1, y1) = points[upper];
    if x1 == x0 {
        return y1;
    }
    y0 + (y1 - y0) * (x - x0) / (x1 - x0)
}

/// Membership of `x` (not NaN) in the trapezoid `(a, b, c, d)`: 0 outside `[a, d]`, 1 on
/// `[b, c]` (and on the open side of a shoulder, `a` = −∞ or `d` = +∞), linear between.
pub(crate) fn trapezoid(x: f64, a: f64, b: f64, c: f64, d: f64) -> f64 {
    if x < a || x > d {
        0.0
    } else if (b <= x && x <= c) || (a == f64::NEG_INFINITY && x < b) || (d == f64::INFINITY && x > c) {
        1.0
    } else if x < b {
        (x - a) / (b - a)
    } else {
        (d - x) / (d - c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(class: &str, p: &[f64]) -> Term {
        Term::from_parameters(class, p).unwrap()
    }

    #[test]
    fn triangle_by_hand() {
        let tri = t("Triangle", &[0.0, 1.0, 3.0]);
        assert_eq!(tri.membership(-0.1), 0.0);
        assert_eq!(tri.membership(0.5), 0.5);
        assert_eq!(tri.membership(1.0), 1.0);
        assert_eq!(tri.membership(2.0), 0.5);
        assert_eq!(tri.membership(3.0), 0.0);
        assert!(tri.membership(f64::NAN).is_nan());
        let shoulder = t("Triangle", &[f64::NEG_INFINITY, 0.0, 1.0]);
        assert_eq!(shoulder.membership(-1e300), 1.0);
    }

    #[test]
    fn trapezoid_and_height() {
        let tr = t("Trapezoid", &[0.0, 1.0, 2.0, 4.0, 0.5]);
        assert_eq!(tr.membership(0.5), 0.25);
        assert_eq!(tr.membership(1.5), 0.5);
        assert_eq!(tr.membership(3.0), 0.25);
        assert_eq!(tr.membership(4.5), 0.0);
        assert_eq!(tr.parameters(), vec![0.0, 1.0, 2.0, 4.0, 0.5]);
    }

    #[test]
    fn smooth_shapes_by_hand() {
        let s = t("SShape", &[0.0, 2.0]);
        assert_eq!(s.membership(0.5), 2.0 * 0.25 * 0.25);
        assert_eq!(s.membership(1.0), 0.5);
        assert_eq!(s.membership(1.5), 1.0 - 2.0 * 0.25 * 0.25);
        let z = t("ZShape", &[0.0, 2.0]);
        assert!((z.membership(0.5) + s.membership(0.5) - 1.0).abs() < 1e-15);
        let g = t("Gaussian", &[1.0, 2.0]);
        assert!((g.membership(3.0) - (-0.5f64).exp()).abs() < 1e-15);
        let c = t("Cosine", &[0.0, 2.0]);
        assert!((c.membership(0.5) - 0.5).abs() < 1e-15);
        assert_eq!(c.membership(1.5), 0.0);
        let d = t("Discrete", &[0.0, 0.0, 1.0, 1.0, 3.0, 0.0]);
        assert_eq!(d.membership(2.0), 0.5);
        assert_eq!(d.membership(-5.0), 0.0);
        let sp = t("Spike", &[0.0, 10.0]);
        assert!((sp.membership(1.0) - (-1.0f64).exp()).abs() < 1e-15);
        let bell = t("Bell", &[0.0, 2.0, 1.0]);
        assert_eq!(bell.membership(2.0), 0.5);
        let concave = t("Concave", &[0.5, 1.0]);
        assert_eq!(concave.membership(0.5), 0.5);
        assert_eq!(concave.membership(1.2), 1.0);
    }

    #[test]
    fn tsukamoto_inverts_monotonic_terms() {
        for term in [
            t("Ramp", &[0.0, 2.0]),
            t("Ramp", &[2.0, 0.0]),
            t("Sigmoid", &[1.0, 3.0]),
            t("SShape", &[0.0, 2.0]),
            t("ZShape", &[0.0, 2.0]),
            t("Concave", &[0.5, 1.0]),
            t("Concave", &[1.0, 0.5]),
        ] {
            for w in [0.1, 0.3, 0.5, 0.7, 0.9] {
                let x = term.tsukamoto(w).unwrap();
                assert!((term.membership(x) - w).abs() < 1e-12, "{term:?} at {w}: x={x}");
            }
        }
    }

    #[test]
    fn bad_parameters_are_errors() {
        assert!(Term::from_parameters("Triangle", &[0.0, 1.0]).is_err());
        assert!(Term::from_parameters("Triangle", &[0.0, f64::NAN, 1.0]).is_err());
        assert!(Term::from_parameters("Blob", &[0.0]).is_err());
        assert!(Term::from_parameters("Discrete", &[1.0, 0.0, 0.0, 1.0]).is_err());
    }

    #[test]
    fn infinite_and_out_of_range_parameters_fail_the_check() {
        let (inf, ninf) = (f64::INFINITY, f64::NEG_INFINITY);
        let check = |class: &str, p: &[f64]| Term::from_parameters(class, p).and_then(|t| t.check());
        assert!(check("Triangle", &[ninf, 15.0, inf]).is_err());
        assert!(check("Triangle", &[ninf, 15.0, 20.0]).is_ok());
        assert!(check("Trapezoid", &[0.0, 1.0, 2.0, inf]).is_ok());
        assert!(check("Triangle", &[0.0, inf, 20.0]).is_err());
        assert!(check("Gaussian", &[5.0, inf]).is_err());
        assert!(check("Gaussian", &[5.0, 0.0]).is_err());
        assert!(check("Triangle", &[0.0, 1.0, 2.0, inf]).is_err());
        assert!(check("Triangle", &[0.0, 1.0, 2.0, -1.0]).is_err());
        assert!(check("Triangle", &[0.0, 1.0, 2.0, 0.5]).is_ok());
        assert!(check("Constant", &[inf]).is_err());
        assert!(check("Constant", &[3.0]).is_ok());
        assert!(check("Linear", &[1.0, inf]).is_err());
        assert!(check("Discrete", &[0.0, 0.0, 1.0, 1.0, 5.0]).is_err());
        assert!(check("Discrete", &[0.0, 0.0, 1.0, 1.0, 0.5]).is_ok());
        assert!(check("Discrete", &[0.0, 0.0, 1.0, inf]).is_err());
    }

    #[test]
    fn terms_whose_arithmetic_overflows_fail_the_check() {
        let term = |class: &str, p: &[f64]| Term::from_parameters(class, p).unwrap();
        // At a point where its shape is well above 0, each gives NaN or 0 (a span, square or
        // reciprocal at infinity), and the check says so.
        for (class, p, x) in [
            ("Arc", &[-1e308, 1e308][..], 0.0),
            ("SemiEllipse", &[-1e308, 1e308], 0.0),
            ("Arc", &[0.0, 1e200], 1e199),
            ("Triangle", &[-1e308, 1e308, 1e308], 0.0),
            ("Ramp", &[-1e308, 1e308], 1.0),
            ("SShape", &[-1e308, 1e308], -1e307),
            ("Gaussian", &[0.0, 1e-200], 0.0),
            ("Spike", &[0.0, 1e-320], 0.0),
            ("Cosine", &[0.0, 1e-320], 0.0),
            ("Discrete", &[-1e308, 0.0, 1e308, 1.0], 0.0),
        ] {
            let t = term(class, p);
            let m = t.membership(x);
            assert!(!(m.is_finite() && m > 0.0), "{class} {p:?} at {x}: {m}");
            let e = t.check().unwrap_err();
            assert!(e.contains("overflow its arithmetic"), "{class} {p:?}: {e}");
        }
        // Wide but computable.
        for (class, p) in
            [("Arc", &[-1e150, 1e150][..]), ("Triangle", &[-1e307, 0.0, 1e307]), ("Gaussian", &[0.0, 1e-100])]
        {
            assert_eq!(term(class, p).check(), Ok(()), "{class} {p:?}");
        }
    }

    #[test]
    fn arcs_ellipses_and_binaries_by_hand() {
        let half = 3f64.sqrt() / 2.0;
        // An arc rising from 0 to 2 (centred on 2), and one falling from 2 to 0.
        let up = t("Arc", &[0.0, 2.0]);
        let down = t("Arc", &[2.0, 0.0]);
        for (x, want) in [(-1.0, 0.0), (0.0, 0.0), (1.0, half), (2.0, 1.0), (3.0, 1.0)] {
            assert!((up.membership(x) - want).abs() < 1e-15, "up at {x}");
            assert!((down.membership(2.0 - x) - want).abs() < 1e-15, "down at {}", 2.0 - x);
        }
        for share in [0.1, 0.5, 0.9] {
            for (arc, h) in [(&up, 1.0), (&down, 1.0), (&t("Arc", &[1.0, 4.0, 0.8]), 0.8)] {
                let w = share * h;
                let x = arc.tsukamoto(w).unwrap();
                assert!((arc.membership(x) - w).abs() < 1e-12, "{arc:?} at {w}: {x}");
            }
        }
        let e = t("SemiEllipse", &[2.0, 0.0, 0.5]);
        assert_eq!(e.parameters(), vec![0.0, 2.0, 0.5]);
        for (x, want) in [(-0.1, 0.0), (0.0, 0.0), (0.5, 0.5 * half), (1.0, 0.5), (2.0, 0.0), (2.1, 0.0)] {
            assert!((e.membership(x) - want).abs() < 1e-15, "ellipse at {x}");
        }
        let right = t("Binary", &[0.5, f64::INFINITY]);
        let left = t("Binary", &[0.5, f64::NEG_INFINITY]);
        assert!(right.check().is_ok() && left.check().is_ok());
        assert_eq!([0.4, 0.5, 0.6].map(|x| right.membership(x)), [0.0, 1.0, 1.0]);
        assert_eq!([0.4, 0.5, 0.6].map(|x| left.membership(x)), [1.0, 1.0, 0.0]);
        assert!(right.membership(f64::NAN).is_nan());
        // Degenerate ones are refused by the check.
        assert!(t("Arc", &[1.0, 1.0]).check().is_err());
        assert!(t("SemiEllipse", &[1.0, 1.0]).check().is_err());
        assert!(t("Binary", &[1.0, 1.0]).check().is_err());
        assert!(t("Binary", &[f64::INFINITY, 1.0]).check().is_err());
    }

    #[test]
    fn membership_column_is_membership_bit_for_bit() {
        let terms = [
            t("Triangle", &[-1.0, 0.5, 2.0, 0.8]),
            t("Trapezoid", &[f64::NEG_INFINITY, -1.0, 0.0, 2.0]),
            t("Rectangle", &[-1.0, 1.0]),
            t("Ramp", &[2.0, -1.0]),
            t("Gaussian", &[0.3, 0.7]),
            t("GaussianProduct", &[-0.5, 0.4, 0.5, 0.9, 0.6]),
            t("Bell", &[0.0, 1.2, 2.5]),
            t("Sigmoid", &[0.2, -4.0]),
            t("SigmoidDifference", &[-1.0, 3.0, 2.0, 1.0]),
            t("SigmoidProduct", &[-1.0, 3.0, -2.0, 1.0]),
            t("SShape", &[-1.0, 1.5]),
            t("ZShape", &[-1.0, 1.5]),
            t("PiShape", &[-2.0, -1.0, 0.5, 2.0]),
            t("Spike", &[0.1, 2.0]),
            t("Cosine", &[0.0, 3.0]),
            t("Concave", &[0.5, 2.0]),
            t("Concave", &[0.5, -2.0]),
            t("Constant", &[0.25]),
            t("Linear", &[2.0, 1.0]),
            t("Discrete", &[-2.0, 0.0, 0.0, 1.0, 1.0, 0.2, 2.5, 0.9]),
            t("Arc", &[2.0, -1.0]),
            t("SemiEllipse", &[-1.5, 2.0]),
            t("Binary", &[0.0, f64::NEG_INFINITY]),
            Term::function("x^2 - 1").unwrap(),
        ];
        let mut xs: Vec<f64> = (0..=200).map(|i| -3.0 + 0.03 * i as f64).collect();
        xs.extend([f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -0.0]);
        for term in &terms {
            let mut column = vec![0.0; xs.len()];
            term.membership_column(&xs, &mut column);
            for (&x, &y) in xs.iter().zip(&column) {
                let want = term.membership(x);
                assert!(y.to_bits() == want.to_bits() || (y.is_nan() && want.is_nan()), "{term:?} at {x}: {y} {want}");
            }
            let degrees: Vec<f64> = (0..=100).map(|i| 0.01 * i as f64).chain([f64::NAN, -0.5, 1.5]).collect();
            let mut column = vec![0.0; degrees.len()];
            term.tsukamoto_column(&degrees, &mut column);
            for (&d, &z) in degrees.iter().zip(&column) {
                let want = term.tsukamoto(d).unwrap_or(f64::NAN);
                assert!(z.to_bits() == want.to_bits() || (z.is_nan() && want.is_nan()), "{term:?} at {d}: {z} {want}");
            }
        }
    }
}
