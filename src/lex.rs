//! The words and numbers of strider's text formats: the plain text world (`maps::text`), the
//! `*.profile` ground profiles ([`crate::ground`]), the snapshot trajectory file, the interval
//! lists of `strider db build`, and the numbers of FuzzyLite Language and of rules.
//!
//! A line is split into whitespace-separated [`Tok`]s, each with its 1-based column in
//! characters, so every error can name the line and column of the word at fault; [`tokenize`]
//! also ends the line at a `#` comment. Numbers are read with [`Tok::number`] (finite only)
//! or, in FLL's spelling of the infinities and NaN, with [`parse_number`], written back
//! exactly by [`number`], and shown in messages by [`shown`]. No IO.

use crate::diagnostic::SourceError;

/// One whitespace-separated word and its 1-based column (in characters).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tok<'a> {
    /// The word.
    pub text: &'a str,
    /// Its 1-based column, in characters.
    pub col: usize,
}

impl Tok<'_> {
    /// The word as a finite number; the error names `file`, `line` and the word's column.
    pub fn number(self, file: &str, line: usize) -> Result<f64, SourceError> {
        match self.text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(SourceError::new(file, line, self.col, format!("`{}` is not a finite number", self.text))),
            Err(_) => Err(SourceError::new(file, line, self.col, format!("expected a number, found `{}`", self.text))),
        }
    }
}

/// Splits a line into tokens, stopping at `#`. Also returns the column just past the last
/// token, for "missing number" errors.
pub fn tokenize(line: &str) -> (Vec<Tok<'_>>, usize) {
    let mut toks = Vec::new();
    let mut start: Option<(usize, usize)> = None;
    let mut col = 0;
    let mut end_col = 1;
    for (byte, c) in line.char_indices() {
        col += 1;
        if c == '#' || c.is_whitespace() {
            if let Some((b, cl)) = start.take() {
                toks.push(Tok { text: &line[b..byte], col: cl });
                end_col = col;
            }
            if c == '#' {
                return (toks, end_col);
            }
        } else if start.is_none() {
            start = Some((byte, col));
        }
    }
    if let Some((b, cl)) = start {
        toks.push(Tok { text: &line[b..], col: cl });
        end_col = col + 1;
    }
    (toks, end_col)
}

/// The whitespace-separated words of a line, `#` included (for formats without comments).
pub fn words(line: &str) -> Vec<Tok<'_>> {
    let mut col = 0;
    let mut start: Option<(usize, usize)> = None;
    let mut out = Vec::new();
    for (byte, c) in line.char_indices() {
        col += 1;
        match (c.is_whitespace(), start) {
            (false, None) => start = Some((byte, col)),
            (true, Some((b, cl))) => {
                out.push(Tok { text: &line[b..byte], col: cl });
                start = None;
            }
            _ => {}
        }
    }
    if let Some((b, cl)) = start {
        out.push(Tok { text: &line[b..], col: cl });
    }
    out
}

/// A number as FLL writes it: `nan`, `inf`, `-inf`, or the shortest decimal that reads back
/// as the same value.
pub fn number(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x == f64::INFINITY {
        "inf".into()
    } else if x == f64::NEG_INFINITY {
        "-inf".into()
    } else {
        format!("{x}")
    }
}

/// A number as a message shows it: the shortest decimal that reads back as the same value,
/// in exponent form when it would be long (`1e300`, `2.5e-9`), `NaN` and `inf` as Rust writes
/// them.
pub fn shown(x: f64) -> String {
    if x.is_finite() && x != 0.0 && !(1e-5..1e16).contains(&x.abs()) { format!("{x:e}") } else { format!("{x}") }
}

/// Reads an FLL number (`nan`, `inf`, `+inf`, `-inf` or a decimal).
pub fn parse_number(s: &str) -> Option<f64> {
    match s.to_ascii_lowercase().as_str() {
        "nan" | "+nan" | "-nan" => Some(f64::NAN),
        "inf" | "+inf" | "infinity" | "+infinity" => Some(f64::INFINITY),
        "-inf" | "-infinity" => Some(f64::NEG_INFINITY),
        other => other.parse::<f64>().ok().filter(|v| v.is_finite()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_and_columns() {
        let (t, end) = tokenize("  box\t1 2  # c");
        let cols: Vec<(usize, &str)> = t.iter().map(|t| (t.col, t.text)).collect();
        assert_eq!(cols, vec![(3, "box"), (7, "1"), (9, "2")]);
        assert_eq!(end, 10);
        let (t, end) = tokenize("start 1 2");
        assert_eq!(t.len(), 3);
        assert_eq!(end, 10);
        let w: Vec<(usize, &str)> = words(" 1\t22  é3 #4\r").iter().map(|t| (t.col, t.text)).collect();
        assert_eq!(w, vec![(2, "1"), (4, "22"), (8, "é3"), (11, "#4")]);
    }

    #[test]
    fn numbers() {
        for x in [0.0, -1.5, 1e-300, f64::INFINITY, f64::NEG_INFINITY, 0.1 + 0.2] {
            assert_eq!(parse_number(&number(x)), Some(x));
        }
        assert!(parse_number(&number(f64::NAN)).unwrap().is_nan());
        assert_eq!(parse_number("abc"), None);
        let e = Tok { text: "inf", col: 4 }.number("f", 2).unwrap_err();
        assert_eq!((e.line, e.col, e.message.as_str()), (2, 4, "`inf` is not a finite number"));
        assert_eq!(Tok { text: "-2.5", col: 1 }.number("f", 1).unwrap(), -2.5);
        let texts: Vec<String> = [1e300, -2.5e-9, 0.25, 1e15, 0.0, f64::NAN, f64::NEG_INFINITY].map(shown).into();
        assert_eq!(texts, ["1e300", "-2.5e-9", "0.25", "1000000000000000", "0", "NaN", "-inf"]);
    }
}
