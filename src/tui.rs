//! The live terminal view (DESIGN.md §6; seed 000 §3.1 for what is shown, seed 002 §3.1 for
//! manual driving): the world top-down, drawn by the same [`draw_scene`] routine as the PNG
//! frames through a terminal [`Painter`](crate::render::scene::Painter) ([`canvas`]); panels
//! for the fuzzy planner's inputs, outputs and fired rules, the controller mode, metrics and
//! the log ([`ui`]); pause, stepping, speed, manual driving, goal setting, zoom, pan and hot
//! reload ([`app`], [`source`]); and the terminal handling ([`terminal`]).
//!
//! Invariants: the core stays free of IO — this module is a front-end; the simulation
//! advances in fixed steps independent of the frame rate, so the same seed gives the same run
//! as `strider run`; the terminal is restored on every way out.
//!
//! [`draw_scene`]: crate::render::scene::draw_scene

pub mod app;
pub mod canvas;
pub mod source;
pub mod terminal;
pub mod ui;

pub use app::{App, Config};
pub use canvas::TermCanvas;
pub use source::MapSpec;

/// Loads `config` and runs the view until the user quits. Load errors (`file:line:col`) are
/// returned before the terminal is touched.
pub fn run(config: Config) -> anyhow::Result<()> {
    let app = App::load(config).map_err(|e| anyhow::anyhow!(e))?;
    terminal::run(app)?;
    Ok(())
}
