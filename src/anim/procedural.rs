//! Procedural key-frame locomotion for the built-in actor (seed 002 §4.1 walk generation on
//! level ground; DESIGN.md §3–4): the clips of the default animation database.
//!
//! As in seed 002 §4.1, each step is described by key frames — heel strike, loading response,
//! mid-stance, heel-off, toe-off — and the motion between them is interpolated; the swing foot
//! follows a cubic Bezier curve in the sagittal plane of its step whose two inner control points
//! are raised; the legs are solved from where the feet go. The module is split by job:
//!
//! - [`gait`]: the preset gaits (speed, cadence, key-frame values) and their validation;
//! - [`curves`]: key-frame curves, Hermite bridges, ramps and the Bezier curve;
//! - [`leg`]: leg inverse kinematics, foot pitch, the heel and toe points;
//! - [`motion`]: the path, footfalls, pelvis progress, height and heading, the swing, and the
//!   motion that poses the actor at any time;
//! - [`catalogue`]: the clips of the default database, [`default_clips`], and the named clip
//!   builders.
//!
//! Simplified with respect to the seed: only level ground (no uphill and downhill key frames, no
//! Bezier adjustment against a ground profile, no footstep search). Everything is deterministic.

pub mod catalogue;
pub mod curves;
pub mod gait;
pub mod leg;
pub mod motion;

pub use catalogue::{
    DEFAULT_STEPS, STRAIGHT_STEPS, TurningStop, contact_params, default_clips, default_database, default_intervals,
    idle_clip, locomotion, locomotion_path, pivot_clip, speed_change_clip, start_clip, stop_clip, turning_start_clip,
    turning_stop_clip,
};
pub use gait::{Gait, GaitError};

use super::actor::PELVIS_HEIGHT_M;

/// Frame rate of the default clips, frames per second.
pub const FRAME_RATE_HZ: f64 = 60.0;

/// Pelvis height when standing still, metres: the knees slightly unlocked.
pub const STANDING_PELVIS_M: f64 = PELVIS_HEIGHT_M - 0.002;
