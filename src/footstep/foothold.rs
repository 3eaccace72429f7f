//! Where a foot may stand (seed 002 §4.2: a configuration collides when a foot is over a gap,
//! on an edge, or the step is too high), and the reasons a step fails.
//!
//! A foothold at `x` is valid when the whole sole, the span `[x − L/2, x + L/2]` (`L` the foot
//! length), lies on one stretch of ground with no gap and no vertical step inside it, every
//! piece under it is no steeper than the limit, and the ground nowhere rises above the sole
//! (the straight line from the ground under its heel end to the ground under its toe end): the
//! sole may bridge a hollow, never straddle a crest. Consecutive footholds differ in height by at most the
//! step-up and step-down limits.

use std::fmt;

use glam::DVec2;

use super::FootstepParams;
use crate::ground::{GroundProfile, Unsupported};

/// How far the ground may rise above the sole's line, metres: a numerical tolerance only — a
/// rigid sole does not stand across a crest.
pub const SOLE_CONFORMITY_M: f64 = 1e-6;

/// Tolerance on the height limits, metres (a step exactly at the limit is allowed).
const LIMIT_TOLERANCE_M: f64 = 1e-9;

/// Which foot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Foot {
    /// The left foot (the first to swing).
    Left,
    /// The right foot.
    Right,
}

impl Foot {
    /// The other foot.
    pub fn other(self) -> Foot {
        match self {
            Foot::Left => Foot::Right,
            Foot::Right => Foot::Left,
        }
    }

    /// 0 for the left foot, 1 for the right (the order of the skeleton's sides).
    pub fn index(self) -> usize {
        match self {
            Foot::Left => 0,
            Foot::Right => 1,
        }
    }

    /// `"left"` or `"right"`.
    pub fn name(self) -> &'static str {
        match self {
            Foot::Left => "left",
            Foot::Right => "right",
        }
    }
}

/// A foot standing on the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Foothold {
    /// Which foot.
    pub foot: Foot,
    /// The sole: its centre (the foothold's `x`, and the ground height there) and pitch.
    pub sole: Sole,
}

/// A sole in the sagittal plane: its centre and its pitch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sole {
    /// Centre of the sole (the foothold), metres along the path.
    pub x_m: f64,
    /// Height of the sole's centre, metres.
    pub z_m: f64,
    /// Pitch of the sole, radians, positive toes up (on ground rising toward +X).
    pub pitch_rad: f64,
}

impl Sole {
    /// The heel end of a sole `foot_length_m` long.
    pub fn heel(&self, foot_length_m: f64) -> DVec2 {
        self.centre() - self.half(foot_length_m)
    }

    /// The toe end of a sole `foot_length_m` long.
    pub fn toe(&self, foot_length_m: f64) -> DVec2 {
        self.centre() + self.half(foot_length_m)
    }

    /// The centre as a point.
    pub fn centre(&self) -> DVec2 {
        DVec2::new(self.x_m, self.z_m)
    }

    fn half(&self, foot_length_m: f64) -> DVec2 {
        0.5 * foot_length_m * DVec2::new(self.pitch_rad.cos(), self.pitch_rad.sin())
    }
}

/// Why a foothold or a step is not valid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepFailure {
    /// No ground under the sole at `x`.
    NoGround {
        /// Where, metres.
        x_m: f64,
    },
    /// The sole would bridge a gap.
    Gap {
        /// Where the ground ends, metres.
        from_m: f64,
        /// Where it resumes (`None`: nowhere).
        to_m: Option<f64>,
    },
    /// A vertical step under the sole.
    VerticalStep {
        /// Where, metres.
        x_m: f64,
        /// Its height, metres (negative: down).
        height_m: f64,
    },
    /// Ground steeper than the limit under the sole.
    TooSteep {
        /// The sole's centre, metres.
        x_m: f64,
        /// The steepest piece under it, degrees.
        slope_deg: f64,
    },
    /// The ground rises above the sole's line (a bump under it).
    Uneven {
        /// The sole's centre, metres.
        x_m: f64,
        /// How far above the line, metres.
        height_m: f64,
    },
    /// The next foothold is higher than the step-up limit.
    StepTooHigh {
        /// The rise, metres.
        rise_m: f64,
    },
    /// The next foothold is lower than the step-down limit.
    StepTooLow {
        /// The drop, metres.
        drop_m: f64,
    },
    /// The swing curve cannot clear the ground without raising its control points beyond
    /// the limit.
    SwingBlocked {
        /// Raise above the higher foothold the swing would need, metres.
        needed_m: f64,
    },
    /// A leg cannot reach its foot, or would have to bend its knee beyond the limit.
    OutOfReach {
        /// Phase of the step (0 lift-off, 1 touch-down).
        phase: f64,
        /// Hip-to-ankle distance asked for, metres.
        distance_m: f64,
    },
}

impl fmt::Display for StepFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            StepFailure::NoGround { x_m } => write!(f, "no ground under the sole at x = {x_m:.3} m"),
            StepFailure::Gap { from_m, to_m: Some(to) } => {
                write!(f, "the sole would bridge a gap from x = {from_m:.3} m to {to:.3} m")
            }
            StepFailure::Gap { from_m, to_m: None } => {
                write!(f, "the sole would overhang the end of the ground at x = {from_m:.3} m")
            }
            StepFailure::VerticalStep { x_m, height_m } => {
                write!(f, "a vertical step of {height_m:+.3} m under the sole at x = {x_m:.3} m")
            }
            StepFailure::TooSteep { x_m, slope_deg } => {
                write!(f, "the ground under the sole at x = {x_m:.3} m slopes {slope_deg:.1}°, more than the limit")
            }
            StepFailure::Uneven { x_m, height_m } => {
                write!(f, "the ground rises {height_m:.3} m above the sole at x = {x_m:.3} m")
            }
            StepFailure::StepTooHigh { rise_m } => write!(f, "a step up of {rise_m:.3} m, more than the limit"),
            StepFailure::StepTooLow { drop_m } => write!(f, "a step down of {drop_m:.3} m, more than the limit"),
            StepFailure::SwingBlocked { needed_m } => write!(
                f,
                "the swinging foot would have to rise {needed_m:.3} m above the higher foothold to clear the ground"
            ),
            StepFailure::OutOfReach { phase, distance_m } => write!(
                f,
                "a leg cannot span {distance_m:.3} m from hip to ankle (at {:.0} % of the step)",
                phase * 100.0
            ),
        }
    }
}

/// The sole of a foot centred at `x`, or why it cannot stand there.
pub fn sole_at(ground: &GroundProfile, params: &FootstepParams, x: f64) -> Result<Sole, StepFailure> {
    let length = params.leg.foot_length_m();
    let (x0, x1) = (x - 0.5 * length, x + 0.5 * length);
    let (first, last) = ground.continuous(x0, x1).map_err(|u| match u {
        Unsupported::NoGround { x_m } => StepFailure::NoGround { x_m },
        Unsupported::Gap { from_m, to_m } => StepFailure::Gap { from_m, to_m },
        Unsupported::Step { x_m, height_m } => StepFailure::VerticalStep { x_m, height_m },
    })?;
    let pieces = &ground.pieces()[first..=last];
    let slope_deg = pieces.iter().map(|p| p.slope_deg()).fold(0.0, f64::max);
    if slope_deg > params.max_slope_deg {
        return Err(StepFailure::TooSteep { x_m: x, slope_deg });
    }
    let (z0, z1) = (pieces[0].height_at(x0), pieces[pieces.len() - 1].height_at(x1));
    let slope = (z1 - z0) / length;
    let bump = ground.max_above_line(x0, x1, x0, z0, slope);
    if bump > SOLE_CONFORMITY_M {
        return Err(StepFailure::Uneven { x_m: x, height_m: bump });
    }
    Ok(Sole { x_m: x, z_m: 0.5 * (z0 + z1), pitch_rad: slope.atan() })
}

/// Whether a step from the foothold `from` to `to` keeps within the height limits.
pub fn height_change(params: &FootstepParams, from: &Sole, to: &Sole) -> Result<(), StepFailure> {
    let rise = to.z_m - from.z_m;
    if rise > params.max_step_up_m + LIMIT_TOLERANCE_M {
        Err(StepFailure::StepTooHigh { rise_m: rise })
    } else if -rise > params.max_step_down_m + LIMIT_TOLERANCE_M {
        Err(StepFailure::StepTooLow { drop_m: -rise })
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ground::GroundPiece;

    fn ground(pieces: &[(f64, f64, f64, f64)]) -> GroundProfile {
        GroundProfile::new(
            pieces.iter().map(|&(x0_m, z0_m, x1_m, z1_m)| GroundPiece { x0_m, z0_m, x1_m, z1_m }).collect(),
        )
        .unwrap()
    }

    #[test]
    fn the_whole_sole_must_stand_on_even_ground() {
        let p = FootstepParams::default();
        // Flat to 2, a 0.2 step up, a gap, a 20° slope, a 40° slope, a crest.
        let g = ground(&[
            (0.0, 0.0, 2.0, 0.0),
            (2.0, 0.2, 3.0, 0.2),
            (3.5, 0.2, 5.0, 0.2 + 1.5 * 20f64.to_radians().tan()),
            (6.0, 0.0, 7.0, 40f64.to_radians().tan()),
            (8.0, 0.0, 9.0, 0.5),
            (9.0, 0.5, 10.0, 0.0),
        ]);
        let s = sole_at(&g, &p, 1.0).unwrap();
        assert_eq!((s.x_m, s.z_m, s.pitch_rad), (1.0, 0.0, 0.0));
        assert!(sole_at(&g, &p, 1.875).is_ok(), "toe against the riser");
        assert!(matches!(sole_at(&g, &p, 1.95), Err(StepFailure::VerticalStep { x_m: 2.0, .. })));
        assert!(matches!(sole_at(&g, &p, 2.95), Err(StepFailure::Gap { from_m: 3.0, to_m: Some(3.5) })));
        assert!(matches!(sole_at(&g, &p, 3.2), Err(StepFailure::NoGround { .. })));
        let slope = sole_at(&g, &p, 4.0).unwrap();
        assert!((slope.pitch_rad - 20f64.to_radians()).abs() < 1e-12);
        assert!(matches!(sole_at(&g, &p, 6.5), Err(StepFailure::TooSteep { .. })));
        assert!(matches!(sole_at(&g, &p, 9.0), Err(StepFailure::Uneven { .. })), "on the crest");
        assert!(matches!(sole_at(&g, &p, 9.95), Err(StepFailure::Gap { from_m: 10.0, to_m: None })));
        assert!(sole_at(&g, &p, 8.5).is_ok());
    }

    #[test]
    fn height_limits_hold_exactly_at_the_limit() {
        let p = FootstepParams::default();
        let low = Sole { x_m: 0.0, z_m: 0.0, pitch_rad: 0.0 };
        let up = |z_m| Sole { z_m, ..low };
        assert!(height_change(&p, &low, &up(0.45)).is_ok());
        assert!(matches!(height_change(&p, &low, &up(0.46)), Err(StepFailure::StepTooHigh { .. })));
        assert!(height_change(&p, &up(0.5), &low).is_ok());
        assert!(matches!(height_change(&p, &up(0.51), &low), Err(StepFailure::StepTooLow { .. })));
        assert!(!StepFailure::StepTooLow { drop_m: 0.6 }.to_string().is_empty());
    }
}
