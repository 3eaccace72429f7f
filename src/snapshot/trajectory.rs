//! The text trajectory kept beside a snapshot's pictures, and where two trajectories part.
//!
//! One line per simulation step: step number, time (s), position (m), heading (rad) and the
//! animation interval playing (`-` for the disc), whitespace-separated after a few `#` header
//! lines, one of which gives the region of the world the frames show (x and y from, x and y
//! to, metres):
//!
//! ```text
//! # strider snapshot trajectory 1
//! # scenario u_trap, task 0, seed 1, body animated, time step 0.05 s
//! # view -5.800000 -5.800000 14.000000 5.800000
//! # step time_s x_m y_m heading_rad interval
//! 0 0.000 0.000000 0.000000 0.000000 12
//! ```
//!
//! Two trajectories part at the first step where the positions are more than
//! [`POSITION_TOLERANCE_M`] apart, the headings more than [`HEADING_TOLERANCE_RAD`], or the
//! intervals differ — or where one of them ends.

use std::fmt::{self, Write};

use glam::DVec2;

use crate::diagnostic::SourceError;
use crate::geom::Aabb;
use crate::lex::{Tok, words};

/// First line of a trajectory file.
pub const MAGIC: &str = "# strider snapshot trajectory 1";
/// Positions further apart than this count as parted, metres (1 mm).
pub const POSITION_TOLERANCE_M: f64 = 1e-3;
/// Headings further apart than this count as parted, radians (1 mrad).
pub const HEADING_TOLERANCE_RAD: f64 = 1e-3;

/// The state of the character at one simulation step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Simulation step (0 = the start).
    pub step: usize,
    /// Simulated time, seconds.
    pub time_s: f64,
    /// Position, metres.
    pub position: DVec2,
    /// Heading, radians counter-clockwise from +x.
    pub heading: f64,
    /// The animation interval playing (`None` for the kinematic disc).
    pub interval: Option<usize>,
}

/// A trajectory file: the region the frames show and the samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// The world region every frame of the snapshot shows, metres.
    pub view: Option<Aabb>,
    /// One sample per simulation step, in order.
    pub samples: Vec<Sample>,
}

const VIEW: &str = "# view ";

/// `view` as [`parse`] reads it back from [`to_text`] (coordinates rounded to micrometres), so
/// frames drawn when the goldens are written and when they are checked show the same region.
pub fn as_written(view: Aabb) -> Aabb {
    let round = |x: f64| format!("{x:.6}").parse::<f64>().unwrap_or(x);
    Aabb::new(DVec2::new(round(view.min.x), round(view.min.y)), DVec2::new(round(view.max.x), round(view.max.y)))
}

/// Writes `record` as a trajectory file; `about` goes on the second header line.
pub fn to_text(about: &str, record: &Record) -> String {
    let mut s = String::with_capacity(64 * (record.samples.len() + 4));
    let _ = writeln!(s, "{MAGIC}");
    let _ = writeln!(s, "# {about}");
    if let Some(v) = &record.view {
        let _ = writeln!(s, "{VIEW}{:.6} {:.6} {:.6} {:.6}", v.min.x, v.min.y, v.max.x, v.max.y);
    }
    let _ = writeln!(s, "# step time_s x_m y_m heading_rad interval");
    for p in &record.samples {
        let _ = write!(s, "{} {:.3} {:.6} {:.6} {:.6} ", p.step, p.time_s, p.position.x, p.position.y, p.heading);
        match p.interval {
            Some(i) => {
                let _ = writeln!(s, "{i}");
            }
            None => s.push_str("-\n"),
        }
    }
    s
}

/// Reads a trajectory file written by [`to_text`]; errors name `file`, line and column.
pub fn parse(text: &str, file: &str) -> Result<Record, SourceError> {
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, first)) if first.trim_end() == MAGIC => {}
        _ => return Err(SourceError::new(file, 1, 1, format!("not a snapshot trajectory (expected '{MAGIC}')"))),
    }
    let mut record = Record { view: None, samples: Vec::new() };
    for (n, line) in lines {
        let line_no = n + 1;
        let real = |t: Tok, what: &str| -> Result<f64, SourceError> {
            t.text.parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| {
                SourceError::new(file, line_no, t.col, format!("{what} must be a number, found '{}'", t.text))
            })
        };
        if let Some(rest) = line.strip_prefix(VIEW) {
            let f = words(line);
            if f.len() != 6 {
                return Err(SourceError::new(
                    file,
                    line_no,
                    1,
                    format!("expected '{VIEW}X0 Y0 X1 Y1', found '{rest}'"),
                ));
            }
            let (x0, y0) = (real(f[2], "x")?, real(f[3], "y")?);
            let (x1, y1) = (real(f[4], "x")?, real(f[5], "y")?);
            if !(x0 < x1 && y0 < y1) {
                return Err(SourceError::new(file, line_no, f[2].col, "the view must be a non-empty region"));
            }
            record.view = Some(Aabb::new(DVec2::new(x0, y0), DVec2::new(x1, y1)));
            continue;
        }
        if line.trim().is_empty() || line.trim_start().starts_with('#') {
            continue;
        }
        let fields = words(line);
        if fields.len() != 6 {
            return Err(SourceError::new(
                file,
                line_no,
                1,
                format!("expected step, time, x, y, heading and interval, found {} fields", fields.len()),
            ));
        }
        let count = |t: Tok, what: &str| -> Result<usize, SourceError> {
            t.text
                .parse::<usize>()
                .map_err(|_| SourceError::new(file, line_no, t.col, format!("bad {what} '{}'", t.text)))
        };
        let step = count(fields[0], "step")?;
        if record.samples.last().is_some_and(|p| p.step >= step) {
            return Err(SourceError::new(file, line_no, 1, "steps must increase"));
        }
        record.samples.push(Sample {
            step,
            time_s: real(fields[1], "time")?,
            position: DVec2::new(real(fields[2], "x")?, real(fields[3], "y")?),
            heading: real(fields[4], "heading")?,
            interval: match fields[5].text {
                "-" => None,
                _ => Some(count(fields[5], "interval")?),
            },
        });
    }
    Ok(record)
}

/// What parted first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Parting {
    /// The positions, by more than [`POSITION_TOLERANCE_M`].
    Position,
    /// The headings, by more than [`HEADING_TOLERANCE_RAD`].
    Heading,
    /// The animation intervals playing.
    Interval,
    /// The golden run ended (reached its goal or its time limit) while this one went on.
    GoldenEnds,
    /// This run ended while the golden one went on.
    ActualEnds,
}

/// Where a trajectory first leaves its golden one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Divergence {
    /// What parted first.
    pub what: Parting,
    /// Step of the first difference.
    pub step: usize,
    /// Time of the first difference, seconds.
    pub time_s: f64,
    /// Distance between the two positions then (for an ended run: between its last position
    /// and the other run's position then), metres.
    pub distance_m: f64,
    /// The golden sample at that step (its last sample if it ended).
    pub golden: Sample,
    /// This run's sample at that step (its last sample if it ended).
    pub actual: Sample,
    /// Largest distance between the two runs at the same step, metres.
    pub widest_m: f64,
    /// When the largest distance occurs, seconds.
    pub widest_time_s: f64,
}

fn angle_between(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

/// The first step where `actual` leaves `golden`, or `None` when they agree step by step
/// (within the tolerances) and end together.
pub fn first_divergence(golden: &[Sample], actual: &[Sample]) -> Option<Divergence> {
    let common = golden.len().min(actual.len());
    let (mut widest_m, mut widest_time_s) = (0.0f64, 0.0);
    let mut first: Option<(usize, Parting)> = None;
    for i in 0..common {
        let (g, a) = (&golden[i], &actual[i]);
        let d = g.position.distance(a.position);
        if d > widest_m {
            (widest_m, widest_time_s) = (d, g.time_s);
        }
        if first.is_none() {
            first = if d > POSITION_TOLERANCE_M {
                Some((i, Parting::Position))
            } else if g.interval != a.interval {
                Some((i, Parting::Interval))
            } else if angle_between(g.heading, a.heading) > HEADING_TOLERANCE_RAD {
                Some((i, Parting::Heading))
            } else {
                None
            };
        }
    }
    let (i, what) = match first {
        Some(f) => f,
        None if golden.len() == actual.len() => return None,
        None if golden.len() < actual.len() => (common, Parting::GoldenEnds),
        None => (common, Parting::ActualEnds),
    };
    let g = golden[i.min(golden.len().checked_sub(1)?)];
    let a = actual[i.min(actual.len().checked_sub(1)?)];
    let time_s = match what {
        Parting::GoldenEnds => a.time_s,
        _ => g.time_s,
    };
    Some(Divergence {
        what,
        step: i,
        time_s,
        distance_m: g.position.distance(a.position),
        golden: g,
        actual: a,
        widest_m,
        widest_time_s,
    })
}

impl fmt::Display for Divergence {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (g, a) = (&self.golden, &self.actual);
        let interval = |i: Option<usize>| i.map_or_else(|| "-".to_string(), |i| i.to_string());
        match self.what {
            Parting::GoldenEnds => write!(
                f,
                "the golden run ends at t = {:.2} s (step {}); this run goes on to t = {:.2} s",
                g.time_s, g.step, a.time_s
            )?,
            Parting::ActualEnds => write!(
                f,
                "this run ends at t = {:.2} s (step {}); the golden run goes on to t = {:.2} s",
                a.time_s, a.step, g.time_s
            )?,
            what => {
                write!(
                    f,
                    "the trajectories part at t = {:.2} s (step {}): {:.4} m apart (golden ({:.3}, {:.3}), now ({:.3}, {:.3}))",
                    self.time_s, self.step, self.distance_m, g.position.x, g.position.y, a.position.x, a.position.y
                )?;
                match what {
                    Parting::Interval => write!(
                        f,
                        ", interval {} in the golden run, {} now",
                        interval(g.interval),
                        interval(a.interval)
                    )?,
                    Parting::Heading => {
                        write!(f, ", headings {:.2}° apart", angle_between(g.heading, a.heading).to_degrees())?
                    }
                    _ => {}
                }
            }
        }
        if self.widest_m > POSITION_TOLERANCE_M {
            write!(f, "; at most {:.3} m apart (t = {:.2} s)", self.widest_m, self.widest_time_s)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(n: usize, dy: f64) -> Vec<Sample> {
        (0..n)
            .map(|i| Sample {
                step: i,
                // Quotients of integers: the same doubles the text's decimals read back as.
                time_s: (i * 50) as f64 / 1000.0,
                position: DVec2::new((i * 100) as f64 / 1000.0, if i >= 10 { dy * (i - 9) as f64 } else { 0.0 }),
                heading: 0.0,
                interval: Some(i / 5),
            })
            .collect()
    }

    #[test]
    fn text_round_trip() {
        let view = Some(Aabb::new(DVec2::new(-1.5, -2.0), DVec2::new(3.25, 4.0)));
        let r = Record { view, samples: line(30, 0.0) };
        let text = to_text("test", &r);
        assert_eq!(parse(&text, "t.txt").unwrap(), r);
        let mut disc = Record { view: None, samples: r.samples.clone() };
        disc.samples[3].interval = None;
        let back = parse(&to_text("disc", &disc), "t.txt").unwrap();
        assert_eq!((back.view, back.samples[3].interval), (None, None));
    }

    #[test]
    fn bad_lines_are_located() {
        let err = parse("hello\n", "t.txt").unwrap_err();
        assert_eq!((err.file.as_str(), err.line), ("t.txt", 1));
        let text = format!("{MAGIC}\n0 0.0 1.0 2.0 0.0 -\n1 0.05 x 2.0 0.0 -\n");
        let err = parse(&text, "t.txt").unwrap_err();
        assert_eq!((err.line, err.col), (3, 8), "{err}");
        let err = parse(&format!("{MAGIC}\n0 0.0 1.0\n"), "t.txt").unwrap_err();
        assert_eq!(err.line, 2, "{err}");
        let err = parse(&format!("{MAGIC}\n# view 1 2 0 3\n"), "t.txt").unwrap_err();
        assert_eq!((err.line, err.col), (2, 8), "{err}");
    }

    #[test]
    fn divergence_is_the_first_step_beyond_a_millimetre() {
        let g = line(40, 0.0);
        assert_eq!(first_divergence(&g, &g), None);
        let a = line(40, 0.0004);
        // 0.4 mm per step after step 9: the third such step is 1.2 mm off.
        let d = first_divergence(&g, &a).unwrap();
        assert_eq!((d.what, d.step), (Parting::Position, 12));
        assert!((d.time_s - 0.6).abs() < 1e-12);
        assert!((d.distance_m - 0.0012).abs() < 1e-12);
        assert!((d.widest_m - 0.0004 * 30.0).abs() < 1e-12);
        assert!(d.to_string().contains("t = 0.60 s"), "{d}");
    }

    #[test]
    fn intervals_and_ends_part_too() {
        let g = line(20, 0.0);
        let mut a = g.clone();
        a[7].interval = Some(99);
        let d = first_divergence(&g, &a).unwrap();
        assert_eq!((d.what, d.step), (Parting::Interval, 7));
        let d = first_divergence(&g, &g[..15]).unwrap();
        assert_eq!((d.what, d.step), (Parting::ActualEnds, 15));
        let d = first_divergence(&g[..12], &g).unwrap();
        assert_eq!((d.what, d.step), (Parting::GoldenEnds, 12));
        assert!((d.time_s - 0.6).abs() < 1e-12);
    }
}
