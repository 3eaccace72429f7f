//! strider: a terminal / 2D top-down simulator and scripting host for character locomotion
//! planning. See `ARCHITECTURE.md` for the map of the crate.
//!
//! The modules stand in layers and every import points down them (`ARCHITECTURE.md`, Layers;
//! `tests/layers.rs` checks it): the foundation ([`rng`], [`diagnostic`], [`lex`]), geometry
//! ([`geom`], [`ground`]), the character ([`anim`], [`footstep`]), the [`world`], the planners
//! ([`fuzzy`], [`plan`], [`upper`]), scenarios ([`scenario`], [`maps`]) and the simulation
//! ([`sim`], [`experiment`], [`baseline`]) make the core, which does no IO, reads no clock and
//! owns no global random generator (every random number comes from an [`rng::stream`] keyed by
//! the inputs); above it [`script`] builds core data from Rhai and [`builtin`] holds the data
//! compiled into the binary; then [`reproduce`], [`render`], [`snapshot`] and the loading
//! layer ([`load`], [`files`]); at the top the front ends, [`cli`] and [`tui`].

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
