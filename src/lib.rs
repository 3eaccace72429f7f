//! strider: a terminal / 2D top-down simulator and scripting host for character locomotion
//! planning. See `ARCHITECTURE.md` for the map of the crate.
//!
//! Dependencies flow one way: the core ([`fuzzy`], [`geom`], [`world`], [`plan`], [`anim`],
//! [`sim`], [`experiment`], [`scenario`], [`maps`], [`rng`]) does no IO, reads no clock and owns
//! no global random generator (every random number comes from an [`rng::stream`] keyed by the
//! inputs); [`script`] builds core data from Rhai; [`render`], [`tui`], [`cli`] and
//! [`snapshot`] are front-ends, and [`builtin`] holds the data compiled into the binary.

// `!(x > 0.0)` is deliberately true for NaN; the code relies on that to reject NaN input.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod anim;
pub mod baseline;
pub mod builtin;
pub mod cli;
pub mod diagnostic;
pub mod experiment;
pub mod files;
pub mod footstep;
pub mod fuzzy;
pub mod geom;
pub mod ground;
pub mod lex;
pub mod load;
pub mod maps;
pub mod plan;
pub mod render;
pub mod reproduce;
pub mod rng;
pub mod scenario;
pub mod script;
pub mod sim;
pub mod snapshot;
pub mod tui;
pub mod upper;
pub mod world;
