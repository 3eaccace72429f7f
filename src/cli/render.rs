//! `strider render`: top-down PNG frames of a navigation episode (seed 000 Fig 2-style
//! pictures) — obstacle hulls, goal, start, trail, agent and heading, sensor sectors, the
//! outcome and a legend — and a final trajectory frame; or the whole episode as one animated
//! GIF, every frame showing the same region.

use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use clap::Args;

use super::run::{MapArgs, job, load_controller, load_map_args};
use crate::files::write_atomic;
use crate::load::Outcome;
use crate::render::gif::encode_gif;
use crate::render::png::{PngPainter, encode, parse_size, render_png};
use crate::render::poses::draw_strip;
use crate::render::scene::Scene;
use crate::render::sim_view::{SideViews, scene_of, strip_pose_of};
use crate::sim::{Body, Simulation, StepParameters};

/// `strider render` options.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Map, scenario, rules and seed.
    #[command(flatten)]
    pub map: MapArgs,
    /// Directory for the PNG frames (created if missing).
    #[arg(long, required_unless_present = "gif")]
    pub out: Option<PathBuf>,
    /// Also (or instead) write the episode as one animated GIF: a frame every `--every` steps
    /// and the final one, all showing the same region, played at four times the simulated
    /// speed, looping.
    #[arg(long, value_name = "FILE")]
    pub gif: Option<PathBuf>,
    /// Write a frame every K simulation steps (0: only the final frame).
    #[arg(long, default_value_t = 20)]
    pub every: usize,
    /// Frame size, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x800", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Which episode of the matching `strider run` to render (same map, seed and numbering).
    #[arg(long, default_value_t = 0)]
    pub episode: usize,
    /// Agent body.
    #[command(flatten)]
    pub body: crate::load::BodyArgs,
    /// Also write `poses.png`: a side-view strip of the animated character's skeleton, one pose
    /// every 0.25 s over the first 16 samples.
    #[arg(long)]
    pub poses: bool,
    /// Also write `side.png`: the side view of the character's legs on the ground profile
    /// (the digital-actor paper's Fig 6 and Fig 8) through every step it took, unrolled along its path, on a map
    /// with uneven terrain; and `upper_side.png`, a strip of the character seen from its left
    /// where its upper body bent or moved its arms for obstacles (the digital-actor paper's Fig 9), on a map
    /// with obstacles the upper body can touch. Needs the animated character.
    #[arg(long)]
    pub side: bool,
    /// Also write `upper_front.png`: a strip of the character seen from ahead where its upper
    /// body twisted or moved its arms for obstacles (the digital-actor paper's Fig 9). Needs the animated
    /// character and a map with obstacles the upper body can touch.
    #[arg(long)]
    pub front: bool,
}

/// Poses in the side-view strip.
const POSES: usize = 16;

/// An animated GIF plays this many times faster than the simulated time.
const GIF_SPEEDUP: f64 = 4.0;

/// The last frame of a GIF shows this long before the animation starts again, milliseconds.
const GIF_HOLD_MS: u32 = 2000;

/// GIF frames drawn at once (in parallel) before they are encoded.
const GIF_BATCH: usize = 8;

/// `strider render`.
pub fn render(args: RenderArgs) -> Outcome {
    // Flag combinations first, before any work.
    if args.poses && args.body.body == crate::load::BodyKind::Disc {
        return Err(
            anyhow!("--poses draws the animated character's skeleton; it cannot be used with --body disc").into()
        );
    }
    if args.side && args.body.body == crate::load::BodyKind::Disc {
        return Err(anyhow!(
            "--side draws the animated character's legs and upper body; it cannot be used with --body disc"
        )
        .into());
    }
    if args.front && args.body.body == crate::load::BodyKind::Disc {
        return Err(
            anyhow!("--front draws the animated character's upper body; it cannot be used with --body disc").into()
        );
    }
    if args.gif.is_some() && args.every == 0 {
        return Err(anyhow!("--gif animates a frame every --every steps; --every 0 draws only the final one").into());
    }
    if args.out.is_none() && (args.poses || args.side || args.front) {
        return Err(anyhow!("--poses, --side and --front write pictures into the --out directory; give one").into());
    }
    if let Some(gif) = &args.gif {
        crate::files::check_writable(gif)?;
    }
    let source = load_map_args(&args.map)?;
    let controller = load_controller(args.map.rules.as_deref())?;
    let job = job(&source, args.episode, args.map.seed);
    let world = job.scenario.world();
    let upper = world.upper_body_matters();
    let legs = !job.scenario.terrain.is_flat();
    if args.side && !legs && !upper {
        return Err(anyhow!(
            "--side draws the legs on uneven terrain or the upper body among obstacles it can touch, and {} has \
             neither (flat, every obstacle a full-height wall)",
            job.scenario.name
        )
        .into());
    }
    if args.front && !upper {
        return Err(anyhow!(
            "--front draws the upper body among obstacles it can touch, and {} has none (every obstacle is a \
             full-height wall)",
            job.scenario.name
        )
        .into());
    }
    if let Some(out) = &args.out {
        std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    }
    let mut params =
        StepParameters { animation: crate::load::load_animation(&args.body)?, ..StepParameters::default() };
    params.limits.radius = job.scenario.agent_radius;
    let mut sim = Simulation::new(world, params);
    sim.add_agent(job.scenario.tasks[job.task], &controller);
    // The GIF's frames, drawn once the episode's whole region is known.
    let gif_world = sim.world.clone();
    let mut gif_frames: Vec<(Scene, u32)> = Vec::new();
    let frame_ms = (args.every as f64 * sim.params.dt_s * 1e3 / GIF_SPEEDUP).round() as u32;
    let (w, h) = args.size;
    let name = job.scenario.name.clone();
    let mut frames = 0usize;
    let mut save = |sim: &Simulation, file: String| -> Outcome {
        let caption = format!("{name}  t = {:.2} s", sim.time_s);
        let scene = scene_of(sim, Some(caption));
        if args.gif.is_some() {
            let last = file == FINAL_FRAME;
            gif_frames.push((scene.clone().in_world(&gif_world), if last { GIF_HOLD_MS } else { frame_ms }));
        }
        let Some(out) = &args.out else { return Ok(()) };
        let png = encode(&render_png(&scene, w, h)).map_err(|e| anyhow!("cannot encode PNG: {e}"))?;
        let path = out.join(file);
        write_atomic(&path, &png).with_context(|| format!("cannot write {}", path.display()))?;
        frames += 1;
        Ok(())
    };
    let mut step = 0usize;
    let mut strip = Vec::new();
    let per_pose = (0.25 / sim.params.dt_s).round().max(1.0) as usize;
    let mut side = (args.side || args.front).then(|| SideViews::new(&sim));
    while !sim.all_done() {
        if args.every > 0 && step.is_multiple_of(args.every) {
            save(&sim, format!("frame_{step:06}.png"))?;
        }
        let moving = sim.agents[0].body.speed() > 0.05 || !strip.is_empty();
        if args.poses
            && moving
            && step.is_multiple_of(per_pose)
            && strip.len() < POSES
            && let Some(b) = sim.agents[0].body.animated()
        {
            strip.push(strip_pose_of(b, format!("{:.2} s", sim.time_s)));
        }
        if let Some(side) = &mut side {
            side.before_step(&sim, step);
        }
        sim.step();
        step += 1;
        if let Some(side) = &mut side {
            side.after_step(&sim);
        }
    }
    save(&sim, FINAL_FRAME.to_string())?;
    let out = args.out.as_deref().unwrap_or(Path::new("."));
    if let Some(path) = &args.gif {
        write_gif(path, gif_frames, args.size)?;
    }
    if args.poses {
        if strip.is_empty() {
            return Err(anyhow!("--poses needs the animated body").into());
        }
        let mut painter = PngPainter::new(1600, 320);
        draw_strip(&strip, &mut painter);
        let png = encode(painter.pixmap()).map_err(|e| anyhow!("cannot encode PNG: {e}"))?;
        let path = out.join("poses.png");
        write_atomic(&path, &png).with_context(|| format!("cannot write {}", path.display()))?;
    }
    if let Some(side) = &side {
        if side.upper_unmoved() {
            eprintln!("the upper body kept the database's motion all the way: no upper-body strip to draw");
        }
        for (file, pixmap) in side.pictures(&sim, &name, args.side, args.front) {
            let png = encode(&pixmap).map_err(|e| anyhow!("cannot encode PNG: {e}"))?;
            let path = out.join(file);
            write_atomic(&path, &png).with_context(|| format!("cannot write {}", path.display()))?;
        }
    }
    let a = &sim.agents[0];
    let written = match (&args.out, &args.gif) {
        (Some(out), Some(gif)) => format!("{frames} frame(s) in {} and {}", out.display(), gif.display()),
        (Some(out), None) => format!("{frames} frame(s) in {}", out.display()),
        (None, gif) => format!("{}", gif.as_deref().unwrap_or(Path::new("")).display()),
    };
    eprintln!(
        "{written}: {} after {:.2} s, path {:.2} m",
        if a.outcome == Some(crate::sim::Outcome::Reached) { "goal reached" } else { "goal not reached" },
        a.metrics.time_s,
        a.metrics.path_length_m
    );
    Ok(())
}

/// Name of the last frame.
const FINAL_FRAME: &str = "final.png";

/// Writes the animated GIF of `frames` (scenes and how long each shows, milliseconds) at
/// `size`, every frame showing the region that holds them all, atomically.
fn write_gif(path: &Path, frames: Vec<(Scene, u32)>, size: (u32, u32)) -> Outcome {
    use rayon::prelude::*;
    let region = frames.iter().map(|(s, _)| s.auto_view()).reduce(|a, b| a.union(&b));
    let frames: Vec<(Scene, u32)> = frames.into_iter().map(|(s, ms)| (Scene { view: region, ..s }, ms)).collect();
    let drawn = frames.chunks(GIF_BATCH).flat_map(|batch| {
        batch.par_iter().map(|(scene, ms)| (render_png(scene, size.0, size.1), *ms)).collect::<Vec<_>>()
    });
    let bytes = encode_gif(drawn).map_err(|e| anyhow!("cannot encode {}: {e}", path.display()))?;
    write_atomic(path, &bytes).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}
