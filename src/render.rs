//! Drawing front-end for PNG figures.
//!
//! Everything in this module is a pure function from plain data (curves,
//! sampled grids, titles) to an in-memory [`tiny_skia::Pixmap`]. Nothing here
//! touches the file system: callers decide whether to encode the pixmap as
//! PNG, save it, or embed it elsewhere. Text is rendered with a small built-in
//! bitmap font so output is identical on every machine.

pub mod font;
pub mod gif;
pub mod plot;
pub mod png;
pub mod poses;
pub mod scene;
pub mod side_view;
pub mod sim_view;
