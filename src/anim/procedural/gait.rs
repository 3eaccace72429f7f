//! Locomotion styles (seed 002 §4.1, DESIGN.md §3–4): the preset gaits of the built-in clips —
//! slow walk, walk, jog, run, sprint — with the key-frame values of one step (knee angles at
//! heel strike, loading, mid-stance and toe-off, the heel strike's toes-up pitch, the swing
//! height) and the checks on their ranges.

use crate::anim::actor::HIP_HALF_WIDTH_M;

/// A locomotion style: speed, cadence and the values of its key frames.
#[derive(Debug, Clone, PartialEq)]
pub struct Gait {
    /// Name, the prefix of clip names (`walk` gives `walk_straight`, …).
    pub name: String,
    /// Forward speed of the pelvis, m/s.
    pub speed_mps: f64,
    /// Time from one foot plant to the next (of the other foot), seconds; a stride is two steps.
    pub step_time_s: f64,
    /// Fraction of a stride each foot is on the ground: above 0.5 walking with double support,
    /// below 0.5 running with a flight phase.
    pub duty_factor: f64,
    /// Where the foot touches down ahead of the pelvis, as a fraction of the distance the pelvis
    /// travels while that foot is on the ground (the pelvis passes over the ankle a little
    /// later, at mid-stance).
    pub strike_ahead: f64,
    /// Height the two inner control points of the swing foot's Bezier curve are raised, metres.
    pub swing_height_m: f64,
    /// Amplitude of the pelvis's lateral sway toward the stance foot, metres.
    pub sway_m: f64,
    /// Lateral distance of each footprint (ankle) from the path, metres.
    pub foot_offset_m: f64,
    /// Amplitude of the shoulders' forward–backward swing, radians.
    pub arm_swing_rad: f64,
    /// Elbow flexion with the arm swung back, radians (more when it swings forward).
    pub elbow_rad: f64,
    /// Forward lean of the waist, radians.
    pub lean_rad: f64,
    /// Amplitude of the waist's twist against the pelvis, radians.
    pub twist_rad: f64,
    /// Toes-up pitch of the foot at heel strike, radians: the heel touches first.
    pub heel_strike_rad: f64,
    /// Knee flexion at heel strike, radians.
    pub knee_strike_rad: f64,
    /// Largest knee flexion while the foot takes the weight, radians: loading response when
    /// walking, mid-stance when running.
    pub knee_load_rad: f64,
    /// Knee flexion at mid-stance when walking (the leg nearly straight), radians.
    pub knee_mid_rad: f64,
    /// Knee flexion at toe-off, radians.
    pub knee_toe_off_rad: f64,
}

/// Why a gait cannot be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GaitError {
    /// A parameter is out of its range or not finite.
    #[error("gait '{gait}': {field} = {value} is out of range ({range})")]
    OutOfRange {
        /// The gait's name.
        gait: String,
        /// The parameter.
        field: &'static str,
        /// Its value.
        value: f64,
        /// The accepted range.
        range: &'static str,
    },
}

impl Gait {
    /// Slow walk: 0.8 m/s, 100 steps per minute, 0.48 m steps.
    pub fn slow_walk() -> Gait {
        Gait {
            name: "slow_walk".into(),
            speed_mps: 0.8,
            step_time_s: 0.6,
            duty_factor: 0.64,
            strike_ahead: 0.36,
            swing_height_m: 0.16,
            sway_m: 0.03,
            foot_offset_m: HIP_HALF_WIDTH_M,
            arm_swing_rad: 0.15,
            elbow_rad: 0.2,
            lean_rad: 0.02,
            twist_rad: 0.03,
            heel_strike_rad: 16f64.to_radians(),
            knee_strike_rad: 4f64.to_radians(),
            knee_load_rad: 15f64.to_radians(),
            knee_mid_rad: 5f64.to_radians(),
            knee_toe_off_rad: 35f64.to_radians(),
        }
    }

    /// Walk: 1.35 m/s, about 124 steps per minute, 0.65 m steps.
    pub fn walk() -> Gait {
        Gait {
            name: "walk".into(),
            speed_mps: 1.35,
            step_time_s: 29.0 / 60.0,
            duty_factor: 0.6,
            strike_ahead: 0.37,
            swing_height_m: 0.2,
            sway_m: 0.025,
            foot_offset_m: HIP_HALF_WIDTH_M,
            arm_swing_rad: 0.3,
            elbow_rad: 0.3,
            lean_rad: 0.04,
            twist_rad: 0.06,
            heel_strike_rad: 15f64.to_radians(),
            knee_strike_rad: 4f64.to_radians(),
            knee_load_rad: 17f64.to_radians(),
            knee_mid_rad: 5f64.to_radians(),
            knee_toe_off_rad: 38f64.to_radians(),
        }
    }

    /// Jog: 2.5 m/s, about 164 steps per minute, 0.92 m steps, short flight phases.
    pub fn jog() -> Gait {
        Gait {
            name: "jog".into(),
            speed_mps: 2.5,
            step_time_s: 22.0 / 60.0,
            duty_factor: 0.4,
            strike_ahead: 0.35,
            swing_height_m: 0.3,
            sway_m: 0.015,
            foot_offset_m: HIP_HALF_WIDTH_M,
            arm_swing_rad: 0.45,
            elbow_rad: 1.2,
            lean_rad: 0.08,
            twist_rad: 0.1,
            heel_strike_rad: 8f64.to_radians(),
            knee_strike_rad: 12f64.to_radians(),
            knee_load_rad: 42f64.to_radians(),
            knee_mid_rad: 42f64.to_radians(),
            knee_toe_off_rad: 25f64.to_radians(),
        }
    }

    /// Run: 3.6 m/s, 180 steps per minute, 1.2 m steps.
    pub fn run() -> Gait {
        Gait {
            name: "run".into(),
            speed_mps: 3.6,
            step_time_s: 20.0 / 60.0,
            duty_factor: 0.32,
            strike_ahead: 0.33,
            swing_height_m: 0.42,
            sway_m: 0.01,
            foot_offset_m: HIP_HALF_WIDTH_M,
            arm_swing_rad: 0.6,
            elbow_rad: 1.35,
            lean_rad: 0.12,
            twist_rad: 0.12,
            heel_strike_rad: 5f64.to_radians(),
            knee_strike_rad: 14f64.to_radians(),
            knee_load_rad: 44f64.to_radians(),
            knee_mid_rad: 44f64.to_radians(),
            knee_toe_off_rad: 25f64.to_radians(),
        }
    }

    /// Sprint: 5.5 m/s, about 212 steps per minute, 1.56 m steps.
    pub fn sprint() -> Gait {
        Gait {
            name: "sprint".into(),
            speed_mps: 5.5,
            step_time_s: 17.0 / 60.0,
            duty_factor: 0.25,
            strike_ahead: 0.33,
            swing_height_m: 0.55,
            sway_m: 0.008,
            foot_offset_m: HIP_HALF_WIDTH_M,
            arm_swing_rad: 0.8,
            elbow_rad: 1.45,
            lean_rad: 0.2,
            twist_rad: 0.15,
            heel_strike_rad: 2f64.to_radians(),
            knee_strike_rad: 16f64.to_radians(),
            knee_load_rad: 44f64.to_radians(),
            knee_mid_rad: 44f64.to_radians(),
            knee_toe_off_rad: 25f64.to_radians(),
        }
    }

    /// The five presets, slowest first.
    pub fn presets() -> Vec<Gait> {
        vec![Gait::slow_walk(), Gait::walk(), Gait::jog(), Gait::run(), Gait::sprint()]
    }

    /// Distance from one footprint to the next along the path, metres.
    pub fn step_length_m(&self) -> f64 {
        self.speed_mps * self.step_time_s
    }

    /// Time each foot stays on the ground, seconds.
    pub fn stance_time_s(&self) -> f64 {
        2.0 * self.duty_factor * self.step_time_s
    }

    /// Distance from the pelvis back to the footprint (ankle) at touch-down, metres.
    pub fn strike_distance_m(&self) -> f64 {
        self.strike_ahead * self.speed_mps * self.stance_time_s()
    }

    /// Steps per minute.
    pub fn cadence_spm(&self) -> f64 {
        60.0 / self.step_time_s
    }

    /// True when the feet leave the ground together at times (duty factor below 0.5).
    pub fn is_running(&self) -> bool {
        self.duty_factor < 0.5
    }

    /// Checks every parameter's range.
    pub fn validate(&self) -> Result<(), GaitError> {
        let deg = |d: f64| d.to_radians();
        let fields: [(&'static str, f64, f64, f64, &'static str); 18] = [
            ("speed_mps", self.speed_mps, 0.05, 12.0, "0.05..=12"),
            ("step_time_s", self.step_time_s, 0.1, 2.0, "0.1..=2"),
            ("duty_factor", self.duty_factor, 0.15, 0.9, "0.15..=0.9"),
            ("strike_ahead", self.strike_ahead, 0.0, 1.0, "0..=1"),
            ("swing_height_m", self.swing_height_m, 0.0, 0.8, "0..=0.8"),
            ("sway_m", self.sway_m, 0.0, 0.1, "0..=0.1"),
            ("foot_offset_m", self.foot_offset_m, 0.0, 0.2, "0..=0.2"),
            ("arm_swing_rad", self.arm_swing_rad, 0.0, 1.5, "0..=1.5"),
            ("elbow_rad", self.elbow_rad, 0.0, 2.0, "0..=2"),
            ("lean_rad", self.lean_rad, -0.3, 0.6, "-0.3..=0.6"),
            ("twist_rad", self.twist_rad, 0.0, 0.5, "0..=0.5"),
            ("heel_strike_rad", self.heel_strike_rad, 0.0, deg(35.0), "0..=35°"),
            ("knee_strike_rad", self.knee_strike_rad, 0.0, deg(60.0), "0..=60°"),
            ("knee_load_rad", self.knee_load_rad, 0.0, deg(80.0), "0..=80°"),
            ("knee_mid_rad", self.knee_mid_rad, 0.0, deg(80.0), "0..=80°"),
            ("knee_toe_off_rad", self.knee_toe_off_rad, 0.0, deg(80.0), "0..=80°"),
            ("step_length_m", self.step_length_m(), 0.05, 2.0, "0.05..=2"),
            ("strike_distance_m", self.strike_distance_m(), 0.0, 0.6, "0..=0.6"),
        ];
        for (field, value, lo, hi, range) in fields {
            if !(value >= lo && value <= hi) {
                return Err(GaitError::OutOfRange { gait: self.name.clone(), field, value, range });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaits_validate() {
        for g in Gait::presets() {
            g.validate().unwrap();
            assert!(g.cadence_spm() > 95.0 && g.cadence_spm() < 230.0);
            assert_eq!(g.is_running(), g.speed_mps > 2.0);
        }
        let mut g = Gait::walk();
        g.duty_factor = f64::NAN;
        assert!(matches!(g.validate(), Err(GaitError::OutOfRange { field: "duty_factor", .. })));
        let mut g = Gait::walk();
        g.knee_toe_off_rad = 2.0;
        assert!(matches!(g.validate(), Err(GaitError::OutOfRange { field: "knee_toe_off_rad", .. })));
        let speeds: Vec<f64> = Gait::presets().iter().map(|g| g.speed_mps).collect();
        assert_eq!(speeds, [0.8, 1.35, 2.5, 3.6, 5.5]);
        // The walk touches down about 29 cm ahead of the pelvis.
        assert!((Gait::walk().strike_distance_m() - 0.29).abs() < 0.01);
    }
}
