//! Footsteps and legs on uneven ground, in the character's sagittal plane (seed 002 §3.2, §4;
//! DESIGN.md §4).
//!
//! The ground ahead is a 1-D [`GroundProfile`]: straight supported pieces along X (walking is
//! toward +X), with gaps where there is no foothold and vertical steps where two pieces meet.
//! The [`FootstepPlanner`] of seed 002 §4.2 chooses the lengths of the next `n` steps from
//! `m + 1` values evenly spaced in `[s_min, s_max]`; [`legs`] generates the leg motion of each
//! step with key frames, a cubic Bezier swing and two-link inverse kinematics (seed 002 §4.1).
//!
//! - [`crate::ground`] (below this module, and below the world's terrain that cuts them):
//!   the ground profile, its queries, and the `*.profile` file format.
//! - [`foothold`]: which foot, where a sole may stand, and why a step fails ([`StepFailure`]).
//! - [`legs`]: the key frames, the swing curve raised until it clears the ground, the pelvis
//!   height and the leg poses of one step.
//! - [`step`]: the step set and [`check_step`], the one definition of a valid step.
//! - [`planner`]: the sliding-window planner, its exhaustive look-ahead, and whole walks.
//!
//! **Invariants.** Every foothold the planner returns holds the whole sole on ground no steeper
//! than the limit, with no gap or vertical step under it, within the step-up and step-down
//! limits of the previous foothold; every swing clears the ground; both legs reach at every
//! sample. When no step can be taken the planner stops and says why — it never returns an
//! invalid step. The planner is deterministic and reads no clock: callers time it.

pub mod foothold;
pub mod legs;
pub mod planner;
mod reach;
pub mod step;

pub use crate::ground::{Course, GroundPiece, GroundProfile, Hazard, ProfileError};
pub use foothold::{Foot, Foothold, Sole, StepFailure};
pub use legs::{LegPose, StepKind, StepPose, Swing};
pub use planner::{
    Decision, FootstepPlanner, PlanError, PlannedStep, PlannerMode, StopReason, Walk, WalkOutcome, walk,
};
pub use step::{StepSet, check_step, position_m};

use crate::anim::actor::{ANKLE_HEIGHT_M, FOOT_FORWARD_M, HEEL_BACK_M, PELVIS_HEIGHT_M, SHIN_M, THIGH_M};
use crate::lex::shown;

/// The sagittal geometry of a leg and its foot. Distances in metres. Defaults: the built-in
/// actor ([`crate::anim::actor`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegGeometry {
    /// Hip to knee, metres (default 0.45).
    pub thigh_m: f64,
    /// Knee to ankle, metres (default 0.43).
    pub shin_m: f64,
    /// Height of the ankle above the sole, metres (default 0.07).
    pub ankle_height_m: f64,
    /// How far the heel reaches behind the ankle, metres (default 0.05).
    pub heel_back_m: f64,
    /// How far the toe tip reaches ahead of the ankle, metres (default 0.19).
    pub toe_forward_m: f64,
    /// Height of the hip joint above the sole when standing straight, metres (default 0.95).
    pub hip_height_m: f64,
    /// Largest knee flexion, degrees (default 140°): it sets the shortest hip-to-ankle distance.
    pub max_knee_flexion_deg: f64,
    /// Knee flexion of the supporting leg at mid-stance, degrees (default 5°, the walk's).
    pub stance_knee_deg: f64,
}

impl Default for LegGeometry {
    fn default() -> Self {
        LegGeometry {
            thigh_m: THIGH_M,
            shin_m: SHIN_M,
            ankle_height_m: ANKLE_HEIGHT_M,
            heel_back_m: HEEL_BACK_M,
            toe_forward_m: FOOT_FORWARD_M,
            hip_height_m: PELVIS_HEIGHT_M,
            max_knee_flexion_deg: 140.0,
            stance_knee_deg: 5.0,
        }
    }
}

impl LegGeometry {
    /// Thigh plus shin, metres.
    pub fn length_m(&self) -> f64 {
        self.thigh_m + self.shin_m
    }

    /// Heel to toe tip, metres.
    pub fn foot_length_m(&self) -> f64 {
        self.heel_back_m + self.toe_forward_m
    }

    /// Hip-to-ankle distance with the knee bent by `knee_deg`, metres.
    pub fn reach_m(&self, knee_deg: f64) -> f64 {
        let (t, s) = (self.thigh_m, self.shin_m);
        (t * t + s * s + 2.0 * t * s * knee_deg.to_radians().cos()).max(0.0).sqrt()
    }

    /// The longest hip-to-ankle distance a leg is asked to reach (the knee keeps about 3°),
    /// metres.
    pub fn max_reach_m(&self) -> f64 {
        self.reach_m(3.0)
    }

    /// The shortest hip-to-ankle distance (the knee at its largest flexion), metres.
    pub fn min_reach_m(&self) -> f64 {
        self.reach_m(self.max_knee_flexion_deg)
    }
}

/// Parameters of the footstep planner and of the legs it plans for (seed 002 §4.1–4.2). The
/// defaults are a person's: the built-in actor's legs and 0.24 m feet, steps of 0.25–0.9 m
/// (0.65 m preferred, the walk's), a step up of at most 0.45 m and down of at most 0.5 m,
/// slopes up to 30°, and the paper's window of n = 3 steps over m = 13 intervals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootstepParams {
    /// The legs and feet.
    pub leg: LegGeometry,
    /// Shortest step (`s_min`), metres (default 0.25).
    pub step_min_m: f64,
    /// Longest step (`s_max`), metres (default 0.9).
    pub step_max_m: f64,
    /// The preferred (nominal) step `s_init`, metres (default 0.65); snapped to the nearest of
    /// the step set's values.
    pub step_init_m: f64,
    /// Steps planned ahead, `n` (default 3).
    pub window_steps: usize,
    /// Intervals dividing `[s_min, s_max]`, `m` (default 13): `m + 1` step lengths.
    pub intervals: usize,
    /// Highest rise from one foothold to the next, metres (default 0.45).
    pub max_step_up_m: f64,
    /// Deepest drop from one foothold to the next, metres (default 0.5).
    pub max_step_down_m: f64,
    /// Steepest ground a sole may stand on, degrees (default 30°).
    pub max_slope_deg: f64,
    /// How far the swing curve's control points sit above the higher of its two footholds
    /// before any raising, metres (default 0.08).
    pub swing_lift_m: f64,
    /// Highest the control points may be raised above the higher foothold, metres (default
    /// 0.7); a swing needing more fails.
    pub max_swing_lift_m: f64,
    /// Gap kept between the swinging sole and the ground once the foot is off it, metres
    /// (default 0.02); it grows from 0 at lift-off and shrinks back to 0 at touch-down.
    pub swing_clearance_m: f64,
}

impl Default for FootstepParams {
    fn default() -> Self {
        FootstepParams {
            leg: LegGeometry::default(),
            step_min_m: 0.25,
            step_max_m: 0.9,
            step_init_m: 0.65,
            window_steps: 3,
            intervals: 13,
            max_step_up_m: 0.45,
            max_step_down_m: 0.5,
            max_slope_deg: 30.0,
            swing_lift_m: 0.08,
            max_swing_lift_m: 0.7,
            swing_clearance_m: 0.02,
        }
    }
}

/// Largest window (`n`) accepted.
pub const MAX_WINDOW_STEPS: usize = 8;
/// Largest number of intervals (`m`) accepted.
pub const MAX_INTERVALS: usize = 200;
/// Largest search space `(m + 1)^n` accepted: the window's configurations are tabulated.
pub const MAX_CONFIGURATIONS: usize = 1 << 20;
/// Smallest spacing of the step set, metres.
pub const MIN_STEP_SPACING_M: f64 = 1e-3;

/// Why a set of parameters cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamsError {
    /// A value is not finite or outside its range.
    #[error("{field} = {} is out of range: {expected}", shown(*value))]
    OutOfRange {
        /// The parameter.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What is accepted.
        expected: &'static str,
    },
    /// `s_max` is not above `s_min`.
    #[error("inverted step limits: step_max_m = {} must be greater than step_min_m = {}", shown(*max), shown(*min))]
    InvertedStepLimits {
        /// `s_min`, metres.
        min: f64,
        /// `s_max`, metres.
        max: f64,
    },
    /// A count is outside its range.
    #[error("{field} = {value} is out of range: {expected}")]
    Count {
        /// The parameter.
        field: &'static str,
        /// Its value.
        value: usize,
        /// What is accepted.
        expected: String,
    },
}

impl FootstepParams {
    /// The parameters [`FootstepParams::set`] takes by name.
    pub const KEYS: &'static str = "window_steps, intervals, step_min_m, step_max_m, step_init_m, max_step_up_m, \
                                     max_step_down_m, max_slope_deg or foot_length_m";

    /// Sets the parameter named `key` (one of [`FootstepParams::KEYS`]) to `value`: the one way
    /// maps of every format give them. Counts must be whole numbers; ranges are checked by
    /// [`FootstepParams::validate`] once all are set. `foot_length_m` scales the sole keeping
    /// the heel's share of it.
    pub fn set(&mut self, key: &str, value: f64) -> Result<(), String> {
        let count = || {
            if value.is_finite() && value >= 0.0 && value.fract() == 0.0 && value <= 1e6 {
                Ok(value as usize)
            } else {
                Err(format!("`{key}` must be a whole number ≥ 0, found {}", shown(value)))
            }
        };
        match key {
            "window_steps" => self.window_steps = count()?,
            "intervals" => self.intervals = count()?,
            "step_min_m" => self.step_min_m = value,
            "step_max_m" => self.step_max_m = value,
            "step_init_m" => self.step_init_m = value,
            "max_step_up_m" => self.max_step_up_m = value,
            "max_step_down_m" => self.max_step_down_m = value,
            "max_slope_deg" => self.max_slope_deg = value,
            "foot_length_m" => {
                // The heel's share of the sole; the actor's when the sole has no length to
                // take it from (a `foot_length_m 0` before this one).
                let foot = self.leg.foot_length_m();
                let heel = if foot > 0.0 && foot.is_finite() {
                    self.leg.heel_back_m / foot
                } else {
                    HEEL_BACK_M / (HEEL_BACK_M + FOOT_FORWARD_M)
                };
                self.leg.heel_back_m = value * heel;
                self.leg.toe_forward_m = value * (1.0 - heel);
            }
            other => return Err(format!("unknown parameter `{other}` (expected {})", Self::KEYS)),
        }
        Ok(())
    }

    /// Checks every parameter: finite, in range, `0 < s_min < s_max`, `s_init` within them,
    /// `1 ≤ n ≤ 8`, `1 ≤ m ≤ 200`, `(m + 1)^n ≤ 2^20`, steps at least 1 mm apart.
    pub fn validate(&self) -> Result<(), ParamsError> {
        let range = |field: &'static str, value: f64, ok: bool, expected: &'static str| {
            if value.is_finite() && ok { Ok(()) } else { Err(ParamsError::OutOfRange { field, value, expected }) }
        };
        let l = &self.leg;
        range("thigh_m", l.thigh_m, l.thigh_m > 0.0 && l.thigh_m <= 10.0, "0 < thigh ≤ 10 m")?;
        range("shin_m", l.shin_m, l.shin_m > 0.0 && l.shin_m <= 10.0, "0 < shin ≤ 10 m")?;
        range("ankle_height_m", l.ankle_height_m, l.ankle_height_m >= 0.0 && l.ankle_height_m <= 1.0, "0–1 m")?;
        // The sole as a whole first: maps give its length, which sets heel and toe.
        let foot = l.foot_length_m();
        range(
            "foot_length_m",
            foot,
            foot > 0.0 && l.heel_back_m <= 1.0 && l.toe_forward_m <= 1.0,
            "a sole longer than 0 reaching at most 1 m behind and 1 m ahead of the ankle (heel_back_m + toe_forward_m)",
        )?;
        range("heel_back_m", l.heel_back_m, l.heel_back_m >= 0.0 && l.heel_back_m <= 1.0, "0–1 m")?;
        range("toe_forward_m", l.toe_forward_m, l.toe_forward_m >= 0.0 && l.toe_forward_m <= 1.0, "0–1 m")?;
        let standing = l.ankle_height_m + l.length_m();
        range(
            "hip_height_m",
            l.hip_height_m,
            l.hip_height_m > l.ankle_height_m && l.hip_height_m <= standing + 1e-9,
            "above the ankle, at most ankle height + thigh + shin",
        )?;
        range(
            "max_knee_flexion_deg",
            l.max_knee_flexion_deg,
            (10.0..=175.0).contains(&l.max_knee_flexion_deg),
            "10–175°",
        )?;
        range("stance_knee_deg", l.stance_knee_deg, (3.0..=60.0).contains(&l.stance_knee_deg), "3–60°")?;
        range("step_min_m", self.step_min_m, self.step_min_m > 0.0 && self.step_min_m <= 100.0, "0 < s_min ≤ 100 m")?;
        range("step_max_m", self.step_max_m, self.step_max_m > 0.0 && self.step_max_m <= 100.0, "0 < s_max ≤ 100 m")?;
        if !(self.step_max_m > self.step_min_m) {
            return Err(ParamsError::InvertedStepLimits { min: self.step_min_m, max: self.step_max_m });
        }
        range(
            "step_init_m",
            self.step_init_m,
            self.step_init_m >= self.step_min_m && self.step_init_m <= self.step_max_m,
            "within [step_min_m, step_max_m]",
        )?;
        let count = |field: &'static str, value: usize, lo: usize, hi: usize| {
            if (lo..=hi).contains(&value) {
                Ok(())
            } else {
                Err(ParamsError::Count { field, value, expected: format!("{lo} ≤ {field} ≤ {hi}") })
            }
        };
        count("window_steps", self.window_steps, 1, MAX_WINDOW_STEPS)?;
        count("intervals", self.intervals, 1, MAX_INTERVALS)?;
        let configurations = (self.intervals + 1).checked_pow(self.window_steps as u32).unwrap_or(usize::MAX);
        if configurations > MAX_CONFIGURATIONS {
            return Err(ParamsError::Count {
                field: "window_steps",
                value: self.window_steps,
                expected: format!(
                    "(intervals + 1)^window_steps ≤ {MAX_CONFIGURATIONS}; {} ^ {} is {configurations}",
                    self.intervals + 1,
                    self.window_steps
                ),
            });
        }
        let spacing = (self.step_max_m - self.step_min_m) / self.intervals as f64;
        range("step spacing", spacing, spacing >= MIN_STEP_SPACING_M, "(s_max − s_min) / m ≥ 1 mm")?;
        range("max_step_up_m", self.max_step_up_m, self.max_step_up_m >= 0.0 && self.max_step_up_m <= 10.0, "0–10 m")?;
        range(
            "max_step_down_m",
            self.max_step_down_m,
            self.max_step_down_m >= 0.0 && self.max_step_down_m <= 10.0,
            "0–10 m",
        )?;
        range("max_slope_deg", self.max_slope_deg, (0.0..=80.0).contains(&self.max_slope_deg), "0–80°")?;
        range("swing_lift_m", self.swing_lift_m, (0.0..=10.0).contains(&self.swing_lift_m), "0–10 m")?;
        range(
            "max_swing_lift_m",
            self.max_swing_lift_m,
            self.max_swing_lift_m >= self.swing_lift_m && self.max_swing_lift_m <= 10.0,
            "at least swing_lift_m, at most 10 m",
        )?;
        range("swing_clearance_m", self.swing_clearance_m, (0.0..=1.0).contains(&self.swing_clearance_m), "0–1 m")?;
        Ok(())
    }

    /// The step set: `m + 1` lengths evenly spaced in `[s_min, s_max]`, metres.
    pub fn step_lengths_m(&self) -> Vec<f64> {
        let m = self.intervals.max(1);
        (0..=m).map(|j| self.step_min_m + (self.step_max_m - self.step_min_m) * j as f64 / m as f64).collect()
    }

    /// The index in [`step_lengths_m`](Self::step_lengths_m) nearest to `step_m` (clamped).
    pub fn step_index(&self, step_m: f64) -> usize {
        let m = self.intervals.max(1);
        let u = (step_m - self.step_min_m) / (self.step_max_m - self.step_min_m) * m as f64;
        if u.is_nan() { 0 } else { u.round().clamp(0.0, m as f64) as usize }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_a_persons_and_valid() {
        let p = FootstepParams::default();
        p.validate().unwrap();
        let foot = p.leg.foot_length_m();
        assert!((0.2..=0.3).contains(&foot), "foot {foot}");
        assert!(p.step_max_m <= 0.9 && p.max_step_up_m <= 0.45 && p.max_step_down_m <= 0.5);
        assert_eq!((p.window_steps, p.intervals), (3, 13));
        let s = p.step_lengths_m();
        assert_eq!(s.len(), 14);
        assert!((s[1] - s[0] - 0.05).abs() < 1e-12);
        assert!((s[p.step_index(p.step_init_m)] - 0.65).abs() < 1e-12);
        assert!(p.leg.min_reach_m() < 0.35 && p.leg.max_reach_m() < p.leg.length_m());
    }

    #[test]
    fn a_foot_length_is_named_as_given_and_never_made_nan() {
        let set = |pairs: &[(&str, f64)]| {
            let mut p = FootstepParams::default();
            for (k, v) in pairs {
                p.set(k, *v).unwrap();
            }
            p
        };
        // The last value counts, whatever came before.
        let p = set(&[("foot_length_m", 0.0), ("foot_length_m", 0.24)]);
        p.validate().unwrap();
        assert!((p.leg.foot_length_m() - 0.24).abs() < 1e-12);
        let d = LegGeometry::default();
        assert!((p.leg.heel_back_m / 0.24 - d.heel_back_m / d.foot_length_m()).abs() < 1e-12);
        for (value, text) in
            [(2.0, "foot_length_m = 2 is out"), (0.0, "foot_length_m = 0 is out"), (1e300, "= 1e300 is")]
        {
            let e = set(&[("foot_length_m", value)]).validate().unwrap_err().to_string();
            assert!(e.contains(text), "{e}");
        }
    }

    #[test]
    fn bad_parameters_are_named() {
        let ok = FootstepParams::default();
        let cases: Vec<(FootstepParams, &str)> = vec![
            (FootstepParams { intervals: 0, ..ok }, "intervals = 0"),
            (FootstepParams { window_steps: 0, ..ok }, "window_steps = 0"),
            (FootstepParams { step_min_m: 0.9, step_max_m: 0.3, step_init_m: 0.5, ..ok }, "inverted step limits"),
            (FootstepParams { step_min_m: 0.5, step_max_m: 0.5, step_init_m: 0.5, ..ok }, "inverted step limits"),
            (FootstepParams { step_min_m: f64::NAN, ..ok }, "step_min_m = NaN"),
            (FootstepParams { max_slope_deg: f64::INFINITY, ..ok }, "max_slope_deg = inf"),
            (FootstepParams { step_init_m: 1.5, ..ok }, "step_init_m"),
            (FootstepParams { window_steps: 9, ..ok }, "window_steps = 9"),
            (FootstepParams { window_steps: 6, intervals: 13, ..ok }, "≤ 1048576"),
            (FootstepParams { intervals: 200, step_max_m: 0.3, ..ok }, "step_init_m"),
            (FootstepParams { intervals: 100, step_min_m: 0.64, step_max_m: 0.7, ..ok }, "1 mm"),
            (FootstepParams { max_step_down_m: -0.1, ..ok }, "max_step_down_m"),
            (FootstepParams { leg: LegGeometry { thigh_m: 0.0, ..ok.leg }, ..ok }, "thigh_m"),
            (FootstepParams { step_max_m: 1e300, ..ok }, "step_max_m = 1e300 is out of range"),
        ];
        for (p, needle) in cases {
            let e = p.validate().expect_err(needle).to_string();
            assert!(e.contains(needle), "'{e}' should mention '{needle}'");
        }
    }
}
