//! Character animation (seed 000 §3.2, seed 002 §4.1; DESIGN.md §3): skeletons and clips, BVH
//! files, the built-in 22-DOF actor and its procedural walk clips, the animation database of
//! foot-plant intervals with K nearest neighbours, transitions, the SARSA-trained interval
//! policy, and the animated body that drives the simulator with root motion.
//!
//! Pure core: nothing here does IO except through the caller's strings and bytes.

pub mod actor;
pub mod body;
pub mod bvh;
pub mod clip;
pub mod db;
pub mod player;
pub mod policy;
pub mod procedural;
pub mod rig;
pub mod skeleton;
pub mod warp;

pub use clip::{Clip, Ground, mirror_pairs};
pub use db::{Database, DbError, DbParams, IntervalSpec};
pub use skeleton::{Channel, Joint, Pose, Skeleton, SkeletonError, angle_between, heading, mirror_rotation, slerp};
