//! The step set and the one definition of a valid step (seed 002 §4.2), shared by the
//! sliding-window planner and the exhaustive search that widens its horizon.
//!
//! Footholds lie on a lattice: the start plus whole micrometres, step lengths being rounded
//! to the micrometre, so positions reached by different sequences compare exactly.

use super::FootstepParams;
use super::foothold::{Sole, StepFailure, height_change, sole_at};
use super::legs::{Swing, can_stand};
use crate::ground::GroundProfile;

/// The position of a foothold `offset_um` micrometres from `start_m`, metres.
pub fn position_m(start_m: f64, offset_um: i64) -> f64 {
    start_m + offset_um as f64 / 1e6
}

/// The step set: `m + 1` lengths evenly spaced in `[s_min, s_max]`, in whole micrometres.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StepSet {
    lengths_um: Vec<i64>,
    nominal: usize,
}

impl StepSet {
    /// The step set of `params` (validated ones), the nominal step `s_init`.
    pub fn new(params: &FootstepParams) -> StepSet {
        let lengths_um = params.step_lengths_m().iter().map(|s| (s * 1e6).round() as i64).collect();
        StepSet { lengths_um, nominal: params.step_index(params.step_init_m) }
    }

    /// The lengths, micrometres, shortest first.
    pub fn lengths_um(&self) -> &[i64] {
        &self.lengths_um
    }

    /// Number of lengths, `m + 1`.
    pub fn len(&self) -> usize {
        self.lengths_um.len()
    }

    /// Whether the set is empty (never, for validated parameters).
    pub fn is_empty(&self) -> bool {
        self.lengths_um.is_empty()
    }

    /// Length `j`, metres.
    pub fn length_m(&self, j: usize) -> f64 {
        self.lengths_um[j] as f64 / 1e6
    }

    /// Index of the nominal step `s_init`.
    pub fn nominal(&self) -> usize {
        self.nominal
    }
}

/// Every check of a step that moves the foot at `lift_off` past `stance` to `touch_down`:
/// the height limits, both legs at double support, the swing raised until clear, the reach
/// along it. The soles must already be valid footholds.
pub(crate) fn check_soles(
    ground: &GroundProfile,
    params: &FootstepParams,
    lift_off: Sole,
    stance: Sole,
    touch_down: Sole,
) -> Result<Swing, StepFailure> {
    height_change(params, &stance, &touch_down)?;
    can_stand(params, &stance, &touch_down)?;
    Swing::plan(ground, params, lift_off, stance, touch_down)
}

/// Whether the step that moves the foot at `lift_off_m` past the one at `stance_m` to
/// `touch_down_m` is valid, and its legs if so: all three footholds hold the whole sole, the
/// step keeps within the height limits, the swing clears the ground, both legs reach. The
/// planner takes exactly these steps.
pub fn check_step(
    ground: &GroundProfile,
    params: &FootstepParams,
    lift_off_m: f64,
    stance_m: f64,
    touch_down_m: f64,
) -> Result<Swing, StepFailure> {
    let c = sole_at(ground, params, touch_down_m)?;
    let a = sole_at(ground, params, lift_off_m)?;
    let b = sole_at(ground, params, stance_m)?;
    check_soles(ground, params, a, b, c)
}
