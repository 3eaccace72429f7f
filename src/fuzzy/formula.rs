//! Formulas of FuzzyLite `Function` terms: infix arithmetic over numbers, `x` (the value the
//! membership is evaluated at) and the engine's input and output variables by name, with the
//! operators and functions fuzzylite's `FunctionFactory` registers.
//!
//! Grammar, loosest binding first: `or`; `and`; `+ -`; `* / %`; prefix `-` / `+` (also spelled
//! `.-` / `.+`) over a power; `^` / `**` (right-associative); prefix `!` (logical not) and `~`
//! (negation), binding tighter than a power (`~x^2` is `(~x)^2`, `-x^2` is `-(x^2)`, as in
//! fuzzylite). Operands are numbers (`1`, `.5`, `2e-3`, `nan`, `inf`), `x`, variable names,
//! parenthesised formulas and calls `name(a, b)` of the functions listed in [`Func`]; `pi`
//! may be written without parentheses.
//!
//! A formula is parsed once ([`Formula::parse`]) into a postfix program; its variable names
//! are bound to input or output indices by [`Formula::bind`] (the compiled evaluators do it
//! on their own copy of the engine) and [`Formula::eval`] runs the program on a fixed stack,
//! allocating nothing. Arithmetic is IEEE's: NaN and the infinities propagate. Comparisons
//! and logical operators give 1 or 0 (NaN is true, as a non-zero number; `eq(nan, nan)` is 1,
//! as in fuzzylite). Sizes are bounded ([`MAX_CHARS`], [`MAX_CODE`], [`MAX_DEPTH`]) so no
//! formula can overflow the parser's or the evaluator's stack.

use std::f64::consts::PI;

/// Longest formula, in characters.
pub const MAX_CHARS: usize = 4096;
/// Most instructions of a compiled formula.
pub const MAX_CODE: usize = 1024;
/// Deepest nesting of the parser, and most values on the evaluation stack.
pub const MAX_DEPTH: usize = 64;

/// What a formula's variable name refers to once bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    /// Not bound yet: evaluates to NaN.
    Unbound,
    /// Input variable `i` of the engine.
    Input(u32),
    /// Output variable `o` of the engine.
    Output(u32),
}

/// A function callable from a formula.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Func {
    Pi,
    Acos,
    Asin,
    Atan,
    Ceil,
    Cos,
    Cosh,
    Exp,
    Abs,
    Floor,
    Log,
    Log10,
    Round,
    Sin,
    Sinh,
    Sqrt,
    Tan,
    Tanh,
    Log1p,
    Acosh,
    Asinh,
    Atanh,
    Gt,
    Ge,
    Eq,
    Neq,
    Le,
    Lt,
    Min,
    Max,
    Pow,
    Atan2,
    Fmod,
}

/// Every function by its name in formulas (`abs` and `fabs` are the same).
const FUNCTIONS: [(&str, Func); 34] = [
    ("pi", Func::Pi),
    ("acos", Func::Acos),
    ("asin", Func::Asin),
    ("atan", Func::Atan),
    ("ceil", Func::Ceil),
    ("cos", Func::Cos),
    ("cosh", Func::Cosh),
    ("exp", Func::Exp),
    ("abs", Func::Abs),
    ("fabs", Func::Abs),
    ("floor", Func::Floor),
    ("log", Func::Log),
    ("log10", Func::Log10),
    ("round", Func::Round),
    ("sin", Func::Sin),
    ("sinh", Func::Sinh),
    ("sqrt", Func::Sqrt),
    ("tan", Func::Tan),
    ("tanh", Func::Tanh),
    ("log1p", Func::Log1p),
    ("acosh", Func::Acosh),
    ("asinh", Func::Asinh),
    ("atanh", Func::Atanh),
    ("gt", Func::Gt),
    ("ge", Func::Ge),
    ("eq", Func::Eq),
    ("neq", Func::Neq),
    ("le", Func::Le),
    ("lt", Func::Lt),
    ("min", Func::Min),
    ("max", Func::Max),
    ("pow", Func::Pow),
    ("atan2", Func::Atan2),
    ("fmod", Func::Fmod),
];

impl Func {
    /// How many arguments the function takes.
    pub fn arity(self) -> usize {
        use Func::*;
        match self {
            Pi => 0,
            Gt | Ge | Eq | Neq | Le | Lt | Min | Max | Pow | Atan2 | Fmod => 2,
            _ => 1,
        }
    }

    fn unary(self, a: f64) -> f64 {
        use Func::*;
        match self {
            Acos => a.acos(),
            Asin => a.asin(),
            Atan => a.atan(),
            Ceil => a.ceil(),
            Cos => a.cos(),
            Cosh => a.cosh(),
            Exp => a.exp(),
            Abs => a.abs(),
            Floor => a.floor(),
            Log => a.ln(),
            Log10 => a.log10(),
            // Half way rounds to even, as NumPy's `round`.
            Round => a.round_ties_even(),
            Sin => a.sin(),
            Sinh => a.sinh(),
            Sqrt => a.sqrt(),
            Tan => a.tan(),
            Tanh => a.tanh(),
            Log1p => a.ln_1p(),
            Acosh => a.acosh(),
            Asinh => a.asinh(),
            Atanh => a.atanh(),
            _ => f64::NAN,
        }
    }

    fn binary(self, a: f64, b: f64) -> f64 {
        use Func::*;
        match self {
            Gt => truth(a > b),
            Ge => truth(a >= b || same(a, b)),
            Eq => truth(same(a, b)),
            Neq => truth(!same(a, b)),
            Le => truth(a <= b || same(a, b)),
            Lt => truth(a < b),
            // Python's `min`/`max` of two: the second only when it compares strictly better.
            Min => {
                if b < a {
                    b
                } else {
                    a
                }
            }
            Max => {
                if b > a {
                    b
                } else {
                    a
                }
            }
            Pow => a.powf(b),
            Atan2 => a.atan2(b),
            Fmod => a % b,
            _ => f64::NAN,
        }
    }
}

/// Equal, or both NaN.
fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

fn truth(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

/// The remainder with the sign of the divisor (NumPy's and Python's `%`); NaN for `b = 0`.
fn remainder(a: f64, b: f64) -> f64 {
    let r = a % b;
    if b == 0.0 || r.is_nan() {
        return r;
    }
    if r == 0.0 {
        0.0f64.copysign(b)
    } else if (r < 0.0) != (b < 0.0) {
        r + b
    } else {
        r
    }
}

/// An operator of the grammar.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Bin {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Pow,
    And,
    Or,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Un {
    Neg,
    Plus,
    Not,
}

/// One step of the postfix program.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Instr {
    Num(f64),
    X,
    Var { name: u32, at: Slot },
    Un(Un),
    Bin(Bin),
    Call(Func),
}

/// A parsed formula: its text as written, the postfix program and the variable names it reads.
#[derive(Debug, Clone)]
pub struct Formula {
    text: String,
    code: Vec<Instr>,
    names: Vec<String>,
    /// Column of each name's first appearance in the text given to [`Formula::parse`].
    columns: Vec<usize>,
}

/// Two formulas are equal when their texts are (the program follows from the text).
impl PartialEq for Formula {
    fn eq(&self, other: &Self) -> bool {
        self.text == other.text
    }
}

/// A formula that does not parse: the message and its 1-based column (in characters) in the
/// formula's text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FormulaError {
    /// 1-based column in the formula's text.
    pub col: usize,
    /// What is wrong.
    pub message: String,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Tok<'a> {
    Num(f64),
    Name(&'a str),
    Op(&'static str),
    Open,
    Close,
    Comma,
    End,
}

struct Parser<'a> {
    toks: Vec<(Tok<'a>, usize)>,
    pos: usize,
    code: Vec<Instr>,
    names: Vec<String>,
    columns: Vec<usize>,
    depth: usize,
}

fn fail<T>(col: usize, message: impl Into<String>) -> Result<T, FormulaError> {
    Err(FormulaError { col, message: message.into() })
}

fn lex(text: &str) -> Result<Vec<(Tok<'_>, usize)>, FormulaError> {
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let mut toks = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let (byte, c) = chars[i];
        let col = i + 1;
        let next = chars.get(i + 1).map(|&(_, c)| c);
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || (c == '.' && next.is_some_and(|n| n.is_ascii_digit())) {
            let mut j = i;
            while j < chars.len() && (chars[j].1.is_ascii_digit() || chars[j].1 == '.') {
                j += 1;
            }
            if j < chars.len() && matches!(chars[j].1, 'e' | 'E') {
                let mut k = j + 1;
                if k < chars.len() && matches!(chars[k].1, '+' | '-') {
                    k += 1;
                }
                if k < chars.len() && chars[k].1.is_ascii_digit() {
                    while k < chars.len() && chars[k].1.is_ascii_digit() {
                        k += 1;
                    }
                    j = k;
                }
            }
            let end = chars.get(j).map_or(text.len(), |&(b, _)| b);
            let word = &text[byte..end];
            match word.parse::<f64>() {
                Ok(v) => toks.push((Tok::Num(v), col)),
                Err(_) => return fail(col, format!("'{word}' is not a number")),
            }
            i = j;
            continue;
        }
        if c.is_alphabetic() || c == '_' {
            let mut j = i;
            while j < chars.len() && (chars[j].1.is_alphanumeric() || chars[j].1 == '_' || chars[j].1 == '.') {
                j += 1;
            }
            // A name never ends with the dot of `.-` or `.+`.
            if j > i + 1 && chars[j - 1].1 == '.' && j < chars.len() && matches!(chars[j].1, '-' | '+') {
                j -= 1;
            }
            let end = chars.get(j).map_or(text.len(), |&(b, _)| b);
            toks.push((Tok::Name(&text[byte..end]), col));
            i = j;
            continue;
        }
        let (tok, len) = match (c, next) {
            ('*', Some('*')) => (Tok::Op("**"), 2),
            ('.', Some('-')) => (Tok::Op(".-"), 2),
            ('.', Some('+')) => (Tok::Op(".+"), 2),
            ('+', _) => (Tok::Op("+"), 1),
            ('-', _) => (Tok::Op("-"), 1),
            ('*', _) => (Tok::Op("*"), 1),
            ('/', _) => (Tok::Op("/"), 1),
            ('%', _) => (Tok::Op("%"), 1),
            ('^', _) => (Tok::Op("^"), 1),
            ('!', _) => (Tok::Op("!"), 1),
            ('~', _) => (Tok::Op("~"), 1),
            ('(', _) => (Tok::Open, 1),
            (')', _) => (Tok::Close, 1),
            (',', _) => (Tok::Comma, 1),
            _ => return fail(col, format!("unexpected character '{c}'")),
        };
        toks.push((tok, col));
        i += len;
    }
    toks.push((Tok::End, chars.len() + 1));
    Ok(toks)
}

/// Binding powers `(left, right)` of a binary operator token.
fn binary(tok: Tok<'_>) -> Option<(Bin, u8, u8)> {
    Some(match tok {
        Tok::Name("or") => (Bin::Or, 50, 51),
        Tok::Name("and") => (Bin::And, 60, 61),
        Tok::Op("+") => (Bin::Add, 70, 71),
        Tok::Op("-") => (Bin::Sub, 70, 71),
        Tok::Op("*") => (Bin::Mul, 80, 81),
        Tok::Op("/") => (Bin::Div, 80, 81),
        Tok::Op("%") => (Bin::Rem, 80, 81),
        Tok::Op("^" | "**") => (Bin::Pow, 90, 90),
        _ => return None,
    })
}

fn describe(tok: Tok<'_>) -> String {
    match tok {
        Tok::Num(v) => format!("number {v}"),
        Tok::Name(n) => format!("'{n}'"),
        Tok::Op(o) => format!("'{o}'"),
        Tok::Open => "'('".into(),
        Tok::Close => "')'".into(),
        Tok::Comma => "','".into(),
        Tok::End => "the end of the formula".into(),
    }
}

impl<'a> Parser<'a> {
    fn peek(&self) -> (Tok<'a>, usize) {
        self.toks[self.pos.min(self.toks.len() - 1)]
    }

    fn emit(&mut self, col: usize, i: Instr) -> Result<(), FormulaError> {
        if self.code.len() >= MAX_CODE {
            return fail(col, format!("the formula is too long (more than {MAX_CODE} operations)"));
        }
        self.code.push(i);
        Ok(())
    }

    fn enter(&mut self, col: usize) -> Result<(), FormulaError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return fail(col, format!("the formula nests more than {MAX_DEPTH} deep"));
        }
        Ok(())
    }

    /// A formula whose binary operators bind at least `min`.
    fn expr(&mut self, min: u8) -> Result<(), FormulaError> {
        let (_, col) = self.peek();
        self.enter(col)?;
        self.prefix()?;
        loop {
            let (tok, col) = self.peek();
            let Some((op, left, right)) = binary(tok) else { break };
            if left < min {
                break;
            }
            self.pos += 1;
            self.expr(right)?;
            self.emit(col, Instr::Bin(op))?;
        }
        self.depth -= 1;
        Ok(())
    }

    fn prefix(&mut self) -> Result<(), FormulaError> {
        let (tok, col) = self.peek();
        self.pos += 1;
        match tok {
            Tok::Op(o @ ("-" | "+" | ".-" | ".+" | "!" | "~")) => {
                // `!` and `~` bind tighter than a power, `-` and `+` looser.
                let tight = matches!(o, "!" | "~");
                self.expr(if tight { 100 } else { 90 })?;
                let op = match o {
                    "-" | ".-" | "~" => Un::Neg,
                    "!" => Un::Not,
                    _ => Un::Plus,
                };
                self.emit(col, Instr::Un(op))
            }
            Tok::Num(v) => self.emit(col, Instr::Num(v)),
            Tok::Open => {
                self.expr(0)?;
                match self.peek() {
                    (Tok::Close, _) => {
                        self.pos += 1;
                        Ok(())
                    }
                    (Tok::End, _) => fail(col, "this '(' is never closed"),
                    (t, c) => fail(c, format!("expected ')' or an operator, found {}", describe(t))),
                }
            }
            Tok::Name(name) => self.name(name, col),
            Tok::End => fail(col, "expected a number, a variable or '(' at the end of the formula"),
            t => fail(col, format!("expected a number, a variable or '(', found {}", describe(t))),
        }
    }

    fn name(&mut self, name: &'a str, col: usize) -> Result<(), FormulaError> {
        let called = matches!(self.peek().0, Tok::Open);
        if let Some(&(_, f)) = FUNCTIONS.iter().find(|(n, _)| *n == name) {
            if !called {
                if f == Func::Pi {
                    return self.emit(col, Instr::Call(f));
                }
                return fail(col, format!("function '{name}' needs its arguments in parentheses: {name}(…)"));
            }
            self.pos += 1;
            let mut count = 0;
            if matches!(self.peek().0, Tok::Close) {
                self.pos += 1;
            } else {
                loop {
                    self.expr(0)?;
                    count += 1;
                    match self.peek() {
                        (Tok::Comma, _) => self.pos += 1,
                        (Tok::Close, _) => {
                            self.pos += 1;
                            break;
                        }
                        (Tok::End, _) => return fail(col, format!("the '(' of {name}(…) is never closed")),
                        (t, c) => return fail(c, format!("expected ',' or ')', found {}", describe(t))),
                    }
                }
            }
            if count != f.arity() {
                let s = if f.arity() == 1 { "" } else { "s" };
                return fail(col, format!("function '{name}' takes {} argument{s}, found {count}", f.arity()));
            }
            return self.emit(col, Instr::Call(f));
        }
        if called {
            return fail(col, format!("unknown function '{name}'"));
        }
        if matches!(name, "and" | "or") {
            return fail(col, format!("expected a number, a variable or '(', found '{name}'"));
        }
        if let Some(v) = crate::lex::parse_number(name) {
            return self.emit(col, Instr::Num(v));
        }
        if name == "x" {
            return self.emit(col, Instr::X);
        }
        let k = match self.names.iter().position(|n| n == name) {
            Some(k) => k,
            None => {
                self.names.push(name.to_string());
                self.columns.push(col);
                self.names.len() - 1
            }
        };
        self.emit(col, Instr::Var { name: k as u32, at: Slot::Unbound })
    }
}

impl Formula {
    /// Parses `text` (surrounding whitespace is dropped; the rest is kept as written).
    pub fn parse(text: &str) -> Result<Formula, FormulaError> {
        let lead = text.chars().take_while(|c| c.is_whitespace()).count();
        let trimmed = text.trim();
        let shift = |e: FormulaError| FormulaError { col: e.col + lead, ..e };
        if trimmed.is_empty() {
            return fail(1, "the formula is empty");
        }
        if trimmed.chars().count() > MAX_CHARS {
            return fail(1 + lead, format!("the formula is longer than {MAX_CHARS} characters"));
        }
        let toks = lex(trimmed).map_err(shift)?;
        let mut p = Parser { toks, pos: 0, code: Vec::new(), names: Vec::new(), columns: Vec::new(), depth: 0 };
        p.expr(0).map_err(shift)?;
        match p.peek() {
            (Tok::End, _) => {}
            (Tok::Close, c) => return Err(shift(FormulaError { col: c, message: "this ')' has no '('".into() })),
            (t, c) => {
                return Err(shift(FormulaError {
                    col: c,
                    message: format!("expected an operator, found {}", describe(t)),
                }));
            }
        }
        // The most values the program ever holds on the stack.
        let mut height: usize = 0;
        for i in &p.code {
            height = match i {
                Instr::Num(_) | Instr::X | Instr::Var { .. } => height + 1,
                Instr::Un(_) => height,
                Instr::Bin(_) => height.saturating_sub(1),
                Instr::Call(f) => (height + 1).saturating_sub(f.arity()),
            };
            if height > MAX_DEPTH {
                return fail(1 + lead, format!("the formula holds more than {MAX_DEPTH} pending values"));
            }
        }
        let columns = p.columns.iter().map(|c| c + lead).collect();
        Ok(Formula { text: trimmed.to_string(), code: p.code, names: p.names, columns })
    }

    /// The formula as written.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The variable names the formula reads (besides `x`), in order of first appearance.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The column where the formula first reads each of [`Formula::names`], in the text given
    /// to [`Formula::parse`].
    pub fn name_columns(&self) -> &[usize] {
        &self.columns
    }

    /// Binds each variable name to the input or output `lookup` names (NaN where `None`).
    pub fn bind(&mut self, lookup: impl Fn(&str) -> Option<Slot>) {
        for i in &mut self.code {
            if let Instr::Var { name, at } = i {
                *at = lookup(&self.names[*name as usize]).unwrap_or(Slot::Unbound);
            }
        }
    }

    /// True when the formula reads some engine variable (not only `x`).
    pub fn reads_variables(&self) -> bool {
        !self.names.is_empty()
    }

    /// True when the formula reads an output variable (bound ones only).
    pub fn reads_outputs(&self) -> bool {
        self.code.iter().any(|i| matches!(i, Instr::Var { at: Slot::Output(_), .. }))
    }

    /// The value at `x`, bound variables read from `inputs` and `outputs` (NaN when missing).
    pub fn eval(&self, x: f64, inputs: &[f64], outputs: &[f64]) -> f64 {
        let mut stack = [0.0f64; MAX_DEPTH];
        let mut top = 0usize;
        for i in &self.code {
            // The parser checked the stack's height at every step, so no index is out of
            // range; `get` keeps it so without a panic path.
            let v = match *i {
                Instr::Num(v) => v,
                Instr::X => x,
                Instr::Var { at, .. } => match at {
                    Slot::Input(k) => inputs.get(k as usize).copied().unwrap_or(f64::NAN),
                    Slot::Output(k) => outputs.get(k as usize).copied().unwrap_or(f64::NAN),
                    Slot::Unbound => f64::NAN,
                },
                Instr::Un(op) => {
                    top = top.saturating_sub(1);
                    let a = stack.get(top).copied().unwrap_or(f64::NAN);
                    match op {
                        Un::Neg => -a,
                        Un::Plus => a,
                        Un::Not => truth(a == 0.0),
                    }
                }
                Instr::Bin(op) => {
                    top = top.saturating_sub(2);
                    let a = stack.get(top).copied().unwrap_or(f64::NAN);
                    let b = stack.get(top + 1).copied().unwrap_or(f64::NAN);
                    match op {
                        Bin::Add => a + b,
                        Bin::Sub => a - b,
                        Bin::Mul => a * b,
                        Bin::Div => a / b,
                        Bin::Rem => remainder(a, b),
                        Bin::Pow => a.powf(b),
                        Bin::And => truth(a != 0.0 && b != 0.0),
                        Bin::Or => truth(a != 0.0 || b != 0.0),
                    }
                }
                Instr::Call(f) => match f.arity() {
                    0 => PI,
                    1 => {
                        top = top.saturating_sub(1);
                        f.unary(stack.get(top).copied().unwrap_or(f64::NAN))
                    }
                    _ => {
                        top = top.saturating_sub(2);
                        let a = stack.get(top).copied().unwrap_or(f64::NAN);
                        let b = stack.get(top + 1).copied().unwrap_or(f64::NAN);
                        f.binary(a, b)
                    }
                },
            };
            if let Some(slot) = stack.get_mut(top) {
                *slot = v;
            }
            top += 1;
        }
        if top == 0 { f64::NAN } else { stack.get(top - 1).copied().unwrap_or(f64::NAN) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(text: &str, x: f64) -> f64 {
        Formula::parse(text).unwrap_or_else(|e| panic!("{text}: {e:?}")).eval(x, &[], &[])
    }

    fn error(text: &str) -> FormulaError {
        Formula::parse(text).unwrap_err()
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(at("1 + 2 * 3", 0.0), 7.0);
        assert_eq!(at("(1 + 2) * 3", 0.0), 9.0);
        assert_eq!(at("1 - 2 - 3", 0.0), -4.0);
        assert_eq!(at("8 / 4 / 2", 0.0), 1.0);
        assert_eq!(at("2 ^ 3 ^ 2", 0.0), 512.0);
        assert_eq!(at("2 ** 3 ** 2", 0.0), 512.0);
        assert_eq!(at("2 * 3 ^ 2", 0.0), 18.0);
        assert_eq!(at("2*3%4", 0.0), 2.0);
        assert_eq!(at("1 + 2 and 0", 0.0), 0.0);
        assert_eq!(at("0 and 1 or 1", 0.0), 1.0);
        assert_eq!(at("1 or 0 and 0", 0.0), 1.0);
    }

    #[test]
    fn unary_operators() {
        assert_eq!(at("-x^2", 3.0), -9.0);
        assert_eq!(at(".-x^2", 3.0), -9.0);
        assert_eq!(at("~x^2", 3.0), 9.0);
        assert_eq!(at("2^-x", 1.0), 0.5);
        assert_eq!(at("-x*2", 3.0), -6.0);
        assert_eq!(at("x - -x", 3.0), 6.0);
        assert_eq!(at("+x", 3.0), 3.0);
        assert_eq!(at("--x", 3.0), 3.0);
        assert_eq!(at("!x", 3.0), 0.0);
        assert_eq!(at("!x", 0.0), 1.0);
        assert_eq!(at("!x", f64::NAN), 0.0);
        assert_eq!(at("7 % -3", 0.0), -2.0);
        assert_eq!(at("-7 % 3", 0.0), 2.0);
        assert_eq!(at("fmod(-7, 3)", 0.0), -1.0);
    }

    #[test]
    fn functions_and_numbers() {
        assert_eq!(at("sin(x)/x", 2.0), 2f64.sin() / 2.0);
        assert!(at("sin(x)/x", 0.0).is_nan());
        assert_eq!(at("fabs(x) + abs(x)", -1.5), 3.0);
        assert_eq!(at("pow(2, 10)", 0.0), 1024.0);
        assert_eq!(at("atan2(1, 1)", 0.0), std::f64::consts::FRAC_PI_4);
        assert_eq!(at("pi", 0.0), PI);
        assert_eq!(at("pi()", 0.0), PI);
        assert_eq!(at("round(2.5) + round(3.5)", 0.0), 6.0);
        assert_eq!(at("min(x, nan)", 2.0), 2.0);
        assert!(at("min(nan, x)", 2.0).is_nan());
        assert_eq!(at("max(1, 2)", 0.0), 2.0);
        assert_eq!(at("1e-3 * x", 2.0), 0.002);
        assert_eq!(at(".5 + 2.E1", 0.0), 20.5);
        assert_eq!(at("lt(x, 1) + le(x, 1) + eq(x, 1) + neq(x, 1) + ge(x, 1) + gt(x, 1)", 1.0), 3.0);
        assert_eq!(at("eq(nan, nan) + ge(nan, nan)", 0.0), 2.0);
        assert_eq!(at("1/0", 0.0), f64::INFINITY);
        assert!(at("inf - inf", 0.0).is_nan());
        assert_eq!(at("sqrt(log(exp(4)))", 0.0), 2.0);
        assert_eq!(at("floor(-1.5) + ceil(-1.5)", 0.0), -3.0);
    }

    #[test]
    fn variables_are_bound_by_name() {
        let mut f = Formula::parse("fabs(outputFx-trueFx) + inputX * x").unwrap();
        assert_eq!(f.names(), ["outputFx", "trueFx", "inputX"]);
        assert!(f.eval(1.0, &[1.0], &[1.0, 2.0]).is_nan());
        f.bind(|n| match n {
            "inputX" => Some(Slot::Input(0)),
            "outputFx" => Some(Slot::Output(0)),
            "trueFx" => Some(Slot::Output(1)),
            _ => None,
        });
        assert!(f.reads_outputs());
        assert_eq!(f.eval(3.0, &[2.0], &[1.0, 4.0]), 9.0);
        assert_eq!(f.text(), "fabs(outputFx-trueFx) + inputX * x");
    }

    #[test]
    fn bad_formulas_are_located_errors() {
        for (text, col, needle) in [
            ("", 1, "empty"),
            ("   ", 1, "empty"),
            ("sin(x", 1, "never closed"),
            ("(x + 1", 1, "never closed"),
            ("x + 1)", 6, "no '('"),
            ("foo(x)", 1, "unknown function 'foo'"),
            ("sin(x, 1)", 1, "takes 1 argument, found 2"),
            ("pow(x)", 1, "takes 2 arguments, found 1"),
            ("x +", 4, "end of the formula"),
            ("x y", 3, "expected an operator"),
            ("x $ 1", 3, "unexpected character"),
            ("sin x", 1, "parentheses"),
            ("1..2", 1, "not a number"),
            ("* x", 1, "found '*'"),
            (" x +* 2", 5, "found '*'"),
        ] {
            let e = error(text);
            assert_eq!(e.col, col, "{text}: {e:?}");
            assert!(e.message.contains(needle), "{text}: {e:?}");
        }
    }

    #[test]
    fn sizes_are_bounded() {
        let deep = format!("{}x{}", "(".repeat(100), ")".repeat(100));
        assert!(error(&deep).message.contains("nests"));
        let tower = vec!["x"; 100].join("^");
        assert!(error(&tower).message.contains("nests") || error(&tower).message.contains("pending"));
        let long = vec!["x"; 1000].join("+");
        assert!(error(&long).message.contains("too long"));
        let wide = vec!["x"; 500].join("+");
        assert!(Formula::parse(&wide).is_ok());
        let minus = format!("{}x", "-".repeat(1000));
        assert!(Formula::parse(&minus).is_err());
    }
}
