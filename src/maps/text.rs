//! The plain text world format: one item per line, numbers in metres and radians, `#` starts a
//! comment (to the end of the line), blank lines are ignored. Tokens are separated by spaces or
//! tabs.
//!
//! | line | meaning |
//! |------|---------|
//! | `start x y [yaw_rad]` | start pose of a task (yaw defaults to 0, facing +x) |
//! | `goal x y [radius]` | goal point of a task (radius defaults to [`Task::DEFAULT_GOAL_RADIUS`]) |
//! | `time_limit t` | time limit (s) of the task completed by the latest `goal` (default: [`Task::new`]) |
//! | `agent_radius r` | radius of the agent's disc (default [`DEFAULT_AGENT_RADIUS`](crate::scenario::DEFAULT_AGENT_RADIUS)) |
//! | `cyl x y r` | vertical cylinder |
//! | `box cx cy w h [yaw_rad]` | rectangle of size `w` × `h` centred on `(cx, cy)` |
//! | `convex x1 y1 x2 y2 …` | convex hull of at least three points |
//! | `poly x1 y1 x2 y2 …` | simple, possibly non-convex polygon (split into convex parts) |
//! | `z_extent z_min z_max` | vertical extent of the obstacles that follow (default [`DEFAULT_Z`]) |
//! | `platform z SHAPE` | terrain: flat ground at height `z` inside `SHAPE` (a `box`, `cyl`, `convex` or `poly` with its numbers, as above) |
//! | `hole SHAPE` | terrain: no ground (no foothold) inside `SHAPE` |
//! | `slope z0 z1 cx cy w h [yaw_rad]` | terrain: a box whose ground rises linearly from `z0` at its −x side to `z1` at its +x side |
//! | `stairs z0 z1 n cx cy w h [yaw_rad]` | terrain: a box of `n` equal treads along its x axis, from ground at `z0` before it to `z1` after it (tread `k` at `z0 + (z1 − z0)(k + 1)/(n + 1)`) |
//! | `footsteps KEY VALUE …` | the footstep planner's parameters of the map's characters (any of [`FootstepParams::KEYS`](crate::footstep::FootstepParams::KEYS)), checked as a whole |
//! | `ref_path_length L` | BARN extra: reference path length (m), the scenario's [`Reference`] |
//! | `optimal_time_at_2mps T` | BARN extra: optimal time at 2 m/s (s), kept in [`TextExtras`] |
//! | `crowd [stay]`, `agent …`, `seek …`, `flee …`, … | a crowd: many agents with goal sequences in one episode ([`crowd`]) |
//!
//! Terrain lines are painted in order over flat ground at height 0: where several cover a point,
//! the last decides (a `hole` then `platform … cyl` stones on it make stepping stones). Obstacles
//! whose `z_extent` keeps them at most 0.45 m high are ground to step onto or over, not walls
//! ([`Terrain`](crate::world::Terrain)).
//!
//! Tasks are formed by pairing `start` and `goal` lines in order: each `goal` takes the oldest
//! `start` not yet paired, so both `start A, goal A, start B, goal B` and
//! `start A, start B, goal A, goal B` give the tasks A and B. A `goal` with no unpaired `start`
//! before it, or a `start` never followed by a `goal`, is an error. The BARN challenge worlds and
//! the Menge U-trap scenario are files of this format.
//!
//! Errors name the file, the line and the column of the offending token; a line that takes the
//! world past its bounds ([`WorldBudget`]) is refused as it is read. After reading, the
//! parser checks that no start or goal lies within the agent radius of an obstacle and then runs
//! [`Scenario::validate`]. [`write`] prints a scenario in this format with shortest
//! round-tripping numbers, so [`parse`] gives back the same obstacles and tasks.

mod crowd;

use std::fmt::Write as _;
use std::path::Path;

use glam::DVec2;

use super::{TaskEnd, first_blocked_task};
use crate::diagnostic::SourceError;
use crate::geom::GeomError;
use crate::lex::{Tok, tokenize};
use crate::scenario::{BARN_SPEED_MPS, Reference, Scenario, WorldBudget};
use crate::world::obstacle::DEFAULT_Z;
use crate::world::terrain::{FeatureKind, MAX_STAIR_TREADS, TerrainFeature};
use crate::world::{Obstacle, ObstacleShape, Pose, Task, Terrain, World};

/// Largest `ref_path_length` (metres) or `optimal_time_at_2mps` (seconds) a world may give.
const MAX_REFERENCE: f64 = 1e7;

/// Items of a text world that describe a benchmark rather than the world (BARN challenge).
/// [`parse`] keeps the reference path's length as the scenario's [`Reference`] (from
/// `optimal_time_at_2mps` at 2 m/s when only that is given); [`parse_with_extras`] also
/// returns them as written.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TextExtras {
    /// `ref_path_length`: length of the BARN reference path, metres.
    pub ref_path_length_m: Option<f64>,
    /// `optimal_time_at_2mps`: the BARN optimal time (reference length at 2 m/s), seconds.
    pub optimal_time_at_2mps_s: Option<f64>,
}

/// Reads a text world. `file` names the source in errors; its stem becomes the scenario name.
/// Benchmark extras (`ref_path_length`, `optimal_time_at_2mps`) become the scenario's
/// [`Reference`].
pub fn parse(text: &str, file: &str) -> Result<Scenario, SourceError> {
    parse_with_extras(text, file).map(|(scenario, _)| scenario)
}

/// Reads a text world and its benchmark extras. See the [module docs](self) for the format.
pub fn parse_with_extras(text: &str, file: &str) -> Result<(Scenario, TextExtras), SourceError> {
    Parser::new(file).run(text)
}

/// Writes `scenario` in the text world format: agent radius, tasks, then obstacles, numbers in
/// shortest round-tripping form (`format!("{x}")`). A time limit is written only when it
/// differs from [`Task::new`]'s default, a `z_extent` line only when the extent changes.
pub fn write(scenario: &Scenario) -> String {
    let mut out = String::new();
    let name: String = scenario.name.chars().map(|c| if c.is_control() { ' ' } else { c }).collect();
    let _ = writeln!(out, "# strider text world: {name}");
    let _ = writeln!(out, "agent_radius {}", scenario.agent_radius);
    if let Some(r) = scenario.reference {
        let _ = writeln!(out, "ref_path_length {}", r.path_length_m);
    }
    let (f, d) = (&scenario.footsteps, crate::footstep::FootstepParams::default());
    if *f != d {
        let _ = writeln!(
            out,
            "footsteps window_steps {} intervals {} step_min_m {} step_max_m {} step_init_m {} max_step_up_m {} \
             max_step_down_m {} max_slope_deg {} foot_length_m {}",
            f.window_steps,
            f.intervals,
            f.step_min_m,
            f.step_max_m,
            f.step_init_m,
            f.max_step_up_m,
            f.max_step_down_m,
            f.max_slope_deg,
            f.leg.foot_length_m()
        );
    }
    if let Some(c) = &scenario.crowd {
        crowd::write(&mut out, c);
    }
    for t in scenario.tasks.iter().filter(|_| scenario.crowd.is_none()) {
        let s = t.start;
        let _ = writeln!(out, "start {} {} {}", s.position.x, s.position.y, s.yaw);
        let _ = writeln!(out, "goal {} {} {}", t.goal.x, t.goal.y, t.goal_radius);
        if t.time_limit_s.to_bits() != Task::new(t.start, t.goal).time_limit_s.to_bits() {
            let _ = writeln!(out, "time_limit {}", t.time_limit_s);
        }
    }
    let mut z = DEFAULT_Z;
    for o in &scenario.obstacles {
        if (o.z_min, o.z_max) != z {
            z = (o.z_min, o.z_max);
            let _ = writeln!(out, "z_extent {} {}", z.0, z.1);
        }
        match &o.shape {
            ObstacleShape::Box { center, width, height, yaw } => {
                let _ = writeln!(out, "box {} {} {width} {height} {yaw}", center.x, center.y);
            }
            ObstacleShape::Cylinder { center, radius } => {
                let _ = writeln!(out, "cyl {} {} {radius}", center.x, center.y);
            }
            ObstacleShape::Convex { points } => write_points(&mut out, "convex", points),
            ObstacleShape::Polygon { outline } => write_points(&mut out, "poly", outline),
        }
    }
    for f in scenario.terrain.features() {
        let lead = match f.kind {
            FeatureKind::Platform { z_m } => format!("platform {z_m} "),
            FeatureKind::Hole => "hole ".to_string(),
            FeatureKind::Slope { z0_m, z1_m } => format!("slope {z0_m} {z1_m}"),
            FeatureKind::Stairs { z0_m, z1_m, treads } => format!("stairs {z0_m} {z1_m} {treads}"),
        };
        out.push_str(&lead);
        match (&f.shape, f.kind) {
            (
                ObstacleShape::Box { center, width, height, yaw },
                FeatureKind::Slope { .. } | FeatureKind::Stairs { .. },
            ) => {
                let _ = writeln!(out, " {} {} {width} {height} {yaw}", center.x, center.y);
            }
            (ObstacleShape::Box { center, width, height, yaw }, _) => {
                let _ = writeln!(out, "box {} {} {width} {height} {yaw}", center.x, center.y);
            }
            (ObstacleShape::Cylinder { center, radius }, _) => {
                let _ = writeln!(out, "cyl {} {} {radius}", center.x, center.y);
            }
            (ObstacleShape::Convex { points }, _) => write_points(&mut out, "convex", points),
            (ObstacleShape::Polygon { outline }, _) => write_points(&mut out, "poly", outline),
        }
    }
    out
}

fn write_points(out: &mut String, keyword: &str, points: &[DVec2]) {
    out.push_str(keyword);
    for p in points {
        let _ = write!(out, " {} {}", p.x, p.y);
    }
    out.push('\n');
}

/// A `start` line waiting for its `goal`.
struct PendingStart {
    pose: Pose,
    line: usize,
    col: usize,
}

/// A finished task with the source positions of its start and goal.
struct TaskSource {
    start_line: usize,
    start_col: usize,
    goal_line: usize,
    goal_col: usize,
}

struct Parser<'f> {
    file: &'f str,
    scenario: Scenario,
    extras: TextExtras,
    task_sources: Vec<TaskSource>,
    obstacle_lines: Vec<usize>,
    pending: std::collections::VecDeque<PendingStart>,
    agent_radius_line: Option<usize>,
    last_goal_line: Option<usize>,
    time_limit_line: Option<usize>,
    z: (f64, f64),
    features: Vec<TerrainFeature>,
    budget: WorldBudget,
    crowd: crowd::CrowdLines,
}

impl<'f> Parser<'f> {
    fn new(file: &'f str) -> Self {
        let name = Path::new(file).file_stem().and_then(|s| s.to_str()).unwrap_or(file);
        Parser {
            file,
            scenario: Scenario::new(name),
            extras: TextExtras::default(),
            task_sources: Vec::new(),
            obstacle_lines: Vec::new(),
            pending: Default::default(),
            agent_radius_line: None,
            last_goal_line: None,
            time_limit_line: None,
            z: DEFAULT_Z,
            features: Vec::new(),
            budget: WorldBudget::default(),
            crowd: Default::default(),
        }
    }

    fn err(&self, line: usize, col: usize, message: impl Into<String>) -> SourceError {
        SourceError::new(self.file, line, col, message)
    }

    fn run(mut self, text: &str) -> Result<(Scenario, TextExtras), SourceError> {
        for (i, line) in text.lines().enumerate() {
            let (toks, end_col) = tokenize(line);
            if let Some((&keyword, args)) = toks.split_first() {
                self.item(i + 1, keyword, args, end_col)?;
            }
        }
        self.scenario.terrain = Terrain::from_features(std::mem::take(&mut self.features));
        if let Some(p) = self.pending.front() {
            return Err(self.err(p.line, p.col, "this `start` has no matching `goal` line"));
        }
        if self.crowd.is_crowd() {
            self.make_crowd()?;
        }
        if self.scenario.tasks.is_empty() {
            return Err(self.err(0, 0, "no task: the world needs a `start x y` line followed by a `goal x y` line"));
        }
        self.check_tasks()?;
        let e = self.extras;
        let length = e.ref_path_length_m.or(e.optimal_time_at_2mps_s.map(|t| t * BARN_SPEED_MPS));
        self.scenario.reference = length.map(|path_length_m| Reference { path_length_m });
        Ok((self.scenario, self.extras))
    }

    /// Reads the numbers after a keyword, checking their count is in `min..=max`.
    fn numbers(
        &self,
        line: usize,
        keyword: Tok<'_>,
        args: &[Tok<'_>],
        end_col: usize,
        (min, max): (usize, usize),
        usage: &str,
    ) -> Result<Vec<f64>, SourceError> {
        if args.len() < min {
            let expected = if min == max { format!("{min}") } else { format!("at least {min}") };
            return Err(self.err(
                line,
                end_col,
                format!("`{}` needs {expected} number(s), found {} (usage: {usage})", keyword.text, args.len()),
            ));
        }
        if args.len() > max {
            let extra = args[max];
            return Err(self.err(
                line,
                extra.col,
                format!(
                    "too many numbers for `{}`: expected at most {max}, found {}; unexpected `{}` (usage: {usage})",
                    keyword.text,
                    args.len(),
                    extra.text
                ),
            ));
        }
        args.iter().map(|t| self.number(line, *t)).collect()
    }

    fn number(&self, line: usize, tok: Tok<'_>) -> Result<f64, SourceError> {
        tok.number(self.file, line)
    }

    fn positive(&self, line: usize, tok: Tok<'_>, value: f64, what: &str) -> Result<f64, SourceError> {
        if value > 0.0 {
            Ok(value)
        } else {
            Err(self.err(line, tok.col, format!("{what} must be positive, found {value}")))
        }
    }

    /// Turns a crowd world's agents and `start`/`goal` pairs into its crowd, and the scenario's
    /// tasks into the crowd's (their sources the agents').
    fn make_crowd(&mut self) -> Result<(), SourceError> {
        let tasks: Vec<_> = self
            .scenario
            .tasks
            .iter()
            .zip(&self.task_sources)
            .map(|(t, s)| {
                (*t, crowd::AgentSource { start: (s.start_line, s.start_col), goal: (s.goal_line, s.goal_col) })
            })
            .collect();
        let lines = std::mem::take(&mut self.crowd);
        let (c, sources) = lines.finish(self.file, &tasks, self.scenario.agent_radius)?;
        self.scenario.set_crowd(c);
        self.task_sources = sources
            .into_iter()
            .map(|s| TaskSource {
                start_line: s.start.0,
                start_col: s.start.1,
                goal_line: s.goal.0,
                goal_col: s.goal.1,
            })
            .collect();
        Ok(())
    }

    fn item(&mut self, line: usize, kw: Tok<'_>, args: &[Tok<'_>], end_col: usize) -> Result<(), SourceError> {
        if crowd::CrowdLines::handles(kw.text) {
            return self.crowd.item(self.file, line, kw, args, end_col);
        }
        match kw.text {
            "start" => {
                let v = self.numbers(line, kw, args, end_col, (2, 3), "start x y [yaw_rad]")?;
                let yaw = v.get(2).copied().unwrap_or(0.0);
                let pose = Pose { position: DVec2::new(v[0], v[1]), yaw };
                self.pending.push_back(PendingStart { pose, line, col: args[0].col });
            }
            "goal" => {
                let v = self.numbers(line, kw, args, end_col, (2, 3), "goal x y [radius]")?;
                let Some(start) = self.pending.pop_front() else {
                    return Err(self.err(line, kw.col, "`goal` without a `start`: give `start x y` before each goal"));
                };
                let mut task = Task::new(start.pose, DVec2::new(v[0], v[1]));
                if let Some(&r) = v.get(2) {
                    task.goal_radius = self.positive(line, args[2], r, "goal radius")?;
                }
                self.scenario.tasks.push(task);
                self.crowd.task_added(self.scenario.tasks.len() - 1);
                self.task_sources.push(TaskSource {
                    start_line: start.line,
                    start_col: start.col,
                    goal_line: line,
                    goal_col: args[0].col,
                });
                self.last_goal_line = Some(line);
                self.time_limit_line = None;
            }
            "footsteps" => {
                // Pairs of a parameter's name and its value.
                if args.is_empty() || !args.len().is_multiple_of(2) {
                    return Err(self.err(
                        line,
                        args.last().map_or(end_col, |t| t.col),
                        "`footsteps` needs pairs of a parameter and its value (usage: footsteps step_max_m 0.8 …)",
                    ));
                }
                for pair in args.chunks_exact(2) {
                    let v = self.number(line, pair[1])?;
                    self.scenario.footsteps.set(pair[0].text, v).map_err(|m| self.err(line, pair[0].col, m))?;
                }
                self.scenario.footsteps.validate().map_err(|e| self.err(line, kw.col, format!("footsteps: {e}")))?;
            }
            "time_limit" => {
                let v = self.numbers(line, kw, args, end_col, (1, 1), "time_limit seconds")?;
                let t = self.positive(line, args[0], v[0], "time limit")?;
                if let Some(prev) = self.time_limit_line {
                    return Err(self.err(line, kw.col, format!("this task already has a time limit (line {prev})")));
                }
                match (self.last_goal_line, self.scenario.tasks.last_mut()) {
                    (Some(_), Some(task)) => task.time_limit_s = t,
                    _ => return Err(self.err(line, kw.col, "`time_limit` must follow the `goal` of its task")),
                }
                self.time_limit_line = Some(line);
            }
            "agent_radius" => {
                let v = self.numbers(line, kw, args, end_col, (1, 1), "agent_radius r")?;
                let r = self.positive(line, args[0], v[0], "agent radius")?;
                if let Some(prev) = self.agent_radius_line {
                    return Err(self.err(line, kw.col, format!("agent_radius is already given on line {prev}")));
                }
                self.scenario.agent_radius = r;
                self.agent_radius_line = Some(line);
            }
            "z_extent" => {
                let v = self.numbers(line, kw, args, end_col, (2, 2), "z_extent z_min z_max")?;
                if v[0] >= v[1] {
                    return Err(self.err(
                        line,
                        args[1].col,
                        format!("z_max must be above z_min, found z_min {} and z_max {}", v[0], v[1]),
                    ));
                }
                self.z = (v[0], v[1]);
            }
            "ref_path_length" | "optimal_time_at_2mps" => {
                let v = self.numbers(line, kw, args, end_col, (1, 1), &format!("{} value", kw.text))?;
                let value = self.positive(line, args[0], v[0], kw.text)?;
                // Far beyond any world (tasks stay within 100 km), and small enough that the
                // reference length derived from it stays finite.
                if value > MAX_REFERENCE {
                    return Err(self.err(
                        line,
                        args[0].col,
                        format!("`{}` must be at most {MAX_REFERENCE:e}", kw.text),
                    ));
                }
                let slot = if kw.text == "ref_path_length" {
                    &mut self.extras.ref_path_length_m
                } else {
                    &mut self.extras.optimal_time_at_2mps_s
                };
                if slot.is_some() {
                    return Err(self.err(line, kw.col, format!("`{}` is given twice", kw.text)));
                }
                *slot = Some(value);
            }
            "cyl" | "box" | "convex" | "poly" => {
                let shape = self.shape(line, kw, args, end_col)?;
                self.obstacle(line, kw, args, shape)?;
            }
            "platform" | "hole" => {
                let usage = format!(
                    "{} {}SHAPE …, SHAPE one of box, cyl, convex, poly",
                    kw.text,
                    if kw.text == "hole" { "" } else { "z " }
                );
                let skip = usize::from(kw.text == "platform");
                let Some(&shape_kw) = args.get(skip) else {
                    return Err(self.err(line, end_col, format!("`{}` needs a shape (usage: {usage})", kw.text)));
                };
                let kind = if skip == 1 {
                    FeatureKind::Platform { z_m: self.number(line, args[0])? }
                } else {
                    FeatureKind::Hole
                };
                if !matches!(shape_kw.text, "box" | "cyl" | "convex" | "poly") {
                    return Err(self.err(
                        line,
                        shape_kw.col,
                        format!(
                            "expected a shape (box, cyl, convex or poly), found `{}` (usage: {usage})",
                            shape_kw.text
                        ),
                    ));
                }
                let shape = self.shape(line, shape_kw, &args[skip + 1..], end_col)?;
                self.feature(line, kw, shape, kind)?;
            }
            "slope" | "stairs" => {
                let stairs = kw.text == "stairs";
                let usage =
                    if stairs { "stairs z0 z1 treads cx cy w h [yaw_rad]" } else { "slope z0 z1 cx cy w h [yaw_rad]" };
                let lead = if stairs { 3 } else { 2 };
                let v = self.numbers(line, kw, args, end_col, (lead + 4, lead + 5), usage)?;
                let kind = if stairs {
                    let n = v[2];
                    if !(n >= 1.0 && n.fract() == 0.0 && n <= MAX_STAIR_TREADS as f64) {
                        return Err(self.err(
                            line,
                            args[2].col,
                            format!("stairs need a whole number of treads from 1 to {MAX_STAIR_TREADS}, found {n}"),
                        ));
                    }
                    FeatureKind::Stairs { z0_m: v[0], z1_m: v[1], treads: n as usize }
                } else {
                    FeatureKind::Slope { z0_m: v[0], z1_m: v[1] }
                };
                let width = self.positive(line, args[lead + 2], v[lead + 2], "box width")?;
                let height = self.positive(line, args[lead + 3], v[lead + 3], "box height")?;
                let yaw = v.get(lead + 4).copied().unwrap_or(0.0);
                let shape = ObstacleShape::Box { center: DVec2::new(v[lead], v[lead + 1]), width, height, yaw };
                self.feature(line, kw, shape, kind)?;
            }
            other => {
                return Err(self.err(
                    line,
                    kw.col,
                    format!(
                        "unknown item `{other}` (expected start, goal, time_limit, agent_radius, cyl, box, convex, \
                         poly, z_extent, platform, hole, slope, stairs, ref_path_length, optimal_time_at_2mps, crowd, \
                         agent, seek, flee, seek_agent, flee_agent, seek_region, flow, flow_dynamic or idle)"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Reads an outline: `kw` is its keyword (`cyl`, `box`, `convex` or `poly`), `args` its
    /// numbers.
    fn shape(&self, line: usize, kw: Tok<'_>, args: &[Tok<'_>], end_col: usize) -> Result<ObstacleShape, SourceError> {
        Ok(match kw.text {
            "cyl" => {
                let v = self.numbers(line, kw, args, end_col, (3, 3), "cyl x y r")?;
                let radius = self.positive(line, args[2], v[2], "cylinder radius")?;
                ObstacleShape::Cylinder { center: DVec2::new(v[0], v[1]), radius }
            }
            "box" => {
                let v = self.numbers(line, kw, args, end_col, (4, 5), "box cx cy w h [yaw_rad]")?;
                let width = self.positive(line, args[2], v[2], "box width")?;
                let height = self.positive(line, args[3], v[3], "box height")?;
                let yaw = v.get(4).copied().unwrap_or(0.0);
                ObstacleShape::Box { center: DVec2::new(v[0], v[1]), width, height, yaw }
            }
            _ => {
                let usage = format!("{} x1 y1 x2 y2 x3 y3 …", kw.text);
                let v = self.numbers(line, kw, args, end_col, (6, usize::MAX), &usage)?;
                if v.len() % 2 == 1 {
                    let last = args[args.len() - 1];
                    return Err(self.err(
                        line,
                        last.col,
                        format!("`{}` takes x y pairs, but this last number has no partner", kw.text),
                    ));
                }
                let points: Vec<DVec2> = v.chunks_exact(2).map(|c| DVec2::new(c[0], c[1])).collect();
                if kw.text == "convex" {
                    ObstacleShape::Convex { points }
                } else {
                    ObstacleShape::Polygon { outline: points }
                }
            }
        })
    }

    fn feature(
        &mut self,
        line: usize,
        kw: Tok<'_>,
        shape: ObstacleShape,
        kind: FeatureKind,
    ) -> Result<(), SourceError> {
        let feature = TerrainFeature::new(shape, kind)
            .map_err(|e| self.err(line, kw.col, format!("invalid `{}`: {e}", kw.text)))?;
        self.budget.feature(&feature).map_err(|m| self.err(line, kw.col, m))?;
        self.features.push(feature);
        Ok(())
    }

    fn obstacle(
        &mut self,
        line: usize,
        kw: Tok<'_>,
        args: &[Tok<'_>],
        shape: ObstacleShape,
    ) -> Result<(), SourceError> {
        match Obstacle::build(shape, self.z.0, self.z.1) {
            Ok(o) => {
                self.budget.obstacle(&o).map_err(|m| self.err(line, kw.col, m))?;
                self.scenario.obstacles.push(o);
                self.obstacle_lines.push(line);
                Ok(())
            }
            Err(e) => {
                let point = match &e {
                    GeomError::NonFinite { index } | GeomError::OutOfRange { index, .. } => Some(*index),
                    GeomError::RepeatedPoint { second, .. } => Some(*second),
                    GeomError::NotConvex { index } => Some(*index),
                    GeomError::SelfIntersecting { second, .. } => Some(*second),
                    GeomError::TooManyPoints { max, .. } => Some(*max),
                    _ => None,
                };
                let col = match (kw.text, point) {
                    ("convex" | "poly", Some(i)) => args.get(2 * i).map_or(kw.col, |t| t.col),
                    _ => kw.col,
                };
                Err(self.err(line, col, format!("invalid `{}` obstacle: {e}", kw.text)))
            }
        }
    }

    /// Starts and goals must be clear of every obstacle by the agent radius; then the
    /// scenario's own validation runs.
    fn check_tasks(&self) -> Result<(), SourceError> {
        let world = World::new(self.scenario.obstacles.clone());
        if let Some((i, end, o)) = first_blocked_task(&self.scenario, &world) {
            let t = &self.scenario.tasks[i];
            let src = &self.task_sources[i];
            let (what, p, line, col) = match end {
                TaskEnd::Start => ("start", t.start.position, src.start_line, src.start_col),
                TaskEnd::Goal => ("goal", t.goal, src.goal_line, src.goal_col),
            };
            return Err(self.err(
                line,
                col,
                format!(
                    "the {what} ({}, {}) of task {} is inside the obstacle on line {} (grown by the agent radius {} m)",
                    p.x,
                    p.y,
                    i + 1,
                    self.obstacle_lines.get(o).copied().unwrap_or(0),
                    self.scenario.agent_radius
                ),
            ));
        }
        self.scenario.validate().map_err(|message| {
            let task = message
                .strip_prefix("task ")
                .or_else(|| message.strip_prefix("crowd: agent "))
                .and_then(|rest| rest.split(':').next())
                .and_then(|n| n.parse::<usize>().ok())
                .and_then(|n| n.checked_sub(1))
                .and_then(|i| self.task_sources.get(i));
            match task {
                Some(src) if message.contains("goal") => self.err(src.goal_line, src.goal_col, message),
                Some(src) => self.err(src.start_line, src.start_col, message),
                None => self.err(self.agent_radius_line.unwrap_or(0), 0, message),
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_barn_world_keeps_its_reference_and_scores_episodes() {
        let text = "start 0 0\ngoal 10 0\nref_path_length 10.5\noptimal_time_at_2mps 5.25\ncyl 5 3 0.075\n";
        let s = parse(text, "barn.txt").unwrap();
        let r = s.reference.unwrap();
        assert_eq!(r.path_length_m, 10.5);
        // OT = 5.25 s at 2 m/s: faster than 2·OT scores 0.5, slower than 8·OT 0.125, a miss 0.
        assert_eq!(r.score(true, 3.0, BARN_SPEED_MPS), 0.5);
        assert!((r.score(true, 21.0, BARN_SPEED_MPS) - 0.25).abs() < 1e-12);
        assert_eq!(r.score(true, 100.0, BARN_SPEED_MPS), 0.125);
        assert_eq!(r.score(false, 3.0, BARN_SPEED_MPS), 0.0);
        // Only the optimal time given: the reference length is that time at 2 m/s.
        let s = parse("start 0 0\ngoal 10 0\noptimal_time_at_2mps 6\n", "b.txt").unwrap();
        assert_eq!(s.reference.unwrap().path_length_m, 12.0);
        // Written and read back.
        assert_eq!(parse(&write(&s), "b.txt").unwrap().reference, s.reference);
        assert_eq!(parse("start 0 0\ngoal 10 0\n", "w.txt").unwrap().reference, None);
    }

    #[test]
    fn missing_number_points_past_the_end() {
        let e = parse("start 1", "w.txt").unwrap_err();
        assert_eq!((e.line, e.col), (1, 8), "{e}");
    }
}
