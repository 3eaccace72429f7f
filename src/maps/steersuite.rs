//! SteerSuite test cases (SteerBench's XML, namespace `http://www.magix.ucla.edu/steerbench`)
//! read into a [`Scenario`] with its [`Crowd`]: every agent of the case, each with its goal
//! sequence, run together as one episode.
//!
//! SteerSuite's ground is its x–z plane (y is up): strider's (x, y) is SteerSuite's (x, z), a
//! heading `(dx, dz)` is the yaw `atan2(dz, dx)`, and heights (SteerSuite's y) are the
//! obstacles' vertical extents. Elements, by where they stand:
//!
//! | element | how it is read |
//! |---------|----------------|
//! | `SteerBenchTestCase` (or `SteerSuiteSubSpace`) | the root; its first child must be `header` |
//! | `header` | `version` (1.0, 1.1 or 1.2), `name` (kept by nothing: the scenario is named after the file), `worldBounds` (required: where random positions and targets are drawn), `description` and `passingCriteria` (skipped) |
//! | `suggestedCameraView` | skipped |
//! | `obstacle` | an axis-aligned box `xmin xmax ymin ymax zmin zmax` |
//! | `circleObstacle` | a cylinder: `radius`, `height`, `position` (its base) |
//! | `orientedBoxObstacle` | a box: `size` (x, height y, z), `position` (centre of its base), `thetaY` (degrees about the vertical, SteerSuite's sense: strider's yaw is `−thetaY`) |
//! | `obstacleRegion` | `numObstacles` squares of side `obstacleSize` and height `obstacleHeight`, drawn at random in `regionBounds` |
//! | `agent` | `name` (optional), `initialConditions`, `goalSequence` |
//! | `agentRegion` | `numAgents` agents drawn at random in `regionBounds`, all with the same `initialConditions` (no `position`) and `goalSequence` |
//! | `agentEmitter` | read as one agent, placed at the start (SteerSuite emits copies of it over time; strider does not) |
//! | `initialConditions` | `radius`, `position` (agents only), `direction`, `speed` (initial, along the direction); `color` skipped |
//! | `goalSequence` | goals done in order: `seekStaticTarget`, `fleeStaticTarget`, `seekDynamicTarget`, `fleeDynamicTarget`, `flowStaticDirection`, `flowDynamicDirection`, `idle`, `seekAxisAlignedBoxRegion` ([`GoalKind`]) |
//! | in a goal | `desiredSpeed` (required), `timeDuration` (default 100,000 s, SteerSuite's), `targetLocation`, `targetName`, `random`, `targetDirection`, `type` (the flow kind), `goalRegionBounds`; `Behaviour`, `state`, `flowType` skipped (steering hints for SteerSuite's own algorithms) |
//!
//! An x–y–z tuple is either `<x>…</x><y>…</y><z>…</z>` or `<random>true</random>`; a goal's
//! own `<random>true</random>` makes its target random too. Random draws, all from
//! [`rng::stream`] keyed by the seed (so a seed gives the same case every time), follow
//! SteerSuite's reader: fixed obstacles and agents first, then the random obstacles, each
//! square clear of everything placed (a circle of its side around its centre must overlap
//! nothing) and its centre at least its side inside its region, then the random agents, each
//! disc inside its region (the world bounds for an `agent`) and overlapping no obstacle and no
//! agent placed before it; a position is drawn again up to 10,000 times, then the case is
//! refused as too dense. A random target is drawn in the world bounds, 1 m clear of every
//! obstacle (agents ignored); a random direction uniformly over the circle; a random dynamic
//! target among the other agents. A region whose minimum is given above its maximum (one of
//! the published cases has such) is the box between the two. Agents keep the document's order (a region's agents where
//! the region stands), and goals name their dynamic targets by the first agent of that name.
//!
//! SteerSuite's steering and collision checks are planar: an obstacle blocks the agents
//! whatever its height. So an obstacle's extent is kept where it blocks a walker (from the
//! ground up past the step height) and otherwise widened to `[min(bottom, 0), max(top, 1 m)]`
//! ([`MIN_OBSTACLE_TOP_M`]); the cases' flat boxes (`ymin` = `ymax`) become walls too.
//!
//! Errors are [`SourceError`]s at the file, line and column of the element at fault: malformed
//! or truncated XML (where the parser stopped), unknown or missing elements, bad numbers,
//! counts beyond [`MAX_AGENTS`] agents or [`MAX_OBSTACLES`] obstacles (checked before anything
//! is drawn), a region too dense to place its agents, and every [`Crowd::validate`] error
//! (an agent's start overlapping an obstacle, say) at the agent's element. An XML declaration
//! after leading comments (several published cases have one) is read as if it came first.

use std::collections::HashMap;
use std::path::Path;

use glam::DVec2;
use rand_chacha::ChaCha8Rng;
use roxmltree::{Document, Node};

use crate::diagnostic::SourceError;
use crate::rng;
use crate::scenario::Scenario;
use crate::scenario::crowd::{self, Crowd, CrowdAgent, FlowKind, Goal, GoalKind};
use crate::world::{Obstacle, ObstacleShape, Pose, World};

/// Most agents a case may hold.
pub const MAX_AGENTS: usize = crowd::MAX_AGENTS;
/// Most obstacles a case may hold (the published maps have up to a few thousand).
pub const MAX_OBSTACLES: usize = 100_000;
/// The lowest top an obstacle gets, metres: SteerSuite's usual obstacle height, above the
/// step height, so every obstacle of a case is a wall as it is to SteerSuite.
pub const MIN_OBSTACLE_TOP_M: f64 = 1.0;
/// A goal's duration when the case gives none, seconds (SteerSuite's).
pub const DEFAULT_DURATION_S: f64 = 100_000.0;
/// How far a random target stays from every obstacle, metres (SteerSuite's).
pub const RANDOM_TARGET_CLEARANCE_M: f64 = 1.0;
/// How many times a random position is drawn before the case is refused as too dense
/// (SteerSuite's).
pub const MAX_DRAWS: usize = 10_000;

/// The random streams of a case, one per kind of draw, so adding a draw of one kind leaves the
/// others as they were.
const STREAM_OBSTACLES: u64 = 0x5354_0001;
const STREAM_AGENTS: u64 = 0x5354_0002;
const STREAM_DIRECTIONS: u64 = 0x5354_0003;
const STREAM_TARGETS: u64 = 0x5354_0004;

/// Reads a SteerSuite test case; `file` names it in errors and its stem names the scenario;
/// `seed` decides every random draw.
pub fn parse(text: &str, file: &str, seed: u64) -> Result<Scenario, SourceError> {
    let text = declaration_first(text);
    let doc = Document::parse(&text).map_err(|e| {
        let (line, col) = match e {
            // Truncated: located where the text ends.
            roxmltree::Error::UnexpectedEndOfStream => {
                let last = text.rsplit('\n').next().unwrap_or("");
                (text.split('\n').count(), last.chars().count() + 1)
            }
            _ => (e.pos().row as usize, e.pos().col as usize),
        };
        SourceError::new(file, line, col, format!("not a SteerSuite test case: {e}"))
    })?;
    let reader = Reader { file, doc: &doc };
    let case = reader.case()?;
    let name = Path::new(file).file_stem().and_then(|s| s.to_str()).unwrap_or(file);
    case.resolve(&reader, name, seed)
}

/// The text with an XML declaration that follows leading comments blanked out (newlines kept,
/// so positions stay), as XML allows it only first.
fn declaration_first(text: &str) -> std::borrow::Cow<'_, str> {
    let mut at = 0;
    loop {
        let rest = &text[at..];
        let trimmed = rest.trim_start();
        at += rest.len() - trimmed.len();
        if trimmed.starts_with("<!--") {
            match trimmed.find("-->") {
                Some(end) => at += end + 3,
                None => return text.into(),
            }
        } else {
            break;
        }
    }
    if at == 0 || !text[at..].starts_with("<?xml") {
        return text.into();
    }
    let Some(end) = text[at..].find("?>") else { return text.into() };
    let blank: String = text[at..at + end + 2].chars().map(|c| if c == '\n' { '\n' } else { ' ' }).collect();
    format!("{}{blank}{}", &text[..at], &text[at + end + 2..]).into()
}

/// An axis-aligned box of SteerSuite's (`xmin xmax ymin ymax zmin zmax`).
#[derive(Debug, Clone, Copy)]
struct Bounds {
    min: DVec2,
    max: DVec2,
    y: (f64, f64),
}

/// Where an agent starts.
#[derive(Debug, Clone, Copy)]
enum Place {
    Fixed(DVec2),
    Random(Bounds),
}

/// A goal's target agent.
#[derive(Debug, Clone)]
enum TargetRef {
    Named(String, (usize, usize)),
    Random,
}

/// A goal as written (random parts not drawn yet).
#[derive(Debug, Clone)]
enum RawKind {
    Seek(Option<DVec2>),
    Flee(Option<DVec2>),
    SeekAgent(TargetRef),
    FleeAgent(TargetRef),
    Region { target: DVec2, min: DVec2, max: DVec2 },
    Flow(Option<DVec2>),
    FlowDynamic(FlowKind),
    Idle,
}

#[derive(Debug, Clone)]
struct RawGoal {
    kind: RawKind,
    speed: f64,
    duration: f64,
}

/// An agent as written.
#[derive(Debug, Clone)]
struct RawAgent {
    name: String,
    place: Place,
    /// Heading (`None`: random).
    yaw: Option<f64>,
    radius: f64,
    speed: f64,
    goals: Vec<RawGoal>,
    at: (usize, usize),
}

/// A region of random square obstacles.
#[derive(Debug, Clone, Copy)]
struct ObstacleRegion {
    count: usize,
    size: f64,
    height: f64,
    bounds: Bounds,
    at: (usize, usize),
}

/// The case as written.
#[derive(Debug, Default)]
struct Case {
    world: Option<Bounds>,
    obstacles: Vec<(Obstacle, (usize, usize))>,
    regions: Vec<ObstacleRegion>,
    agents: Vec<RawAgent>,
}

struct Reader<'a, 'input> {
    file: &'a str,
    doc: &'a Document<'input>,
}

impl<'a, 'input> Reader<'a, 'input> {
    fn at(&self, n: Node) -> (usize, usize) {
        let p = self.doc.text_pos_at(n.range().start);
        (p.row as usize, p.col as usize)
    }

    fn err(&self, n: Node, message: impl Into<String>) -> SourceError {
        let (line, col) = self.at(n);
        SourceError::new(self.file, line, col, message)
    }

    fn unexpected(&self, n: Node, parent: Node, expected: &str) -> SourceError {
        self.err(
            n,
            format!("unexpected <{}> in <{}> (expected {expected})", n.tag_name().name(), parent.tag_name().name()),
        )
    }

    fn missing(&self, parent: Node, what: &str) -> SourceError {
        self.err(parent, format!("<{}> has no <{what}>", parent.tag_name().name()))
    }

    /// The text of an element, trimmed.
    fn text<'n>(&self, n: Node<'n, 'input>) -> &'n str {
        n.text().unwrap_or("").trim()
    }

    fn number(&self, n: Node) -> Result<f64, SourceError> {
        let t = self.text(n);
        match t.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.err(n, format!("<{}> must hold a finite number, found `{t}`", n.tag_name().name()))),
        }
    }

    fn count(&self, n: Node, most: usize) -> Result<usize, SourceError> {
        let t = self.text(n);
        match t.parse::<usize>() {
            Ok(v) if v <= most => Ok(v),
            Ok(v) => Err(self.err(n, format!("{v} is more than the {most} a case may hold"))),
            Err(_) => Err(self.err(n, format!("<{}> must hold a whole number, found `{t}`", n.tag_name().name()))),
        }
    }

    fn flag(&self, n: Node) -> Result<bool, SourceError> {
        match self.text(n) {
            "true" => Ok(true),
            "false" => Ok(false),
            t => Err(self.err(n, format!("<{}> must be true or false, found `{t}`", n.tag_name().name()))),
        }
    }

    /// An x–y–z tuple or `<random>true</random>` (`None`).
    fn tuple(&self, n: Node) -> Result<Option<[f64; 3]>, SourceError> {
        let mut v = [None; 3];
        let mut random = false;
        for c in n.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "x" => v[0] = Some(self.number(c)?),
                "y" => v[1] = Some(self.number(c)?),
                "z" => v[2] = Some(self.number(c)?),
                "random" => random = self.flag(c)?,
                _ => return Err(self.unexpected(c, n, "<x>, <y>, <z> or <random>")),
            }
        }
        match (v, random) {
            ([Some(x), Some(y), Some(z)], false) => Ok(Some([x, y, z])),
            ([None, None, None], true) => Ok(None),
            (_, true) => Err(self.err(n, "give either <x>, <y>, <z> or <random>true</random>, not both")),
            _ => Err(self.err(n, format!("<{}> needs <x>, <y> and <z>", n.tag_name().name()))),
        }
    }

    /// A tuple that must not be random.
    fn fixed(&self, n: Node) -> Result<[f64; 3], SourceError> {
        self.tuple(n)?.ok_or_else(|| self.err(n, format!("<{}> cannot be random here", n.tag_name().name())))
    }

    fn bounds(&self, n: Node) -> Result<Bounds, SourceError> {
        let mut v = [None; 6];
        const NAMES: [&str; 6] = ["xmin", "xmax", "ymin", "ymax", "zmin", "zmax"];
        for c in n.children().filter(Node::is_element) {
            match NAMES.iter().position(|&k| k == c.tag_name().name()) {
                Some(i) => v[i] = Some(self.number(c)?),
                None => return Err(self.unexpected(c, n, "<xmin>, <xmax>, <ymin>, <ymax>, <zmin>, <zmax>")),
            }
        }
        let mut out = [0.0; 6];
        for (i, slot) in v.iter().enumerate() {
            out[i] = slot.ok_or_else(|| self.missing(n, NAMES[i]))?;
        }
        Ok(Bounds { min: DVec2::new(out[0], out[4]), max: DVec2::new(out[1], out[5]), y: (out[2], out[3]) })
    }

    /// The whole case as written.
    fn case(&self) -> Result<Case, SourceError> {
        let root = self.doc.root_element();
        if !matches!(root.tag_name().name(), "SteerBenchTestCase" | "SteerSuiteSubSpace") {
            return Err(self.err(root, format!("expected <SteerBenchTestCase>, found <{}>", root.tag_name().name())));
        }
        let mut case = Case::default();
        let mut agents = 0usize;
        for (k, n) in root.children().filter(Node::is_element).enumerate() {
            let name = n.tag_name().name();
            if (k == 0) != (name == "header") {
                return Err(self.err(n, "<header> must come first, once"));
            }
            match name {
                "header" => case.world = Some(self.header(n)?),
                "suggestedCameraView" => {}
                "obstacle" | "circleObstacle" | "orientedBoxObstacle" => {
                    let o = self.obstacle(n)?;
                    case.obstacles.push((o, self.at(n)));
                }
                "obstacleRegion" => case.regions.push(self.obstacle_region(n)?),
                "agent" | "agentEmitter" | "agentRegion" => {
                    let world = case.world.expect("the header came first");
                    let (agent, copies) = self.agent(n, world)?;
                    agents += copies;
                    if agents > MAX_AGENTS {
                        return Err(self.err(n, format!("more than {MAX_AGENTS} agents")));
                    }
                    case.agents.extend(std::iter::repeat_n(agent, copies));
                }
                _ => {
                    return Err(self.unexpected(
                        n,
                        root,
                        "<header>, <suggestedCameraView>, <obstacle>, <circleObstacle>, <orientedBoxObstacle>, \
                         <obstacleRegion>, <agent>, <agentRegion> or <agentEmitter>",
                    ));
                }
            }
            let obstacles = case.obstacles.len() + case.regions.iter().map(|r| r.count).sum::<usize>();
            if obstacles > MAX_OBSTACLES {
                return Err(self.err(n, format!("more than {MAX_OBSTACLES} obstacles")));
            }
        }
        if case.world.is_none() {
            return Err(self.err(root, "the case has no <header>"));
        }
        Ok(case)
    }

    fn header(&self, n: Node) -> Result<Bounds, SourceError> {
        let mut world = None;
        for c in n.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "version" => {
                    if !matches!(self.text(c), "1.0" | "1.1" | "1.2") {
                        return Err(self.err(c, format!("version `{}`: expected 1.0, 1.1 or 1.2", self.text(c))));
                    }
                }
                "worldBounds" => world = Some(self.bounds(c)?),
                "name" | "description" | "passingCriteria" => {}
                _ => {
                    return Err(self.unexpected(
                        c,
                        n,
                        "<version>, <name>, <worldBounds>, <description>, <passingCriteria>",
                    ));
                }
            }
        }
        world.ok_or_else(|| self.missing(n, "worldBounds"))
    }

    /// A fixed obstacle: `obstacle`, `circleObstacle` or `orientedBoxObstacle`.
    fn obstacle(&self, n: Node) -> Result<Obstacle, SourceError> {
        let (shape, (bottom, top)) = match n.tag_name().name() {
            "obstacle" => {
                let b = self.bounds(n)?;
                if !(b.min.x < b.max.x && b.min.y < b.max.y) {
                    return Err(self.err(n, "an obstacle needs xmin < xmax and zmin < zmax"));
                }
                let size = b.max - b.min;
                (ObstacleShape::Box { center: 0.5 * (b.min + b.max), width: size.x, height: size.y, yaw: 0.0 }, b.y)
            }
            "circleObstacle" => {
                let (mut radius, mut height, mut position) = (None, None, None);
                for c in n.children().filter(Node::is_element) {
                    match c.tag_name().name() {
                        "radius" => radius = Some(self.number(c)?),
                        "height" => height = Some(self.number(c)?),
                        "position" => position = Some(self.fixed(c)?),
                        _ => return Err(self.unexpected(c, n, "<radius>, <height>, <position>")),
                    }
                }
                let radius = radius.ok_or_else(|| self.missing(n, "radius"))?;
                let height = height.ok_or_else(|| self.missing(n, "height"))?;
                let [x, y, z] = position.ok_or_else(|| self.missing(n, "position"))?;
                (ObstacleShape::Cylinder { center: DVec2::new(x, z), radius }, (y, y + height))
            }
            _ => {
                let (mut theta, mut size, mut position) = (0.0, None, None);
                for c in n.children().filter(Node::is_element) {
                    match c.tag_name().name() {
                        "thetaY" => theta = self.number(c)?,
                        "size" => size = Some(self.fixed(c)?),
                        "position" => position = Some(self.fixed(c)?),
                        _ => return Err(self.unexpected(c, n, "<thetaY>, <size>, <position>")),
                    }
                }
                let [sx, sy, sz] = size.ok_or_else(|| self.missing(n, "size"))?;
                let [x, y, z] = position.ok_or_else(|| self.missing(n, "position"))?;
                let shape =
                    ObstacleShape::Box { center: DVec2::new(x, z), width: sx, height: sz, yaw: -theta.to_radians() };
                (shape, (y, y + sy))
            }
        };
        let (z_min, z_max) = wall_extent(bottom, top);
        Obstacle::build(shape, z_min, z_max).map_err(|e| self.err(n, format!("invalid <{}>: {e}", n.tag_name().name())))
    }

    fn obstacle_region(&self, n: Node) -> Result<ObstacleRegion, SourceError> {
        let (mut count, mut size, mut height, mut bounds) = (None, None, None, None);
        for c in n.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "numObstacles" => count = Some(self.count(c, MAX_OBSTACLES)?),
                "obstacleSize" => size = Some(self.number(c)?),
                "obstacleHeight" => height = Some(self.number(c)?),
                "regionBounds" => bounds = Some(self.bounds(c)?),
                _ => {
                    return Err(self.unexpected(
                        c,
                        n,
                        "<numObstacles>, <obstacleSize>, <obstacleHeight>, <regionBounds>",
                    ));
                }
            }
        }
        let size = size.ok_or_else(|| self.missing(n, "obstacleSize"))?;
        if !(size > 0.0) {
            return Err(self.err(n, format!("obstacles need a positive <obstacleSize>, found {size}")));
        }
        Ok(ObstacleRegion {
            count: count.ok_or_else(|| self.missing(n, "numObstacles"))?,
            size,
            height: height.ok_or_else(|| self.missing(n, "obstacleHeight"))?,
            bounds: bounds.ok_or_else(|| self.missing(n, "regionBounds"))?,
            at: self.at(n),
        })
    }

    /// An `agent`, `agentEmitter` or `agentRegion` and how many agents it makes.
    fn agent(&self, n: Node, world: Bounds) -> Result<(RawAgent, usize), SourceError> {
        let region = n.tag_name().name() == "agentRegion";
        let (mut name, mut initial, mut goals, mut count, mut bounds) = (String::new(), None, None, None, None);
        for c in n.children().filter(Node::is_element) {
            match (c.tag_name().name(), region) {
                ("name", false) => name = self.text(c).to_string(),
                ("initialConditions", _) => initial = Some(c),
                ("goalSequence", _) => goals = Some(self.goals(c)?),
                ("numAgents", true) => count = Some(self.count(c, MAX_AGENTS)?),
                ("regionBounds", true) => bounds = Some(self.bounds(c)?),
                _ if region => {
                    return Err(self.unexpected(
                        c,
                        n,
                        "<numAgents>, <regionBounds>, <initialConditions>, <goalSequence>",
                    ));
                }
                _ => return Err(self.unexpected(c, n, "<name>, <initialConditions>, <goalSequence>")),
            }
        }
        let initial = initial.ok_or_else(|| self.missing(n, "initialConditions"))?;
        let goals = goals.ok_or_else(|| self.missing(n, "goalSequence"))?;
        let (mut radius, mut speed, mut yaw, mut place) = (None, None, None, None);
        for c in initial.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "radius" => radius = Some(self.number(c)?),
                "speed" => speed = Some(self.number(c)?),
                "direction" => {
                    yaw = Some(match self.tuple(c)? {
                        None => None,
                        Some([x, _, z]) if x != 0.0 || z != 0.0 => Some(z.atan2(x)),
                        Some(_) => return Err(self.err(c, "the direction must not be zero along x and z")),
                    })
                }
                "position" if !region => {
                    place = Some(match self.tuple(c)? {
                        Some([x, _, z]) => Place::Fixed(DVec2::new(x, z)),
                        None => Place::Random(world),
                    })
                }
                "color" => {}
                _ if region => return Err(self.unexpected(c, initial, "<radius>, <direction>, <speed>, <color>")),
                _ => return Err(self.unexpected(c, initial, "<radius>, <position>, <direction>, <speed>, <color>")),
            }
        }
        let place = match (region, place, bounds) {
            (true, _, Some(b)) => Place::Random(b),
            (true, _, None) => return Err(self.missing(n, "regionBounds")),
            (false, Some(p), _) => p,
            (false, None, _) => return Err(self.missing(initial, "position")),
        };
        let agent = RawAgent {
            name,
            place,
            yaw: yaw.ok_or_else(|| self.missing(initial, "direction"))?,
            radius: radius.ok_or_else(|| self.missing(initial, "radius"))?,
            speed: speed.ok_or_else(|| self.missing(initial, "speed"))?,
            goals,
            at: self.at(n),
        };
        let copies = if region { count.ok_or_else(|| self.missing(n, "numAgents"))? } else { 1 };
        Ok((agent, copies))
    }

    fn goals(&self, n: Node) -> Result<Vec<RawGoal>, SourceError> {
        let goals = n.children().filter(Node::is_element).map(|g| self.goal(g, n)).collect::<Result<Vec<_>, _>>()?;
        if goals.is_empty() {
            return Err(self.err(n, "the goal sequence is empty"));
        }
        Ok(goals)
    }

    fn goal(&self, g: Node, parent: Node) -> Result<RawGoal, SourceError> {
        let kind = g.tag_name().name();
        if !matches!(
            kind,
            "seekStaticTarget"
                | "fleeStaticTarget"
                | "seekDynamicTarget"
                | "fleeDynamicTarget"
                | "flowStaticDirection"
                | "flowDynamicDirection"
                | "idle"
                | "seekAxisAlignedBoxRegion"
        ) {
            return Err(self.unexpected(
                g,
                parent,
                "<seekStaticTarget>, <fleeStaticTarget>, <seekDynamicTarget>, <fleeDynamicTarget>, \
                 <flowStaticDirection>, <flowDynamicDirection>, <idle> or <seekAxisAlignedBoxRegion>",
            ));
        }
        let (mut location, mut direction, mut name, mut random) = (None, None, None, false);
        let (mut speed, mut duration, mut flow, mut region) = (None, DEFAULT_DURATION_S, None, None);
        for c in g.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "targetLocation" => location = Some(c),
                "targetDirection" => direction = Some(c),
                "targetName" => name = Some((self.text(c).to_string(), self.at(c))),
                "random" => random |= self.flag(c)?,
                "desiredSpeed" => speed = Some(self.number(c)?),
                "timeDuration" => duration = self.number(c)?,
                "type" => {
                    flow = Some(FlowKind::parse(self.text(c)).ok_or_else(|| {
                        self.err(
                            c,
                            format!("flow type `{}`: expected FOLLOW_CROWD, BOIDS, ADVECT or OTHER", self.text(c)),
                        )
                    })?)
                }
                "goalRegionBounds" => region = Some(self.bounds(c)?),
                "Behaviour" | "state" | "flowType" => {}
                _ => {
                    return Err(self.unexpected(
                        c,
                        g,
                        "<targetLocation>, <targetDirection>, <targetName>, <random>, <desiredSpeed>, \
                         <timeDuration>, <type>, <goalRegionBounds>, <Behaviour>",
                    ));
                }
            }
        }
        let point = |random: bool| -> Result<Option<DVec2>, SourceError> {
            let tuple = match location {
                Some(l) => self.tuple(l)?,
                None if random => None,
                None => return Err(self.missing(g, "targetLocation")),
            };
            Ok(if random { None } else { tuple.map(|[x, _, z]| DVec2::new(x, z)) })
        };
        let target = || -> Result<TargetRef, SourceError> {
            match (random, &name) {
                (true, _) => Ok(TargetRef::Random),
                (false, Some((n, at))) => Ok(TargetRef::Named(n.clone(), *at)),
                (false, None) => Err(self.missing(g, "targetName")),
            }
        };
        let kind = match kind {
            "seekStaticTarget" => RawKind::Seek(point(random)?),
            "fleeStaticTarget" => RawKind::Flee(point(random)?),
            "seekDynamicTarget" => RawKind::SeekAgent(target()?),
            "fleeDynamicTarget" => RawKind::FleeAgent(target()?),
            "flowStaticDirection" => {
                let d = direction.ok_or_else(|| self.missing(g, "targetDirection"))?;
                RawKind::Flow(match self.tuple(d)? {
                    _ if random => None,
                    None => None,
                    Some([x, _, z]) => Some(DVec2::new(x, z)),
                })
            }
            "flowDynamicDirection" => RawKind::FlowDynamic(flow.ok_or_else(|| self.missing(g, "type"))?),
            "idle" => RawKind::Idle,
            _ => {
                let b = region.ok_or_else(|| self.missing(g, "goalRegionBounds"))?;
                let l = location.ok_or_else(|| self.missing(g, "targetLocation"))?;
                let [x, _, z] = self.fixed(l)?;
                RawKind::Region { target: DVec2::new(x, z), min: b.min.min(b.max), max: b.min.max(b.max) }
            }
        };
        Ok(RawGoal { kind, speed: speed.ok_or_else(|| self.missing(g, "desiredSpeed"))?, duration })
    }
}

/// A SteerSuite obstacle's vertical extent as a wall ([`MIN_OBSTACLE_TOP_M`]).
fn wall_extent(bottom: f64, top: f64) -> (f64, f64) {
    (bottom.min(0.0), top.max(MIN_OBSTACLE_TOP_M))
}

/// What random placement must keep clear of, beyond the fixed obstacles: discs (agents) and
/// axis-aligned squares (random obstacles), in a grid of cells.
struct Placed {
    cell: f64,
    items: Vec<Item>,
    cells: HashMap<(i64, i64), Vec<usize>>,
}

#[derive(Debug, Clone, Copy)]
enum Item {
    Disc(DVec2, f64),
    Square(DVec2, f64),
}

impl Placed {
    fn new(cell: f64) -> Placed {
        Placed { cell: cell.max(0.1), items: Vec::new(), cells: HashMap::new() }
    }

    fn range(&self, c: DVec2, reach: f64) -> (i64, i64, i64, i64) {
        let f = |v: f64| (v / self.cell).floor() as i64;
        (f(c.x - reach), f(c.x + reach), f(c.y - reach), f(c.y + reach))
    }

    fn add(&mut self, item: Item) {
        let (c, reach) = match item {
            Item::Disc(c, r) | Item::Square(c, r) => (c, r),
        };
        let (x0, x1, y0, y1) = self.range(c, reach);
        let k = self.items.len();
        self.items.push(item);
        for x in x0..=x1 {
            for y in y0..=y1 {
                self.cells.entry((x, y)).or_default().push(k);
            }
        }
    }

    /// Whether a disc of `r` at `p` overlaps anything placed.
    fn overlaps(&self, p: DVec2, r: f64) -> bool {
        let (x0, x1, y0, y1) = self.range(p, r);
        (x0..=x1).any(|x| {
            (y0..=y1).any(|y| {
                self.cells.get(&(x, y)).is_some_and(|ks| {
                    ks.iter().any(|&k| match self.items[k] {
                        Item::Disc(c, cr) => c.distance(p) < cr + r,
                        Item::Square(c, half) => {
                            let d = ((p - c).abs() - DVec2::splat(half)).max(DVec2::ZERO);
                            d.length() < r
                        }
                    })
                })
            })
        })
    }
}

impl Case {
    /// Draws every random part with `seed` and builds the scenario.
    fn resolve(self, reader: &Reader, name: &str, seed: u64) -> Result<Scenario, SourceError> {
        let file = reader.file;
        let world_bounds = self.world.expect("checked when read");
        let fixed = World::new(self.obstacles.iter().map(|(o, _)| o.clone()).collect());
        let mut scratch = Vec::new();
        let blocked_by_fixed =
            |p: DVec2, r: f64, scratch: &mut Vec<usize>| crowd::overlapped_obstacle(&fixed, p, r, scratch).is_some();
        let largest = self.agents.iter().map(|a| a.radius).fold(0.5, f64::max);
        let mut placed = Placed::new(2.0 * largest);
        let mut positions: Vec<Option<DVec2>> = vec![None; self.agents.len()];
        for (i, a) in self.agents.iter().enumerate() {
            if let Place::Fixed(p) = a.place {
                positions[i] = Some(p);
                if a.radius > 0.0 {
                    placed.add(Item::Disc(p, a.radius));
                }
            }
        }
        // Random obstacles: squares clear of everything placed.
        let mut obstacles: Vec<Obstacle> = self.obstacles.into_iter().map(|(o, _)| o).collect();
        let mut draws = rng::stream(seed, 0, STREAM_OBSTACLES);
        for region in &self.regions {
            let (z_min, z_max) = wall_extent(0.0, region.height);
            for _ in 0..region.count {
                let c = draw(&mut draws, region.bounds, region.size, |c| {
                    blocked_by_fixed(c, region.size, &mut scratch) || placed.overlaps(c, region.size)
                })
                .ok_or_else(|| too_dense(file, region.at, "obstacle"))?;
                let shape = ObstacleShape::Box { center: c, width: region.size, height: region.size, yaw: 0.0 };
                let o = Obstacle::build(shape, z_min, z_max)
                    .map_err(|e| SourceError::new(file, region.at.0, region.at.1, format!("invalid obstacle: {e}")))?;
                obstacles.push(o);
                placed.add(Item::Square(c, 0.5 * region.size));
            }
        }
        // Random agents: discs in their regions clear of every obstacle and agent placed.
        let mut draws = rng::stream(seed, 0, STREAM_AGENTS);
        for (i, a) in self.agents.iter().enumerate() {
            if let Place::Random(b) = a.place {
                let p = draw(&mut draws, b, a.radius, |p| {
                    blocked_by_fixed(p, a.radius, &mut scratch) || placed.overlaps(p, a.radius)
                })
                .ok_or_else(|| too_dense(file, a.at, "agent"))?;
                positions[i] = Some(p);
                placed.add(Item::Disc(p, a.radius.max(0.0)));
            }
        }
        // Directions and targets.
        let all = World::new(obstacles.clone());
        let mut directions = rng::stream(seed, 0, STREAM_DIRECTIONS);
        let mut targets = rng::stream(seed, 0, STREAM_TARGETS);
        let n = self.agents.len();
        let mut agents = Vec::with_capacity(n);
        for (i, a) in self.agents.iter().enumerate() {
            let yaw = a.yaw.unwrap_or_else(|| rng::uniform(&mut directions, 0.0, std::f64::consts::TAU));
            let mut goals = Vec::with_capacity(a.goals.len());
            for g in &a.goals {
                let mut random_target = |targets: &mut ChaCha8Rng| {
                    draw(targets, world_bounds, RANDOM_TARGET_CLEARANCE_M, |p| {
                        crowd::overlapped_obstacle(&all, p, RANDOM_TARGET_CLEARANCE_M, &mut scratch).is_some()
                    })
                    .ok_or_else(|| too_dense(file, a.at, "random target"))
                };
                let agent_ref = |t: &TargetRef, targets: &mut ChaCha8Rng| -> Result<usize, SourceError> {
                    match t {
                        TargetRef::Named(name, at) => {
                            self.agents.iter().position(|b| !b.name.is_empty() && b.name == *name).ok_or_else(|| {
                                SourceError::new(file, at.0, at.1, format!("no agent is named `{name}`"))
                            })
                        }
                        TargetRef::Random if n > 1 => {
                            let k = ((rng::unit(targets) * (n - 1) as f64) as usize).min(n - 2);
                            Ok(if k >= i { k + 1 } else { k })
                        }
                        TargetRef::Random => {
                            Err(SourceError::new(file, a.at.0, a.at.1, "a random dynamic target needs another agent"))
                        }
                    }
                };
                let kind = match &g.kind {
                    RawKind::Seek(p) => GoalKind::SeekPoint(match p {
                        Some(p) => *p,
                        None => random_target(&mut targets)?,
                    }),
                    RawKind::Flee(p) => GoalKind::FleePoint(match p {
                        Some(p) => *p,
                        None => random_target(&mut targets)?,
                    }),
                    RawKind::SeekAgent(t) => GoalKind::SeekAgent(agent_ref(t, &mut targets)?),
                    RawKind::FleeAgent(t) => GoalKind::FleeAgent(agent_ref(t, &mut targets)?),
                    RawKind::Region { target, min, max } => {
                        GoalKind::SeekRegion { target: *target, min: *min, max: *max }
                    }
                    RawKind::Flow(d) => GoalKind::Flow(match d {
                        Some(d) => *d,
                        None => {
                            let angle = rng::uniform(&mut directions, 0.0, std::f64::consts::TAU);
                            DVec2::new(angle.cos(), angle.sin())
                        }
                    }),
                    RawKind::FlowDynamic(k) => GoalKind::FlowDynamic(*k),
                    RawKind::Idle => GoalKind::Idle,
                };
                goals.push(Goal { kind, desired_speed_mps: g.speed, duration_s: g.duration });
            }
            agents.push(CrowdAgent {
                name: a.name.clone(),
                start: Pose { position: positions[i].expect("every agent placed"), yaw },
                radius_m: a.radius,
                speed_mps: a.speed,
                goals,
            });
        }
        let mut scenario = Scenario::new(name);
        scenario.obstacles = obstacles;
        scenario.set_crowd(Crowd { agents, stay_on_arrival: false });
        scenario.validate().map_err(|m| {
            // "crowd: agent N: …" or "task N: …" name the agent.
            let agent = m
                .strip_prefix("crowd: agent ")
                .or_else(|| m.strip_prefix("task "))
                .and_then(|rest| rest.split(':').next())
                .and_then(|k| k.parse::<usize>().ok())
                .and_then(|k| self.agents.get(k.wrapping_sub(1)));
            let (line, col) = agent.map_or((0, 0), |a| a.at);
            SourceError::new(file, line, col, m)
        })?;
        Ok(scenario)
    }
}

/// A point drawn uniformly with its disc of `r` inside `b` (between `min + r` and `max − r` on
/// each axis, a bound given above the other taken as the lower; the middle line when `b` is
/// narrower than the disc) that `blocked` does not
/// refuse, within [`MAX_DRAWS`] draws.
fn draw(rng: &mut ChaCha8Rng, b: Bounds, r: f64, mut blocked: impl FnMut(DVec2) -> bool) -> Option<DVec2> {
    let axis = |a: f64, b: f64, rng: &mut ChaCha8Rng| {
        let (lo, hi) = (a.min(b) + r, a.max(b) - r);
        if lo < hi { rng::uniform(rng, lo, hi) } else { 0.5 * (lo + hi) }
    };
    (0..MAX_DRAWS).find_map(|_| {
        let p = DVec2::new(axis(b.min.x, b.max.x, rng), axis(b.min.y, b.max.y, rng));
        (!blocked(p)).then_some(p)
    })
}

fn too_dense(file: &str, at: (usize, usize), what: &str) -> SourceError {
    SourceError::new(
        file,
        at.0,
        at.1,
        format!("no free place for a random {what} after {MAX_DRAWS} draws: the region is too dense"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A case with a header over ±20 m and the given elements.
    fn case(body: &str) -> String {
        format!(
            "<!-- a comment first --><?xml version=\"1.0\"?>\n<SteerBenchTestCase xmlns=\"http://www.magix.ucla.edu/steerbench\">\n\
             <header><version>1.0</version><name>t</name><worldBounds><xmin>-20</xmin><xmax>20</xmax><ymin>0</ymin>\
             <ymax>0</ymax><zmin>-20</zmin><zmax>20</zmax></worldBounds></header>\n{body}</SteerBenchTestCase>\n"
        )
    }

    fn xyz(x: f64, z: f64) -> String {
        format!("<x>{x}</x><y>0</y><z>{z}</z>")
    }

    fn seek(x: f64, z: f64) -> String {
        format!(
            "<seekStaticTarget><targetLocation>{}</targetLocation><desiredSpeed>1.3</desiredSpeed>\
             <timeDuration>100</timeDuration><Behaviour><SteeringAlgorithm>x</SteeringAlgorithm></Behaviour>\
             </seekStaticTarget>",
            xyz(x, z)
        )
    }

    fn agent(name: &str, position: &str, goals: &str) -> String {
        format!(
            "<agent><name>{name}</name><initialConditions><radius>0.5</radius><position>{position}</position>\
             <direction><x>0</x><y>0</y><z>1</z></direction><speed>0.5</speed></initialConditions>\
             <goalSequence>{goals}</goalSequence></agent>\n"
        )
    }

    #[test]
    fn fixed_agents_and_obstacles_map_x_z_to_the_plane() {
        let body = format!(
            "<suggestedCameraView><position>{}</position><lookat>{}</lookat><up>{}</up></suggestedCameraView>\n\
             <obstacle><xmin>1</xmin><xmax>3</xmax><ymin>0</ymin><ymax>0</ymax><zmin>4</zmin><zmax>5</zmax></obstacle>\n\
             <circleObstacle><radius>1</radius><height>2</height><position>{}</position></circleObstacle>\n\
             <orientedBoxObstacle><thetaY>90</thetaY><size><x>4</x><y>1.5</y><z>1</z></size><position>{}</position>\
             </orientedBoxObstacle>\n{}{}",
            xyz(0.0, 30.0),
            xyz(0.0, 0.0),
            xyz(0.0, 1.0),
            xyz(-10.0, -10.0),
            xyz(10.0, -10.0),
            agent("A", &xyz(-5.0, 0.0), &format!("{}{}", seek(5.0, 0.0), seek(5.0, 8.0))),
            agent(
                "B",
                &xyz(5.0, 0.0),
                "<seekDynamicTarget><targetName>A</targetName><desiredSpeed>1</desiredSpeed>\
                 <timeDuration>20</timeDuration></seekDynamicTarget><idle><desiredSpeed>0</desiredSpeed></idle>",
            ),
        );
        let s = parse(&case(&body), "cases/two.xml", 7).unwrap();
        assert_eq!(s.name, "two");
        assert_eq!(s.obstacles.len(), 3);
        let b = &s.obstacles[0];
        assert_eq!(b.shape, ObstacleShape::Box { center: DVec2::new(2.0, 4.5), width: 2.0, height: 1.0, yaw: 0.0 });
        // A flat box is a wall of the lowest wall height; the cylinder keeps its 2 m.
        assert_eq!((b.z_min, b.z_max), (0.0, MIN_OBSTACLE_TOP_M));
        assert_eq!((s.obstacles[1].z_min, s.obstacles[1].z_max), (0.0, 2.0));
        // thetaY turns the other way round in strider's plane: 90° takes x to −y.
        let ObstacleShape::Box { yaw, .. } = s.obstacles[2].shape else { panic!() };
        assert!((yaw + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let c = s.crowd.as_ref().unwrap();
        assert_eq!(c.agents.len(), 2);
        let a = &c.agents[0];
        assert_eq!(
            (a.name.as_str(), a.start.position, a.radius_m, a.speed_mps),
            ("A", DVec2::new(-5.0, 0.0), 0.5, 0.5)
        );
        assert!((a.start.yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "direction +z is +y");
        assert_eq!(
            a.goals[1],
            Goal { kind: GoalKind::SeekPoint(DVec2::new(5.0, 8.0)), desired_speed_mps: 1.3, duration_s: 100.0 }
        );
        let g = &c.agents[1].goals;
        assert_eq!(g[0].kind, GoalKind::SeekAgent(0));
        assert_eq!((g[1].kind, g[1].duration_s), (GoalKind::Idle, DEFAULT_DURATION_S));
        // One task per agent, to its last static target (or its start), within its radius.
        assert_eq!(s.tasks.len(), 2);
        assert_eq!(
            (s.tasks[0].goal, s.tasks[0].goal_radius, s.tasks[0].time_limit_s),
            (DVec2::new(5.0, 8.0), 0.5, 200.0)
        );
        assert_eq!(s.tasks[1].goal, DVec2::new(5.0, 0.0));
    }

    /// A case of one agent region of `n` agents over the box ±`half` with one random target.
    fn region_case(n: usize, half: f64, obstacles: usize) -> String {
        case(&format!(
            "<obstacleRegion><numObstacles>{obstacles}</numObstacles><obstacleSize>1</obstacleSize>\
             <obstacleHeight>1</obstacleHeight><regionBounds><xmin>-15</xmin><xmax>15</xmax><ymin>0</ymin><ymax>0</ymax>\
             <zmin>-15</zmin><zmax>15</zmax></regionBounds></obstacleRegion>\n\
             <agentRegion><numAgents>{n}</numAgents><regionBounds><xmin>-{half}</xmin><xmax>{half}</xmax><ymin>0</ymin>\
             <ymax>0</ymax><zmin>-{half}</zmin><zmax>{half}</zmax></regionBounds><initialConditions>\
             <direction><random>true</random></direction><radius>0.4</radius><speed>0</speed></initialConditions>\
             <goalSequence><seekStaticTarget><targetLocation><random>true</random></targetLocation>\
             <desiredSpeed>1.3</desiredSpeed><timeDuration>50</timeDuration></seekStaticTarget></goalSequence>\
             </agentRegion>\n"
        ))
    }

    #[test]
    fn random_draws_follow_the_seed_and_overlap_nothing() {
        let text = region_case(60, 6.0, 20);
        let a = parse(&text, "r.xml", 3).unwrap();
        assert_eq!(parse(&text, "r.xml", 3).unwrap().crowd, a.crowd, "the same seed draws the same case");
        let b = parse(&text, "r.xml", 4).unwrap();
        assert_ne!(b.crowd, a.crowd, "another seed draws another case");
        let c = a.crowd.as_ref().unwrap();
        assert_eq!((c.agents.len(), a.obstacles.len()), (60, 20));
        assert!(c.overlapping_starts(0.0).is_empty());
        let world = World::new(a.obstacles.clone());
        let mut scratch = Vec::new();
        for ag in &c.agents {
            let p = ag.start.position;
            assert!(p.abs().max_element() <= 6.0 - 0.4, "inside its region: {p}");
            assert!(crowd::overlapped_obstacle(&world, p, 0.4, &mut scratch).is_none());
            let GoalKind::SeekPoint(t) = ag.goals[0].kind else { panic!() };
            assert!(t.abs().max_element() <= 19.0 && world.clearance(t, 2.0, &mut scratch) >= 1.0, "{t}");
        }
        // The random squares stand apart: a circle of their side around each centre is clear.
        for (i, o) in a.obstacles.iter().enumerate() {
            let ObstacleShape::Box { center, .. } = o.shape else { panic!() };
            for q in &a.obstacles[..i] {
                let ObstacleShape::Box { center: d, .. } = q.shape else { panic!() };
                assert!((center - d).abs().max_element() >= 1.0);
            }
        }
    }

    #[test]
    fn bad_cases_are_located_errors() {
        let at = |text: &str| {
            let e = parse(text, "c.xml", 1).unwrap_err();
            (e.line, e.col, e.message)
        };
        // Truncated XML: located where it ends.
        let full = case(&agent("A", &xyz(0.0, 0.0), &seek(3.0, 0.0)));
        let cut = &full[..full.len() - 40];
        let (line, _, m) = at(cut);
        assert_eq!(line, cut.lines().count(), "{m}");
        assert!(m.contains("not a SteerSuite test case"), "{m}");
        // A bad number, an unknown element, a missing one.
        let (line, _, m) = at(&case(&agent("A", &xyz(0.0, 0.0), &seek(3.0, 0.0)).replace("<speed>0.5", "<speed>fast")));
        assert_eq!(line, 4, "{m}");
        assert!(m.contains("`fast`"), "{m}");
        let (_, _, m) = at(&case("<wall/>\n"));
        assert!(m.contains("unexpected <wall>"), "{m}");
        let (line, col, m) =
            at(&case(&agent("A", &xyz(0.0, 0.0), &seek(3.0, 0.0)).replace("<radius>0.5</radius>", "")));
        assert!(m.contains("no <radius>") && line == 4 && col > 1, "{m}");
        let (_, _, m) = at(&case(&agent(
            "A",
            &xyz(0.0, 0.0),
            "<seekDynamicTarget><targetName>Z</targetName><desiredSpeed>1</desiredSpeed></seekDynamicTarget>",
        )));
        assert!(m.contains("no agent is named `Z`"), "{m}");
        // Counts are bounded before anything is drawn.
        let (_, _, m) = at(&region_case(MAX_AGENTS + 1, 5.0, 0));
        assert!(m.contains("more than"), "{m}");
        // Too dense a region, and an agent inside a wall.
        let (line, _, m) = at(&region_case(400, 3.0, 0));
        assert!(m.contains("too dense") && line == 5, "{m}");
        let wall = "<obstacle><xmin>-1</xmin><xmax>1</xmax><ymin>0</ymin><ymax>1</ymax><zmin>-1</zmin><zmax>1</zmax></obstacle>\n";
        let (line, _, m) = at(&case(&format!("{wall}{}", agent("A", &xyz(0.0, 1.2), &seek(3.0, 3.0)))));
        assert!(m.contains("agent 1") && m.contains("overlaps obstacle 1") && line == 5, "{m}");
        // Header first.
        let (_, _, m) = at("<SteerBenchTestCase><agent/></SteerBenchTestCase>");
        assert!(m.contains("<header> must come first"), "{m}");
    }
}
