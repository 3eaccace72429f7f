//! strider: a terminal / 2D top-down simulator and scripting host for character locomotion
//! planning. See `ARCHITECTURE.md` for the map of the crate.
//!
//! Dependencies flow one way: the core ([`fuzzy`]) does no IO and reads no clock; [`script`]
//! builds core data from Rhai; [`render`] and [`cli`] are front-ends.

pub mod cli;
pub mod diagnostic;
pub mod fuzzy;
pub mod geom;
pub mod render;
pub mod rng;
pub mod script;
