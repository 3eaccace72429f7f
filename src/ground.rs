//! The ground profile (seed 002 §3.2: the ground under the path, cut by the character's
//! sagittal plane) and the `*.profile` file that describes one for the footstep planner alone.
//! It sits below both sides of that cut: the world's terrain makes profiles
//! ([`crate::world::Terrain::profile`]), the footstep planner ([`crate::footstep`]) walks them.
//!
//! A profile is a list of straight pieces of supported ground along X, in increasing X. Two
//! pieces may meet (end to start within [`JOIN_TOLERANCE_M`]): at the same height they join
//! continuously, at different heights they make a vertical step. Wherever no piece covers X
//! there is no foothold (a gap, a hole, the edge of a cliff).
//!
//! The file format: one item per line, numbers in metres, `#` starts a comment, blank lines
//! are ignored, a UTF-8 byte-order mark is accepted.
//!
//! | line | meaning |
//! |------|---------|
//! | `start X` | both feet side by side, soles centred at X |
//! | `goal X` | reached by a foothold at or beyond X (X not before `start`) |
//! | `ground X0 Z0 X1 Z1` | a straight piece of ground from (X0, Z0) to (X1, Z1), X1 > X0 |
//!
//! Exactly one `start` and one `goal`, at least one `ground`; pieces in increasing X without
//! overlap; every number finite and within ±[`MAX_COORDINATE_M`]; files up to
//! [`MAX_PROFILE_BYTES`]. Errors name the file, line and column. Parsing does no IO.

use std::fmt;

use crate::diagnostic::SourceError;
use crate::lex::tokenize;

/// Largest profile text accepted, bytes (16 MiB).
pub const MAX_PROFILE_BYTES: usize = 16 << 20;
/// Largest coordinate magnitude accepted, metres.
pub const MAX_COORDINATE_M: f64 = 1e5;
/// Pieces whose ends are this close (metres) meet; heights this close are equal.
pub const JOIN_TOLERANCE_M: f64 = 1e-6;

/// A straight piece of supported ground, from `(x0, z0)` to `(x1, z1)` with `x1 > x0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundPiece {
    /// Start, metres along the path.
    pub x0_m: f64,
    /// Height at the start, metres.
    pub z0_m: f64,
    /// End, metres along the path.
    pub x1_m: f64,
    /// Height at the end, metres.
    pub z1_m: f64,
}

impl GroundPiece {
    /// The piece's height at `x` (extended linearly outside it), metres.
    pub fn height_at(&self, x: f64) -> f64 {
        self.z0_m + (x - self.x0_m) * self.rise_per_m()
    }

    /// Rise per metre along X.
    pub fn rise_per_m(&self) -> f64 {
        (self.z1_m - self.z0_m) / (self.x1_m - self.x0_m)
    }

    /// Steepness, degrees (0 flat, positive either way).
    pub fn slope_deg(&self) -> f64 {
        self.rise_per_m().atan().to_degrees().abs()
    }
}

/// How a piece ends toward the next one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Join {
    /// The next piece starts where this one ends, at the same height.
    Continuous,
    /// The next piece starts where this one ends, at another height.
    Step,
    /// There is no ground between them.
    Gap,
}

/// What is wrong with a list of ground pieces; `token` is the offending number of the piece
/// (0 = X0, 1 = Z0, 2 = X1, 3 = Z1).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileError {
    /// A piece is malformed or out of order.
    #[error("ground piece {index}: {message}")]
    Piece {
        /// Index of the piece.
        index: usize,
        /// Which of its numbers is at fault.
        token: usize,
        /// What is wrong.
        message: String,
    },
    /// The start or goal is unusable.
    #[error("{0}")]
    Course(String),
}

/// The ground along the path: pieces in increasing X. See the [module docs](self).
#[derive(Debug, Clone, PartialEq)]
pub struct GroundProfile {
    pieces: Vec<GroundPiece>,
    joins: Vec<Join>,
}

/// Why `[x0, x1]` is not one stretch of continuous ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Unsupported {
    /// No ground at `x`.
    NoGround { x_m: f64 },
    /// Ground ends at `from` and resumes at `to` (or nowhere).
    Gap { from_m: f64, to_m: Option<f64> },
    /// A vertical step of `height` (positive up) at `x`.
    Step { x_m: f64, height_m: f64 },
}

/// Checks `piece` (the `index`-th) after `prev`.
fn check_piece(prev: Option<&GroundPiece>, piece: &GroundPiece, index: usize) -> Result<(), ProfileError> {
    let err = |token: usize, message: String| Err(ProfileError::Piece { index, token, message });
    let values = [piece.x0_m, piece.z0_m, piece.x1_m, piece.z1_m];
    for (token, v) in values.into_iter().enumerate() {
        if !v.is_finite() {
            return err(token, format!("{v} is not a finite number"));
        }
        if v.abs() > MAX_COORDINATE_M {
            return err(token, format!("{v} is beyond ±{MAX_COORDINATE_M} m"));
        }
    }
    if !(piece.x1_m > piece.x0_m) {
        return err(2, format!("X1 = {} must be greater than X0 = {}", piece.x1_m, piece.x0_m));
    }
    if let Some(p) = prev
        && piece.x0_m < p.x1_m - JOIN_TOLERANCE_M
    {
        return err(
            0,
            format!(
                "the piece starts at X0 = {} before the previous piece ends (at {}): pieces must be in increasing X \
                 without overlapping",
                piece.x0_m, p.x1_m
            ),
        );
    }
    Ok(())
}

impl GroundProfile {
    /// A profile from pieces in increasing X; see [`ProfileError`] for what is refused.
    pub fn new(pieces: Vec<GroundPiece>) -> Result<GroundProfile, ProfileError> {
        for (i, p) in pieces.iter().enumerate() {
            check_piece(i.checked_sub(1).map(|j| &pieces[j]), p, i)?;
        }
        let joins = pieces
            .windows(2)
            .map(|w| {
                if w[1].x0_m > w[0].x1_m + JOIN_TOLERANCE_M {
                    Join::Gap
                } else if (w[1].z0_m - w[0].z1_m).abs() <= JOIN_TOLERANCE_M {
                    Join::Continuous
                } else {
                    Join::Step
                }
            })
            .collect();
        Ok(GroundProfile { pieces, joins })
    }

    /// A profile of one flat piece from `x0` to `x1` at height 0.
    pub fn flat(x0_m: f64, x1_m: f64) -> Result<GroundProfile, ProfileError> {
        GroundProfile::new(vec![GroundPiece { x0_m, z0_m: 0.0, x1_m, z1_m: 0.0 }])
    }

    /// The pieces, in increasing X.
    pub fn pieces(&self) -> &[GroundPiece] {
        &self.pieces
    }

    /// Index of the first piece ending at or after `x`.
    fn first_ending_after(&self, x: f64) -> usize {
        self.pieces.partition_point(|p| p.x1_m < x)
    }

    /// The ground height at `x` (the top of a vertical step standing at `x`), or `None` where
    /// there is no ground.
    pub fn height_at(&self, x: f64) -> Option<f64> {
        let mut best: Option<f64> = None;
        for p in self.pieces[self.first_ending_after(x)..].iter().take_while(|p| p.x0_m <= x) {
            let z = p.height_at(x);
            best = Some(best.map_or(z, |b: f64| b.max(z)));
        }
        best
    }

    /// The first piece from `x0` on when `[x0, x1]` is one stretch of continuous ground (no
    /// gap, no vertical step inside), with the index of the last piece it covers.
    pub(crate) fn continuous(&self, x0: f64, x1: f64) -> Result<(usize, usize), Unsupported> {
        // The piece holding x0: the last one starting at or before it, which must reach it.
        let i = self.pieces.partition_point(|p| p.x0_m <= x0);
        let Some(first) = i.checked_sub(1) else {
            return Err(Unsupported::NoGround { x_m: x0 });
        };
        let mut k = first;
        if self.pieces[k].x1_m < x0 {
            return Err(Unsupported::NoGround { x_m: x0 });
        }
        while self.pieces[k].x1_m < x1 {
            let end = self.pieces[k].x1_m;
            match self.joins.get(k) {
                None => return Err(Unsupported::Gap { from_m: end, to_m: None }),
                Some(Join::Gap) => return Err(Unsupported::Gap { from_m: end, to_m: Some(self.pieces[k + 1].x0_m) }),
                Some(Join::Step) => {
                    let height_m = self.pieces[k + 1].z0_m - self.pieces[k].z1_m;
                    return Err(Unsupported::Step { x_m: end, height_m });
                }
                Some(Join::Continuous) => k += 1,
            }
        }
        Ok((first, k))
    }

    /// The largest height of the ground above the line through `(x_ref, z_ref)` with `slope`
    /// (rise per metre), over `[x0, x1]`; `-∞` where there is no ground. Exact: pieces are
    /// straight, so the largest difference over each lies at an end of its part in the span.
    pub fn max_above_line(&self, x0: f64, x1: f64, x_ref: f64, z_ref: f64, slope: f64) -> f64 {
        let mut best = f64::NEG_INFINITY;
        for p in self.pieces[self.first_ending_after(x0)..].iter().take_while(|p| p.x0_m <= x1) {
            let (a, b) = (p.x0_m.max(x0), p.x1_m.min(x1));
            for x in [a, b] {
                best = best.max(p.height_at(x) - (z_ref + slope * (x - x_ref)));
            }
        }
        best
    }

    /// The next feature at or after `x` that can stop a walker: the start of a gap, a vertical
    /// step or a piece steeper than `max_slope_deg`, or the end of the ground.
    pub fn next_hazard(&self, x: f64, max_slope_deg: f64) -> Option<Hazard> {
        let start = self.first_ending_after(x);
        for (k, p) in self.pieces.iter().enumerate().skip(start) {
            if p.slope_deg() > max_slope_deg {
                return Some(Hazard::Steep { from_m: p.x0_m.max(x), slope_deg: p.slope_deg() });
            }
            match self.joins.get(k) {
                None => return Some(Hazard::End { at_m: p.x1_m }),
                Some(Join::Gap) => {
                    return Some(Hazard::Gap { from_m: p.x1_m, to_m: self.pieces[k + 1].x0_m });
                }
                Some(Join::Step) => {
                    return Some(Hazard::Step { at_m: p.x1_m, height_m: self.pieces[k + 1].z0_m - p.z1_m });
                }
                Some(Join::Continuous) => {}
            }
        }
        None
    }
}

/// A feature of the ground that can stop a walker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Hazard {
    /// No ground from `from` to `to`.
    Gap {
        /// Where the ground ends, metres.
        from_m: f64,
        /// Where it resumes, metres.
        to_m: f64,
    },
    /// A vertical step (positive up).
    Step {
        /// Where, metres.
        at_m: f64,
        /// Height, metres (negative: a drop).
        height_m: f64,
    },
    /// Ground steeper than the limit.
    Steep {
        /// Where it starts, metres.
        from_m: f64,
        /// Its slope, degrees.
        slope_deg: f64,
    },
    /// The last piece ends.
    End {
        /// Where, metres.
        at_m: f64,
    },
}

impl fmt::Display for Hazard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Hazard::Gap { from_m, to_m } => {
                write!(f, "a gap from x = {from_m:.2} m to {to_m:.2} m ({:.2} m wide)", to_m - from_m)
            }
            Hazard::Step { at_m, height_m } if height_m >= 0.0 => {
                write!(f, "a step up of {height_m:.2} m at x = {at_m:.2} m")
            }
            Hazard::Step { at_m, height_m } => write!(f, "a drop of {:.2} m at x = {at_m:.2} m", -height_m),
            Hazard::Steep { from_m, slope_deg } => {
                write!(f, "ground sloping {slope_deg:.1}° from x = {from_m:.2} m")
            }
            Hazard::End { at_m } => write!(f, "the end of the ground at x = {at_m:.2} m"),
        }
    }
}

/// A profile to walk: the ground, where both feet start and where the goal is.
#[derive(Debug, Clone, PartialEq)]
pub struct Course {
    /// The ground.
    pub ground: GroundProfile,
    /// Where both soles are centred at the start, metres.
    pub start_m: f64,
    /// Reached by a foothold at or beyond it, metres.
    pub goal_m: f64,
    /// Source line of `start` (0 when not read from a file).
    pub start_line: usize,
    /// Source line of `goal` (0 when not read from a file).
    pub goal_line: usize,
}

impl Course {
    /// A course over `ground` from `start_m` to `goal_m` (not before the start; both finite).
    pub fn new(ground: GroundProfile, start_m: f64, goal_m: f64) -> Result<Course, ProfileError> {
        if !start_m.is_finite() || !goal_m.is_finite() {
            return Err(ProfileError::Course(format!("start {start_m} and goal {goal_m} must be finite")));
        }
        if goal_m < start_m {
            return Err(ProfileError::Course(format!(
                "the goal (x = {goal_m}) is before the start (x = {start_m}): walking is toward +X"
            )));
        }
        Ok(Course { ground, start_m, goal_m, start_line: 0, goal_line: 0 })
    }
}

/// Reads a `*.profile` text; `file` names it in errors. See the [module docs](self).
pub fn parse(text: &str, file: &str) -> Result<Course, SourceError> {
    if text.len() > MAX_PROFILE_BYTES {
        return Err(SourceError::new(
            file,
            0,
            0,
            format!("the profile is {} bytes, more than the {} MiB accepted", text.len(), MAX_PROFILE_BYTES >> 20),
        ));
    }
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let err = |line: usize, col: usize, message: String| SourceError::new(file, line, col, message);
    let mut start: Option<(f64, usize)> = None;
    let mut goal: Option<(f64, usize, usize)> = None;
    let mut pieces: Vec<GroundPiece> = Vec::new();
    let mut piece_lines: Vec<usize> = Vec::new();
    for (i, line_text) in text.lines().enumerate() {
        let line = i + 1;
        let (toks, end_col) = tokenize(line_text);
        let Some((&kw, args)) = toks.split_first() else { continue };
        let numbers = |count: usize, usage: &str| -> Result<Vec<f64>, SourceError> {
            if args.len() < count {
                return Err(err(
                    line,
                    end_col,
                    format!("`{}` needs {count} number(s), found {} (usage: {usage})", kw.text, args.len()),
                ));
            }
            if let Some(extra) = args.get(count) {
                return Err(err(line, extra.col, format!("unexpected `{}` (usage: {usage})", extra.text)));
            }
            args.iter().map(|t| t.number(file, line)).collect()
        };
        match kw.text {
            "start" | "goal" => {
                let v = numbers(1, &format!("{} X", kw.text))?[0];
                let previous = if kw.text == "start" { start.map(|s| s.1) } else { goal.map(|g| g.1) };
                if let Some(first) = previous {
                    return Err(err(line, kw.col, format!("a second `{}` (the first is on line {first})", kw.text)));
                }
                if v.abs() > MAX_COORDINATE_M {
                    return Err(err(line, args[0].col, format!("{v} is beyond ±{MAX_COORDINATE_M} m")));
                }
                if kw.text == "start" {
                    start = Some((v, line));
                } else {
                    goal = Some((v, line, args[0].col));
                }
            }
            "ground" => {
                let v = numbers(4, "ground X0 Z0 X1 Z1")?;
                let piece = GroundPiece { x0_m: v[0], z0_m: v[1], x1_m: v[2], z1_m: v[3] };
                if let Err(ProfileError::Piece { token, message, .. }) =
                    check_piece(pieces.last(), &piece, pieces.len())
                {
                    let message = match piece_lines.last() {
                        Some(prev) if token == 0 => format!("{message} (previous piece on line {prev})"),
                        _ => message,
                    };
                    return Err(err(line, args[token].col, message));
                }
                pieces.push(piece);
                piece_lines.push(line);
            }
            other => {
                return Err(err(line, kw.col, format!("unknown item `{other}`: expected `start`, `goal` or `ground`")));
            }
        }
    }
    let Some((start_m, start_line)) = start else {
        return Err(err(0, 0, "no `start X` line: where do the feet stand?".into()));
    };
    let Some((goal_m, goal_line, goal_col)) = goal else {
        return Err(err(0, 0, "no `goal X` line".into()));
    };
    if pieces.is_empty() {
        return Err(err(0, 0, "no `ground X0 Z0 X1 Z1` line: there is nowhere to stand".into()));
    }
    if goal_m < start_m {
        return Err(err(
            goal_line,
            goal_col,
            format!(
                "the goal (x = {goal_m}) is before the start (x = {start_m}, line {start_line}): walking is toward +X"
            ),
        ));
    }
    let ground = GroundProfile::new(pieces).map_err(|e| err(0, 0, e.to_string()))?;
    Ok(Course { ground, start_m, goal_m, start_line, goal_line })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse(text, "t.profile").expect_err(text).to_string()
    }

    #[test]
    fn reads_items_comments_bom_and_crlf() {
        let c = parse(
            "\u{feff}# a step\r\nstart 0.5   # feet here\r\n\r\ngoal 3\nground 0 0 2 0\nground 2 0.2 4 0.2\n\
             ground 4.5 0.2 6 0.5\n",
            "t.profile",
        )
        .unwrap();
        assert_eq!((c.start_m, c.goal_m, c.start_line, c.goal_line), (0.5, 3.0, 2, 4));
        assert_eq!(c.ground.pieces().len(), 3);
        assert_eq!(c.ground.height_at(2.0), Some(0.2), "the top of a vertical step");
        assert_eq!(c.ground.height_at(1.0), Some(0.0));
        assert_eq!(c.ground.height_at(4.2), None);
        assert!((c.ground.height_at(5.25).unwrap() - 0.35).abs() < 1e-12);
        assert_eq!(c.ground.continuous(0.5, 1.5), Ok((0, 0)));
        assert_eq!(c.ground.continuous(1.9, 2.1), Err(Unsupported::Step { x_m: 2.0, height_m: 0.2 }));
        assert_eq!(c.ground.continuous(3.9, 4.6), Err(Unsupported::Gap { from_m: 4.0, to_m: Some(4.5) }));
        assert_eq!(c.ground.continuous(5.9, 6.1), Err(Unsupported::Gap { from_m: 6.0, to_m: None }));
        assert_eq!(c.ground.continuous(-0.1, 0.1), Err(Unsupported::NoGround { x_m: -0.1 }));
        // A sole right against the riser, on either side, is supported.
        assert_eq!(c.ground.continuous(1.8, 2.0), Ok((0, 0)));
        assert_eq!(c.ground.continuous(2.0, 2.2), Ok((1, 1)));
        assert_eq!(c.ground.max_above_line(1.0, 3.0, 0.0, 0.0, 0.0), 0.2);
        assert_eq!(c.ground.max_above_line(4.1, 4.4, 0.0, 0.0, 0.0), f64::NEG_INFINITY);
        assert_eq!(c.ground.next_hazard(0.0, 30.0), Some(Hazard::Step { at_m: 2.0, height_m: 0.2 }));
        assert_eq!(c.ground.next_hazard(2.5, 30.0), Some(Hazard::Gap { from_m: 4.0, to_m: 4.5 }));
        assert_eq!(c.ground.next_hazard(4.6, 30.0), Some(Hazard::End { at_m: 6.0 }));
        assert!(matches!(c.ground.next_hazard(4.6, 5.0), Some(Hazard::Steep { .. })));
    }

    #[test]
    fn continuous_pieces_carry_a_sole_across_their_join() {
        let g = GroundProfile::new(vec![
            GroundPiece { x0_m: 0.0, z0_m: 0.0, x1_m: 1.0, z1_m: 0.1 },
            GroundPiece { x0_m: 1.0, z0_m: 0.1, x1_m: 2.0, z1_m: 0.1 },
        ])
        .unwrap();
        assert_eq!(g.continuous(0.9, 1.1), Ok((0, 1)));
    }

    #[test]
    fn bad_profiles_are_located() {
        let base = "start 0\ngoal 1\n";
        for (text, needle) in [
            ("start 0\ngoal 1\nground 0 0 x 0\n", "t.profile:3:12: expected a number, found `x`"),
            ("start 0\ngoal 1\nground 0 0 1\n", "t.profile:3:13: `ground` needs 4 number(s), found 3"),
            ("start 0\ngoal 1\nground 0 0 1 0 7\n", "t.profile:3:16: unexpected `7`"),
            ("start 0\ngoal 1\nground 0 0 inf 0\n", "t.profile:3:12: `inf` is not a finite number"),
            ("start 0\ngoal 1\nground 0 NaN 1 0\n", "t.profile:3:10: `NaN` is not a finite number"),
            ("start 0\ngoal 1\nground 2 0 1 0\n", "t.profile:3:12: X1 = 1 must be greater than X0 = 2"),
            ("start 0\ngoal 1\nground 1 0 1 0\n", "t.profile:3:12: X1 = 1 must be greater than X0 = 1"),
            ("start 0\ngoal 1\nground 0 0 2 0\nground 1 0 3 0\n", "t.profile:4:8: the piece starts at X0 = 1 before"),
            ("start 0\ngoal 1\nground 0 0 2 0\nground 1 0 3 0\n", "(previous piece on line 3)"),
            ("start 0\ngoal 1\nground 0 0 2e6 0\n", "t.profile:3:12: 2000000 is beyond"),
            ("start 0\ngoal 1\nstep 0 0 1 0\n", "t.profile:3:1: unknown item `step`"),
            ("start 0\ngoal 1\n  start 2\n", "t.profile:3:3: a second `start` (the first is on line 1)"),
            ("start 0\ngoal -1\nground 0 0 2 0\n", "t.profile:2:6: the goal (x = -1) is before the start"),
            ("goal 1\nground 0 0 2 0\n", "t.profile: no `start X` line"),
            ("start 0\nground 0 0 2 0\n", "t.profile: no `goal X` line"),
            (base, "no `ground"),
            ("start\n", "t.profile:1:6: `start` needs 1 number(s), found 0"),
        ] {
            let e = err(text);
            assert!(e.contains(needle), "{text:?}: '{e}' should contain '{needle}'");
        }
        let huge = "#".repeat(MAX_PROFILE_BYTES + 1);
        assert!(err(&huge).contains("more than the 16 MiB"));
    }

    #[test]
    fn pieces_built_in_code_are_checked() {
        let piece = |x0_m, x1_m| GroundPiece { x0_m, z0_m: 0.0, x1_m, z1_m: 0.0 };
        assert!(GroundProfile::new(vec![piece(0.0, 1.0), piece(0.5, 2.0)]).is_err());
        assert!(GroundProfile::new(vec![piece(1.0, 0.0)]).is_err());
        assert!(GroundProfile::new(vec![piece(0.0, f64::NAN)]).is_err());
        assert!(GroundProfile::new(vec![piece(0.0, 1.0), piece(1.0 - 1e-7, 2.0)]).is_ok(), "within tolerance");
        let g = GroundProfile::flat(0.0, 1.0).unwrap();
        assert!(Course::new(g.clone(), 0.5, 0.2).is_err());
        assert!(Course::new(g, f64::NAN, 0.2).is_err());
    }
}
