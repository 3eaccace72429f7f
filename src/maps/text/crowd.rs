//! The crowd lines of the plain text world format ([`super`]): a `crowd` line, `agent` lines
//! and the goal lines that follow each agent, read into a [`Crowd`] and written back.
//!
//! | line | meaning |
//! |------|---------|
//! | `crowd [stay]` | the world is a crowd: all its agents run together as one episode; `stay` keeps agents standing once they ended their last goal (by default they leave) |
//! | `agent x y yaw_rad radius_m speed_mps [NAME]` | an agent of the crowd: start pose, radius, initial speed, a name of one word |
//! | `seek x y speed_mps duration_s` | the last agent's next goal: walk to (x, y) |
//! | `flee x y speed_mps duration_s` | walk away from (x, y) |
//! | `seek_agent N speed_mps duration_s` | follow agent N (numbered from 1 in file order) |
//! | `flee_agent N speed_mps duration_s` | walk away from agent N |
//! | `seek_region x y xmin ymin xmax ymax speed_mps duration_s` | walk to (x, y); achieved inside the box |
//! | `flow dx dy speed_mps duration_s` | walk along the direction (dx, dy) |
//! | `flow_dynamic KIND speed_mps duration_s` | follow the crowd's flow: `follow_crowd`, `boids`, `advect` or `other` |
//! | `idle speed_mps duration_s` | stand |
//!
//! The goals' meanings are [`GoalKind`]'s. A world with a `crowd` or an `agent` line is a
//! crowd. Its `start`/`goal` pairs are agents too, each where its `goal` line stands in the
//! order: the world's `agent_radius`, speed 0, and one `seek` of its goal at
//! 1.3 m/s for its time limit ([`CrowdAgent::from_task`]) (an agent arrives within its own radius,
//! so such a `goal` takes no radius of its own). The scenario's tasks are then the crowd's
//! ([`Crowd::tasks`]).

use std::fmt::Write as _;

use glam::DVec2;

use crate::diagnostic::SourceError;
use crate::lex::Tok;
use crate::scenario::crowd::{Crowd, CrowdAgent, FlowKind, Goal, GoalKind};
use crate::world::{Pose, Task};

/// Where an agent came from in the file.
#[derive(Debug, Clone, Copy)]
pub(super) struct AgentSource {
    /// Line and column of its start (the `agent` or `start` line).
    pub start: (usize, usize),
    /// Line and column of the goal its task leads to.
    pub goal: (usize, usize),
}

/// One agent in file order: read from `agent` lines, or the task of a `start`/`goal` pair.
enum Entry {
    Agent { agent: CrowdAgent, at: (usize, usize), goal_lines: Vec<(usize, usize)> },
    Task(usize),
}

/// The crowd lines of a text world being read.
#[derive(Default)]
pub(super) struct CrowdLines {
    crowd_line: Option<usize>,
    stay: bool,
    entries: Vec<Entry>,
}

impl CrowdLines {
    /// Whether `keyword` starts a crowd line.
    pub fn handles(keyword: &str) -> bool {
        keyword == "crowd" || keyword == "agent" || GoalKind::KEYWORDS.contains(&keyword)
    }

    /// Notes that the `start`/`goal` pair just read made task `index`.
    pub fn task_added(&mut self, index: usize) {
        self.entries.push(Entry::Task(index));
    }

    /// Reads one crowd line.
    pub fn item(
        &mut self,
        file: &str,
        line: usize,
        kw: Tok<'_>,
        args: &[Tok<'_>],
        end_col: usize,
    ) -> Result<(), SourceError> {
        let err = |col: usize, m: String| SourceError::new(file, line, col, m);
        let numbers = |from: usize, count: usize, usage: &str| -> Result<Vec<f64>, SourceError> {
            if args.len() != from + count {
                let col = args.get(from + count).map_or(end_col, |t| t.col);
                return Err(err(col, format!("`{}` takes {} value(s) (usage: {usage})", kw.text, from + count)));
            }
            args[from..].iter().map(|t| t.number(file, line)).collect()
        };
        match kw.text {
            "crowd" => {
                if let Some(prev) = self.crowd_line {
                    return Err(err(kw.col, format!("`crowd` is already given on line {prev}")));
                }
                match args {
                    [] => {}
                    [t] if t.text == "stay" => self.stay = true,
                    [t, ..] => {
                        return Err(err(
                            t.col,
                            format!("expected `stay` or nothing after `crowd`, found `{}`", t.text),
                        ));
                    }
                }
                self.crowd_line = Some(line);
            }
            "agent" => {
                let usage = "agent x y yaw_rad radius_m speed_mps [NAME]";
                let (values, name) = match args.len() {
                    5 => (numbers(0, 5, usage)?, String::new()),
                    6 => (
                        args[..5].iter().map(|t| t.number(file, line)).collect::<Result<Vec<_>, _>>()?,
                        args[5].text.to_string(),
                    ),
                    _ => {
                        return Err(err(
                            args.get(6).map_or(end_col, |t| t.col),
                            format!("`agent` takes 5 numbers and a name (usage: {usage})"),
                        ));
                    }
                };
                let agent = CrowdAgent {
                    name,
                    start: Pose { position: DVec2::new(values[0], values[1]), yaw: values[2] },
                    radius_m: values[3],
                    speed_mps: values[4],
                    goals: Vec::new(),
                };
                self.entries.push(Entry::Agent { agent, at: (line, kw.col), goal_lines: Vec::new() });
            }
            _ => {
                let Some(Entry::Agent { agent, goal_lines, .. }) =
                    self.entries.iter_mut().rev().find(|e| matches!(e, Entry::Agent { .. }))
                else {
                    return Err(err(
                        kw.col,
                        format!("`{}` is a goal of the agent before it: give an `agent` line first", kw.text),
                    ));
                };
                let (lead, usage) = match kw.text {
                    "seek" | "flee" => (2, "x y speed_mps duration_s"),
                    "flow" => (2, "dx dy speed_mps duration_s"),
                    "seek_agent" | "flee_agent" => (1, "AGENT_NUMBER speed_mps duration_s"),
                    "seek_region" => (6, "x y xmin ymin xmax ymax speed_mps duration_s"),
                    "flow_dynamic" => (1, "follow_crowd|boids|advect|other speed_mps duration_s"),
                    _ => (0, "speed_mps duration_s"),
                };
                let usage = format!("{} {usage}", kw.text);
                let tail = numbers(lead, 2, &usage)?;
                let lead_numbers = |n: usize| -> Result<Vec<f64>, SourceError> {
                    args[..n].iter().map(|t| t.number(file, line)).collect()
                };
                let kind = match kw.text {
                    "seek" | "flee" | "flow" => {
                        let v = lead_numbers(2)?;
                        let p = DVec2::new(v[0], v[1]);
                        match kw.text {
                            "seek" => GoalKind::SeekPoint(p),
                            "flee" => GoalKind::FleePoint(p),
                            _ => GoalKind::Flow(p),
                        }
                    }
                    "seek_agent" | "flee_agent" => {
                        let n = args[0].text.parse::<usize>().ok().filter(|&n| n >= 1).ok_or_else(|| {
                            err(args[0].col, format!("expected an agent number from 1, found `{}`", args[0].text))
                        })?;
                        if kw.text == "seek_agent" { GoalKind::SeekAgent(n - 1) } else { GoalKind::FleeAgent(n - 1) }
                    }
                    "seek_region" => {
                        let v = lead_numbers(6)?;
                        GoalKind::SeekRegion {
                            target: DVec2::new(v[0], v[1]),
                            min: DVec2::new(v[2], v[3]),
                            max: DVec2::new(v[4], v[5]),
                        }
                    }
                    "flow_dynamic" => GoalKind::FlowDynamic(FlowKind::parse(args[0].text).ok_or_else(|| {
                        err(
                            args[0].col,
                            format!("flow kind `{}`: expected follow_crowd, boids, advect or other", args[0].text),
                        )
                    })?),
                    _ => GoalKind::Idle,
                };
                agent.goals.push(Goal { kind, desired_speed_mps: tail[0], duration_s: tail[1] });
                goal_lines.push((line, kw.col));
            }
        }
        Ok(())
    }

    /// Whether the world is a crowd (it has a `crowd` or an `agent` line).
    pub fn is_crowd(&self) -> bool {
        self.crowd_line.is_some() || self.entries.iter().any(|e| matches!(e, Entry::Agent { .. }))
    }

    /// The crowd of a crowd world, its agents in file order, with where each came from; `tasks`
    /// are the world's `start`/`goal` pairs with the positions of their start and goal lines,
    /// `radius` the world's agent radius.
    pub fn finish(
        self,
        file: &str,
        tasks: &[(Task, AgentSource)],
        radius: f64,
    ) -> Result<(Crowd, Vec<AgentSource>), SourceError> {
        let mut agents = Vec::with_capacity(self.entries.len());
        let mut sources = Vec::with_capacity(self.entries.len());
        for e in self.entries {
            match e {
                Entry::Agent { agent, at, goal_lines } => {
                    let last_static = agent.goals.iter().rposition(|g| g.kind.static_target().is_some());
                    let goal = last_static.map_or(at, |k| goal_lines[k]);
                    sources.push(AgentSource { start: at, goal });
                    agents.push(agent);
                }
                Entry::Task(k) => {
                    let (t, source) = tasks[k];
                    if t.goal_radius != Task::DEFAULT_GOAL_RADIUS {
                        let (line, col) = source.goal;
                        return Err(SourceError::new(
                            file,
                            line,
                            col,
                            "in a crowd an agent arrives within its own radius: drop this goal's radius",
                        ));
                    }
                    agents.push(CrowdAgent::from_task(&t, radius));
                    sources.push(source);
                }
            }
        }
        Ok((Crowd { agents, stay_on_arrival: self.stay }, sources))
    }
}

/// Writes `crowd` as crowd lines: the `crowd` line, then each agent with its goals. Names are
/// written as one word (blanks, `#` and control characters become `_`).
pub(super) fn write(out: &mut String, crowd: &Crowd) {
    let _ = writeln!(out, "crowd{}", if crowd.stay_on_arrival { " stay" } else { "" });
    for a in &crowd.agents {
        let s = a.start;
        let name: String =
            a.name.chars().map(|c| if c.is_whitespace() || c.is_control() || c == '#' { '_' } else { c }).collect();
        let name = if name.is_empty() { String::new() } else { format!(" {name}") };
        let _ = writeln!(out, "agent {} {} {} {} {}{name}", s.position.x, s.position.y, s.yaw, a.radius_m, a.speed_mps);
        for g in &a.goals {
            let lead = match g.kind {
                GoalKind::SeekPoint(p) | GoalKind::FleePoint(p) | GoalKind::Flow(p) => format!(" {} {}", p.x, p.y),
                GoalKind::SeekAgent(j) | GoalKind::FleeAgent(j) => format!(" {}", j + 1),
                GoalKind::SeekRegion { target, min, max } => {
                    format!(" {} {} {} {} {} {}", target.x, target.y, min.x, min.y, max.x, max.y)
                }
                GoalKind::FlowDynamic(k) => format!(" {}", k.name()),
                GoalKind::Idle => String::new(),
            };
            let _ = writeln!(out, "{}{lead} {} {}", g.kind.keyword(), g.desired_speed_mps, g.duration_s);
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::maps::text::{parse, write};
    use crate::scenario::crowd::{FlowKind, GoalKind};
    use glam::DVec2;

    const WORLD: &str = "\
# two agents crossing, a third from a start/goal pair
agent_radius 0.4
crowd stay
agent -5 0 0 0.5 1.2 Alice
seek 5 0 1.3 60
seek_region 6 6 5 5 7 7 1 30
idle 0 2.5
agent 0 -5 1.5707963267948966 0.25 0 Bob
seek_agent 1 1.5 20
flee 0 0 1 5
flow -1 0.5 1 5
flow_dynamic boids 1 5
flee_agent 3 1 5
start 8 8 2.5
goal -8 -8
time_limit 90
box 0 3 1 1
";

    #[test]
    fn crowd_lines_read_every_goal_and_round_trip() {
        let s = parse(WORLD, "c.txt").unwrap();
        let c = s.crowd.as_ref().unwrap();
        assert!(c.stay_on_arrival);
        assert_eq!(c.agents.len(), 3);
        let (a, b, t) = (&c.agents[0], &c.agents[1], &c.agents[2]);
        assert_eq!((a.name.as_str(), a.radius_m, a.speed_mps, a.goals.len()), ("Alice", 0.5, 1.2, 3));
        assert_eq!(
            a.goals[1].kind,
            GoalKind::SeekRegion { target: DVec2::new(6.0, 6.0), min: DVec2::splat(5.0), max: DVec2::splat(7.0) }
        );
        assert_eq!((a.goals[2].kind, a.goals[2].duration_s), (GoalKind::Idle, 2.5));
        let kinds: Vec<_> = b.goals.iter().map(|g| g.kind).collect();
        assert_eq!(
            kinds,
            [
                GoalKind::SeekAgent(0),
                GoalKind::FleePoint(DVec2::ZERO),
                GoalKind::Flow(DVec2::new(-1.0, 0.5)),
                GoalKind::FlowDynamic(FlowKind::Boids),
                GoalKind::FleeAgent(2)
            ]
        );
        // The start/goal pair is the third agent: the world's radius, one seek for its time limit.
        assert_eq!((t.radius_m, t.speed_mps, t.start.yaw), (0.4, 0.0, 2.5));
        assert_eq!((t.goals[0].kind, t.goals[0].duration_s), (GoalKind::SeekPoint(DVec2::splat(-8.0)), 90.0));
        // The tasks are the crowd's; the agent radius the smallest.
        assert_eq!(s.tasks.len(), 3);
        assert_eq!((s.tasks[0].goal, s.tasks[0].time_limit_s), (DVec2::new(6.0, 6.0), 92.5));
        assert_eq!(s.tasks[1].goal, DVec2::new(0.0, -5.0), "no static target: its start");
        assert_eq!(s.agent_radius, 0.25);
        let again = parse(&write(&s), "c.txt").unwrap();
        assert_eq!(again.crowd, s.crowd);
        assert_eq!(again.tasks, s.tasks);
        assert_eq!(write(&again), write(&s));
    }

    #[test]
    fn bad_crowd_lines_are_located() {
        let at = |text: &str| {
            let e = parse(text, "c.txt").unwrap_err();
            (e.line, e.col, e.message)
        };
        let (l, c, m) = at("seek 1 1 1 1\n");
        assert_eq!((l, c), (1, 1), "{m}");
        assert!(m.contains("give an `agent` line first"), "{m}");
        let (l, _, m) = at("agent 0 0 0 0.5 0\nseek 1 1 1\n");
        assert!(l == 2 && m.contains("takes 4"), "{m}");
        let (l, c, m) = at("agent 0 0 0 0.5 0\nseek_agent 0 1 1\n");
        assert_eq!((l, c), (2, 12), "{m}");
        let (_, _, m) = at("agent 0 0 0 0.5 0\nflow_dynamic swirl 1 1\n");
        assert!(m.contains("swirl"), "{m}");
        let (l, _, m) = at("crowd\ncrowd\n");
        assert!(l == 2 && m.contains("already"), "{m}");
        let (l, _, m) = at("crowd later\n");
        assert!(l == 1 && m.contains("stay"), "{m}");
        // Validation errors point at the agent: a second agent without a goal, one in a wall.
        let (l, _, m) = at("agent 0 0 0 0.5 0\nseek 1 1 1 1\nagent 3 3 0 0.5 0\n");
        assert!(l == 3 && m.contains("agent 2") && m.contains("no goal"), "{m}");
        let (l, _, m) = at("agent 0 0 0 0.5 0\nseek 1 1 1 1\nagent 3 3 0 0.5 0\nidle 0 1\nbox 3 3.6 1 0.5\n");
        assert!(l == 3 && m.contains("inside the obstacle on line 5"), "{m}");
        let (l, _, m) = at("crowd\nstart 0 0\ngoal 5 5 1\n");
        assert!(l == 3 && m.contains("own radius"), "{m}");
    }
}
