//! `strider steps`: walk a 1-D ground profile (`*.profile`) with the footstep planner of seed
//! 002 §4.2 — or, with `--planner off`, with the nominal step alone — and print the footholds,
//! the swings and the planning time of every step, as JSON or as a readable summary.
//!
//! Exit codes: 0 when the goal is reached, 1 when the walker stops short (the output says
//! why), 2 for bad input. The planning time is measured here, around each call into the
//! planner (the core reads no clock).

use std::io::{self, Read, Write};
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, anyhow};
use clap::{Args, ValueEnum};
use serde::Serialize;

use crate::diagnostic::SourceError;
use crate::files::write_atomic;
use crate::footstep::{Course, Decision, FootstepParams, FootstepPlanner, PlannedStep, PlannerMode, WalkOutcome};
use crate::ground::{self, MAX_PROFILE_BYTES};
use crate::load::{Failure, Outcome};
use crate::render::png::encode;
use crate::render::side_view::{SideView, render_side_view};

pub use crate::load::Switch;

/// Output format of `strider steps`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StepsFormat {
    /// One JSON object.
    Json,
    /// A readable summary.
    Text,
}

/// `strider steps` options.
#[derive(Debug, Args)]
pub struct StepsArgs {
    /// The ground profile: `start X`, `goal X` and `ground X0 Z0 X1 Z1` lines.
    pub profile: PathBuf,
    /// Steps planned ahead (the window, n).
    #[arg(long, default_value_t = FootstepParams::default().window_steps)]
    pub window: usize,
    /// Intervals dividing the range of step lengths (m): m + 1 lengths.
    #[arg(long, default_value_t = FootstepParams::default().intervals)]
    pub intervals: usize,
    /// `on`: plan the footsteps; `off`: always the nominal step, stopping before an invalid one.
    #[arg(long, value_enum, default_value_t = Switch::On)]
    pub planner: Switch,
    /// Output format.
    #[arg(long, value_enum, default_value_t = StepsFormat::Json)]
    pub format: StepsFormat,
    /// Also write the walk's side view (the digital-actor paper's Fig 6 and Fig 8): the ground profile, the
    /// footholds and the legs through every swing, as a PNG.
    #[arg(long, value_name = "OUT.png")]
    pub png: Option<PathBuf>,
}

/// The `params` object of the JSON output.
#[derive(Debug, Serialize)]
struct ParamsJson {
    foot_length_m: f64,
    step_min_m: f64,
    step_max_m: f64,
    window_steps: usize,
    intervals: usize,
    max_step_up_m: f64,
    max_step_down_m: f64,
    max_slope_deg: f64,
    leg_length_m: f64,
}

/// One foothold of the JSON output.
#[derive(Debug, Serialize)]
struct FootholdJson {
    foot: &'static str,
    x_m: f64,
    z_m: f64,
}

/// The JSON output.
#[derive(Debug, Serialize)]
struct Report {
    params: ParamsJson,
    reached: bool,
    footholds: Vec<FootholdJson>,
    swings: Vec<Vec<[f64; 2]>>,
    planning_ms: Vec<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    stopped_reason: Option<String>,
}

/// Leg poses drawn per step in the side view.
const SIDE_POSES_PER_STEP: usize = 4;

/// A walk and the time each of its steps took to plan.
struct TimedWalk {
    footholds: Vec<crate::footstep::Foothold>,
    steps: Vec<PlannedStep>,
    planning_ms: Vec<f64>,
    outcome: WalkOutcome,
}

/// Reads a profile file: at most [`MAX_PROFILE_BYTES`], UTF-8 (the error names the line and
/// column of the first bad byte).
pub fn read_profile(path: &std::path::Path) -> anyhow::Result<Course> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).with_context(|| format!("cannot open {name}"))?;
    let mut bytes = Vec::new();
    file.take(MAX_PROFILE_BYTES as u64 + 1).read_to_end(&mut bytes).with_context(|| format!("cannot read {name}"))?;
    if bytes.len() > MAX_PROFILE_BYTES {
        return Err(
            SourceError::new(&name, 0, 0, format!("larger than the {} MiB accepted", MAX_PROFILE_BYTES >> 20)).into()
        );
    }
    let text = match std::str::from_utf8(&bytes) {
        Ok(t) => t,
        Err(e) => {
            let good = &bytes[..e.valid_up_to()];
            let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
            let tail = good.rsplit(|&b| b == b'\n').next().unwrap_or(good);
            let col = String::from_utf8_lossy(tail).chars().count() + 1;
            return Err(SourceError::new(&name, line, col, "not UTF-8 text").into());
        }
    };
    Ok(ground::parse(text, &name)?)
}

/// Walks the course, timing each call into the planner.
fn timed_walk(course: &Course, params: FootstepParams, mode: PlannerMode) -> anyhow::Result<TimedWalk> {
    let mut planner = FootstepPlanner::for_course(course, params, mode)?;
    let (mut steps, mut planning_ms) = (Vec::new(), Vec::new());
    let outcome = loop {
        let clock = Instant::now();
        let decision = planner.next_step(params.step_init_m);
        let ms = clock.elapsed().as_secs_f64() * 1e3;
        match decision {
            Decision::Step(s) => {
                steps.push(s);
                planning_ms.push(ms);
            }
            Decision::Reached => break WalkOutcome::Reached,
            Decision::Stopped(r) => break WalkOutcome::Stopped(r),
        }
    };
    Ok(TimedWalk { footholds: planner.footholds().to_vec(), steps, planning_ms, outcome })
}

/// `x` rounded to the micrometre (for the swing samples).
fn micro(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

fn json(params: &FootstepParams, walk: &TimedWalk) -> anyhow::Result<String> {
    let report = Report {
        params: ParamsJson {
            foot_length_m: params.leg.foot_length_m(),
            step_min_m: params.step_min_m,
            step_max_m: params.step_max_m,
            window_steps: params.window_steps,
            intervals: params.intervals,
            max_step_up_m: params.max_step_up_m,
            max_step_down_m: params.max_step_down_m,
            max_slope_deg: params.max_slope_deg,
            leg_length_m: params.leg.length_m(),
        },
        reached: walk.outcome == WalkOutcome::Reached,
        footholds: walk
            .footholds
            .iter()
            .map(|f| FootholdJson { foot: f.foot.name(), x_m: f.sole.x_m, z_m: f.sole.z_m })
            .collect(),
        swings: walk
            .steps
            .iter()
            .map(|s| s.swing.lowest_points().iter().map(|p| [micro(p.x), micro(p.y)]).collect())
            .collect(),
        planning_ms: walk.planning_ms.clone(),
        stopped_reason: match &walk.outcome {
            WalkOutcome::Reached => None,
            WalkOutcome::Stopped(r) => Some(r.to_string()),
        },
    };
    let mut out = serde_json::to_string(&report)?;
    out.push('\n');
    Ok(out)
}

/// The `q`-quantile of `values` (nearest rank); 0 for none.
fn quantile(values: &[f64], q: f64) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => 0.0,
        n => v[((q * n as f64).ceil() as usize).clamp(1, n) - 1],
    }
}

fn text(args: &StepsArgs, params: &FootstepParams, walk: &TimedWalk) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let planner = match args.planner {
        Switch::On => format!("planner on: {} steps ahead", params.window_steps),
        Switch::Off => "planner off: the nominal step".to_string(),
    };
    let _ = writeln!(
        out,
        "{} ({planner}; steps {:.2}–{:.2} m in {} intervals, nominal {:.2} m; foot {:.2} m)",
        args.profile.display(),
        params.step_min_m,
        params.step_max_m,
        params.intervals,
        params.step_init_m,
        params.leg.foot_length_m(),
    );
    let last = walk.footholds.last().map_or(0.0, |f| f.sole.x_m);
    match &walk.outcome {
        WalkOutcome::Reached => {
            let _ =
                writeln!(out, "reached the goal: last foothold at x = {last:.3} m after {} steps", walk.steps.len());
        }
        WalkOutcome::Stopped(r) => {
            let _ = writeln!(out, "stopped after {} steps at x = {last:.3} m: {r}", walk.steps.len());
        }
    }
    let _ = writeln!(
        out,
        "{:>5}  {:<5}  {:>8}  {:>8}  {:>7}  {:>7}  {:<8}  {:>6}  {:>8}",
        "step", "foot", "x_m", "z_m", "len_m", "rise_m", "kind", "lift_m", "plan_ms"
    );
    for (i, (s, ms)) in walk.steps.iter().zip(&walk.planning_ms).enumerate() {
        let w = &s.swing;
        let _ = writeln!(
            out,
            "{:>5}  {:<5}  {:>8.3}  {:>8.3}  {:>7.3}  {:>+7.3}  {:<8}  {:>6.3}  {:>8.3}",
            i + 1,
            s.foot.name(),
            w.touch_down.x_m,
            w.touch_down.z_m,
            w.length_m(),
            w.touch_down.z_m - w.stance.z_m,
            w.kind.name(),
            w.control_height_m - w.lift_off.z_m.max(w.touch_down.z_m),
            ms
        );
    }
    if !walk.planning_ms.is_empty() {
        let _ = writeln!(
            out,
            "planning per step: median {:.3} ms, p99 {:.3} ms, max {:.3} ms",
            quantile(&walk.planning_ms, 0.5),
            quantile(&walk.planning_ms, 0.99),
            quantile(&walk.planning_ms, 1.0)
        );
    }
    out
}

/// `strider steps`.
pub fn run(args: StepsArgs) -> Outcome {
    let course = read_profile(&args.profile)?;
    let params = FootstepParams { window_steps: args.window, intervals: args.intervals, ..FootstepParams::default() };
    params.validate().context("bad planner options")?;
    let mode = match args.planner {
        Switch::On => PlannerMode::Window,
        Switch::Off => PlannerMode::Nominal,
    };
    let walk = timed_walk(&course, params, mode).map_err(|e| {
        let at = if course.start_line > 0 { format!(":{}", course.start_line) } else { String::new() };
        anyhow!("{}{at}: {e:#}", args.profile.display())
    })?;
    if let Some(path) = &args.png {
        let mut view = SideView::of_walk(course.ground.pieces(), &walk.footholds, &walk.steps, SIDE_POSES_PER_STEP);
        view.foot_length_m = params.leg.foot_length_m();
        view.goal_m = Some(course.goal_m);
        view.stopped = walk.outcome != WalkOutcome::Reached;
        let planner = match args.planner {
            Switch::On => "planner on",
            Switch::Off => "planner off",
        };
        let end = if view.stopped { "stopped" } else { "goal reached" };
        view.caption = Some(format!("{}: {planner}, {} steps, {end}", args.profile.display(), walk.steps.len()));
        let (pixmap, _) = render_side_view(&view);
        let png = encode(&pixmap).map_err(|e| anyhow!("cannot encode PNG: {e}"))?;
        write_atomic(path, &png).with_context(|| format!("cannot write {}", path.display()))?;
    }
    let out = match args.format {
        StepsFormat::Json => json(&params, &walk)?,
        StepsFormat::Text => text(&args, &params, &walk),
    };
    let mut stdout = io::stdout().lock();
    stdout.write_all(out.as_bytes())?;
    stdout.flush()?;
    match &walk.outcome {
        WalkOutcome::Reached => Ok(()),
        WalkOutcome::Stopped(r) => Err(Failure::Task(anyhow!("the goal was not reached: {r}"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_take_the_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(quantile(&v, 0.5), 50.0);
        assert_eq!(quantile(&v, 0.99), 99.0);
        assert_eq!(quantile(&v, 1.0), 100.0);
        assert_eq!(quantile(&[3.0], 0.99), 3.0);
        assert_eq!(quantile(&[], 0.5), 0.0);
    }
}
