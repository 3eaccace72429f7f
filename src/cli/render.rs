//! `strider render`: top-down PNG frames of a navigation episode (seed 000 Fig 2-style
//! pictures) — obstacle hulls, goal, trail, agent and heading, sensor sectors — and a final
//! trajectory frame.

use std::path::PathBuf;

use anyhow::{Context, anyhow};
use clap::Args;

use super::run::{MapArgs, job, load_controller, load_map_args};
use crate::files::write_atomic;
use crate::load::Outcome;
use crate::render::png::{PngPainter, encode, parse_size, render_png};
use crate::render::poses::{StripPose, draw_strip};
use crate::render::side_view::render_side_view;
use crate::render::sim_view::{SideRecorder, StripView, scene_of, strip_pose_of, upper_strip_pose};
use crate::sim::{Body, Simulation, StepParameters};

/// `strider render` options.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Map, scenario, rules and seed.
    #[command(flatten)]
    pub map: MapArgs,
    /// Directory for the PNG frames (created if missing).
    #[arg(long)]
    pub out: PathBuf,
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

/// Most poses in an upper-body strip.
const UPPER_POSES: usize = 12;

/// Offsets (radians) from which a moment counts as the upper body moving for obstacles in the
/// upper-body strips.
const UPPER_MOVED_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// Leg poses per step in the side view.
const SIDE_POSES_PER_STEP: usize = 4;

/// Poses in the side-view strip.
const POSES: usize = 16;

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
    std::fs::create_dir_all(&args.out).with_context(|| format!("cannot create {}", args.out.display()))?;
    let mut params =
        StepParameters { animation: crate::load::load_animation(&args.body)?, ..StepParameters::default() };
    params.limits.radius = job.scenario.agent_radius;
    let mut sim = Simulation::new(world, params);
    sim.add_agent(job.scenario.tasks[job.task], &controller);
    let (w, h) = args.size;
    let name = job.scenario.name.clone();
    let mut frames = 0usize;
    let mut save = |sim: &Simulation, file: String| -> Outcome {
        let caption = format!("{name}  t = {:.2} s", sim.time_s);
        let pixmap = render_png(&scene_of(sim, Some(caption)), w, h);
        let png = encode(&pixmap).map_err(|e| anyhow!("cannot encode PNG: {e}"))?;
        let path = args.out.join(file);
        write_atomic(&path, &png).with_context(|| format!("cannot write {}", path.display()))?;
        frames += 1;
        Ok(())
    };
    let mut step = 0usize;
    let mut strip = Vec::new();
    let mut side = SideRecorder::default();
    // Upper-body strips: the moments the upper body moved for obstacles, every 0.25 s.
    let mut upper_poses: Vec<(StripPose, StripPose)> = Vec::new();
    let per_pose = (0.25 / sim.params.dt_s).round().max(1.0) as usize;
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
        if (args.side || args.front)
            && upper
            && step.is_multiple_of(per_pose)
            && let Some(b) = sim.agents[0].body.animated()
        {
            let c = b.upper_offsets();
            let moved = c.waist.iter().chain(c.arms.iter().flatten()).any(|x| x.abs() > UPPER_MOVED_RAD);
            if moved {
                // Time, waist bend and twist in degrees.
                let caption =
                    format!("{:.2} s b{:.0} t{:+.0}", sim.time_s, c.waist[0].to_degrees(), c.waist[1].to_degrees());
                let solids: Vec<_> = sim.world.solids().collect();
                let pose = |view| upper_strip_pose(b, solids.iter().copied(), view, caption.clone());
                upper_poses.push((pose(StripView::Side), pose(StripView::Front)));
            }
        }
        sim.step();
        step += 1;
        if args.side
            && legs
            && let Some(f) = sim.agents[0].body.animated().and_then(|b| b.footing())
        {
            side.observe(f);
        }
    }
    save(&sim, "final.png".to_string())?;
    if args.poses {
        if strip.is_empty() {
            return Err(anyhow!("--poses needs the animated body").into());
        }
        let mut painter = PngPainter::new(1600, 320);
        draw_strip(&strip, &mut painter);
        let png = encode(painter.pixmap()).map_err(|e| anyhow!("cannot encode PNG: {e}"))?;
        let path = args.out.join("poses.png");
        write_atomic(&path, &png).with_context(|| format!("cannot write {}", path.display()))?;
    }
    if args.side && legs {
        let foot = sim.agents[0].body.animated().and_then(|b| b.footing()).map(|f| f.params().leg.foot_length_m());
        let mut view = side.view(foot.unwrap_or_default(), SIDE_POSES_PER_STEP);
        view.caption = Some(format!("{name}: {} steps, side view", side.len()));
        let (pixmap, _) = render_side_view(&view);
        let png = encode(&pixmap).map_err(|e| anyhow!("cannot encode PNG: {e}"))?;
        let path = args.out.join("side.png");
        write_atomic(&path, &png).with_context(|| format!("cannot write {}", path.display()))?;
    }
    if (args.side || args.front) && upper {
        if upper_poses.is_empty() {
            eprintln!("the upper body kept the database's motion all the way: no upper-body strip to draw");
        }
        // At most a dozen moments, evenly spread over those recorded.
        let n = upper_poses.len();
        let picked: Vec<&(StripPose, StripPose)> =
            (0..n.min(UPPER_POSES)).map(|k| &upper_poses[k * n / n.min(UPPER_POSES)]).collect();
        for (wanted, file, view) in [(args.side, "upper_side.png", 0), (args.front, "upper_front.png", 1)] {
            if !wanted || picked.is_empty() {
                continue;
            }
            let poses: Vec<StripPose> =
                picked.iter().map(|p| if view == 0 { p.0.clone() } else { p.1.clone() }).collect();
            let mut painter = PngPainter::new(160 * poses.len() as u32, 360);
            draw_strip(&poses, &mut painter);
            let png = encode(painter.pixmap()).map_err(|e| anyhow!("cannot encode PNG: {e}"))?;
            let path = args.out.join(file);
            write_atomic(&path, &png).with_context(|| format!("cannot write {}", path.display()))?;
        }
    }
    let a = &sim.agents[0];
    eprintln!(
        "{frames} frame(s) in {}: {} after {:.2} s, path {:.2} m",
        args.out.display(),
        if a.outcome == Some(crate::sim::Outcome::Reached) { "goal reached" } else { "goal not reached" },
        a.metrics.time_s,
        a.metrics.path_length_m
    );
    Ok(())
}
