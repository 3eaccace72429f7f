//! The Rhai API for worlds and tasks (seed 000 Fig 2 environments as scripts; DESIGN.md §1).
//!
//! ```rhai
//! let m = world("corridor");
//! m.agent_radius(0.3);
//! m.start(0.0, 0.0, 0.0);          // x, y (m), heading (deg)
//! m.goal(10.0, 0.0, 0.5);          // x, y, radius (m)
//! m.box(5.0, 1.0, 4.0, 0.2, 0.0);  // centre x, y, width, height (m), yaw (deg)
//! m.cylinder(3.0, -1.0, 0.4);      // centre x, y, radius (m)
//! m.convex([[0, 2], [1, 3], [2, 2]]);
//! m.polygon([[6, -2], [9, -2], [9, 2], [8, 2], [8, -1], [6, -1]]);
//! m.heights(0.0, 0.8);             // vertical extent of the obstacles added after this
//! // Terrain (seed 002 §3.2), painted in order over flat ground at height 0:
//! m.platform_box(12.0, 0.0, 2.0, 2.0, 0.0, 0.3);    // box as above, then its height (m)
//! m.platform_cylinder(15.0, 0.0, 0.3, 0.1);         // centre x, y, radius, height (m)
//! m.platform(0.2, [[0, -3], [1, -3], [1, -2]]);     // height, polygon outline
//! m.hole_box(15.0, 0.0, 2.0, 2.0, 0.0);             // no ground inside (also hole_cylinder, hole)
//! m.slope(18.0, 0.0, 3.0, 2.0, 0.0, 0.0, 0.5);      // box, then z0 at its −x side, z1 at +x
//! m.stairs(21.0, 0.0, 2.0, 2.0, 0.0, 0.5, 0.0, 3);  // box, z0 before, z1 after, treads
//! // The footstep planner of this map's characters (seed 002 §4.2; any subset of the keys):
//! m.footsteps(#{ window_steps: 3, intervals: 13, step_min_m: 0.25, step_max_m: 0.9,
//!                step_init_m: 0.65, max_step_up_m: 0.45, max_step_down_m: 0.5,
//!                max_slope_deg: 30.0, foot_length_m: 0.24 });
//! m
//! ```
//! A crowd (all agents in one episode; see [`crate::scenario::crowd`] for the goals' meaning):
//! ```rhai
//! let m = world("crossing");
//! m.crowd();                              // or m.crowd_stay(): arrived agents stay
//! m.agent(-5.0, 0.0, 0.0, 0.3, 0.0);      // x, y (m), heading (deg), radius (m), speed (m/s)
//! m.seek(5.0, 0.0, 1.3, 60.0);            // x, y, desired speed (m/s), duration (s)
//! m.agent(0.0, -5.0, 90.0, 0.3, 0.0, "bob");  // with a name
//! m.seek_agent(1, 1.3, 20.0);             // agent number (from 1), speed, duration
//! m.flee(0.0, 0.0, 1.0, 5.0);             // also flee_agent(n, …), flow(dx, dy, …),
//! m.seek_region(6.0, 6.0, 5.0, 5.0, 7.0, 7.0, 1.0, 30.0);  // flow_dynamic("boids", …), idle(speed, duration)
//! m
//! ```
//! A world with `crowd()` or an agent is a crowd; its start/goal pairs are agents too, as in
//! the text format ([`CrowdAgent::from_task`]; a goal's radius is unused: an agent arrives
//! within its own).
//!
//! Obstacles at most 0.45 m high (see `heights`) are ground to step onto or over.
//! Each `start` opens a task; the next `goal` closes it. Angles are degrees. The script ends
//! with the world; the core validates it.

use std::cell::RefCell;
use std::rc::Rc;

use glam::DVec2;
use rhai::{Array, Dynamic, EvalAltResult};

use crate::diagnostic::SourceError;
use crate::scenario::crowd::{Crowd, CrowdAgent, FlowKind, Goal, GoalKind};
use crate::scenario::{Scenario, WorldBudget};
use crate::world::obstacle::DEFAULT_Z;
use crate::world::terrain::{FeatureKind, TerrainFeature};
use crate::world::{Obstacle, ObstacleShape, Pose, Task, Terrain};

type Res<T> = Result<T, Box<EvalAltResult>>;

#[derive(Debug, Default)]
struct MapState {
    scenario: Option<Scenario>,
    pending_start: Option<Pose>,
    z: Option<(f64, f64)>,
    time_limit_s: Option<f64>,
    features: Vec<TerrainFeature>,
    budget: WorldBudget,
    /// `crowd()` (`Some(stay)`) was called.
    crowd: Option<bool>,
    /// The crowd's agents in order: given by `agent`, or the index of a start/goal task.
    agents: Vec<Result<CrowdAgent, usize>>,
}

/// A world under construction in a script.
#[derive(Debug, Clone)]
pub struct MapHandle(Rc<RefCell<MapState>>);

fn num(v: &Dynamic, what: &str) -> Res<f64> {
    let x = if let Ok(f) = v.as_float() {
        f
    } else if let Ok(i) = v.as_int() {
        i as f64
    } else {
        return Err(format!("{what} must be a number, found {}", v.type_name()).into());
    };
    if x.is_finite() { Ok(x) } else { Err(format!("{what} must be finite, found {x}").into()) }
}

fn points(list: &Array, what: &str) -> Res<Vec<DVec2>> {
    list.iter()
        .enumerate()
        .map(|(i, p)| {
            let pair =
                p.clone().try_cast::<Array>().filter(|a| a.len() == 2).ok_or_else(|| -> Box<EvalAltResult> {
                    format!("{what}: point {} must be [x, y]", i + 1).into()
                })?;
            Ok(DVec2::new(num(&pair[0], "x")?, num(&pair[1], "y")?))
        })
        .collect()
}

impl MapHandle {
    fn add(&self, shape: ObstacleShape) -> Res<MapHandle> {
        let mut st = self.0.borrow_mut();
        let (z0, z1) = st.z.unwrap_or(DEFAULT_Z);
        let o = Obstacle::build(shape, z0, z1).map_err(|e| -> Box<EvalAltResult> { e.to_string().into() })?;
        st.budget.obstacle(&o)?;
        if let Some(s) = st.scenario.as_mut() {
            s.obstacles.push(o);
        }
        Ok(self.clone())
    }

    fn feature(&self, shape: ObstacleShape, kind: FeatureKind) -> Res<MapHandle> {
        let f = TerrainFeature::new(shape, kind).map_err(|e| -> Box<EvalAltResult> { e.to_string().into() })?;
        let mut st = self.0.borrow_mut();
        st.budget.feature(&f)?;
        st.features.push(f);
        Ok(self.clone())
    }
}

fn box_shape(x: &Dynamic, y: &Dynamic, w: &Dynamic, h: &Dynamic, yaw_deg: &Dynamic) -> Res<ObstacleShape> {
    Ok(ObstacleShape::Box {
        center: DVec2::new(num(x, "x")?, num(y, "y")?),
        width: num(w, "width")?,
        height: num(h, "height")?,
        yaw: num(yaw_deg, "yaw")?.to_radians(),
    })
}

fn cylinder(x: &Dynamic, y: &Dynamic, r: &Dynamic) -> Res<ObstacleShape> {
    Ok(ObstacleShape::Cylinder { center: DVec2::new(num(x, "x")?, num(y, "y")?), radius: num(r, "radius")? })
}

/// Sets the footstep planner's parameters of the map's characters from a Rhai object map;
/// unknown keys and invalid values are errors.
fn footsteps(m: &mut MapHandle, fields: rhai::Map) -> Res<MapHandle> {
    let mut st = m.0.borrow_mut();
    let Some(scenario) = st.scenario.as_mut() else { return Ok(m.clone()) };
    let mut p = scenario.footsteps;
    for (key, value) in &fields {
        let v = if let Ok(i) = value.as_int() { i as f64 } else { num(value, key)? };
        p.set(key, v).map_err(|e| -> Box<EvalAltResult> { format!("footsteps: {e}").into() })?;
    }
    p.validate().map_err(|e| -> Box<EvalAltResult> { format!("footsteps: {e}").into() })?;
    scenario.footsteps = p;
    Ok(m.clone())
}

/// Registers the terrain functions (see the [module docs](self)).
fn register_terrain(engine: &mut rhai::Engine) {
    type D = Dynamic;
    engine.register_fn("footsteps", footsteps);
    engine.register_fn("platform", |m: &mut MapHandle, z: D, pts: Array| -> Res<MapHandle> {
        m.feature(
            ObstacleShape::Polygon { outline: points(&pts, "platform")? },
            FeatureKind::Platform { z_m: num(&z, "platform height")? },
        )
    });
    engine.register_fn("platform_box", |m: &mut MapHandle, x: D, y: D, w: D, h: D, yaw: D, z: D| -> Res<MapHandle> {
        m.feature(box_shape(&x, &y, &w, &h, &yaw)?, FeatureKind::Platform { z_m: num(&z, "platform height")? })
    });
    engine.register_fn("platform_cylinder", |m: &mut MapHandle, x: D, y: D, r: D, z: D| -> Res<MapHandle> {
        m.feature(cylinder(&x, &y, &r)?, FeatureKind::Platform { z_m: num(&z, "platform height")? })
    });
    engine.register_fn("hole", |m: &mut MapHandle, pts: Array| -> Res<MapHandle> {
        m.feature(ObstacleShape::Polygon { outline: points(&pts, "hole")? }, FeatureKind::Hole)
    });
    engine.register_fn("hole_box", |m: &mut MapHandle, x: D, y: D, w: D, h: D, yaw: D| -> Res<MapHandle> {
        m.feature(box_shape(&x, &y, &w, &h, &yaw)?, FeatureKind::Hole)
    });
    engine.register_fn("hole_cylinder", |m: &mut MapHandle, x: D, y: D, r: D| -> Res<MapHandle> {
        m.feature(cylinder(&x, &y, &r)?, FeatureKind::Hole)
    });
    engine.register_fn("slope", |m: &mut MapHandle, x: D, y: D, w: D, h: D, yaw: D, z0: D, z1: D| -> Res<MapHandle> {
        m.feature(box_shape(&x, &y, &w, &h, &yaw)?, FeatureKind::Slope { z0_m: num(&z0, "z0")?, z1_m: num(&z1, "z1")? })
    });
    engine.register_fn(
        "stairs",
        |m: &mut MapHandle, x: D, y: D, w: D, h: D, yaw: D, z0: D, z1: D, treads: rhai::INT| -> Res<MapHandle> {
            let treads = usize::try_from(treads).map_err(|_| -> Box<EvalAltResult> {
                format!("stairs need a positive number of treads, found {treads}").into()
            })?;
            m.feature(
                box_shape(&x, &y, &w, &h, &yaw)?,
                FeatureKind::Stairs { z0_m: num(&z0, "z0")?, z1_m: num(&z1, "z1")?, treads },
            )
        },
    );
}

/// Registers the world-building API on `engine`.
pub fn register(engine: &mut rhai::Engine) {
    engine.register_type_with_name::<MapHandle>("World");
    register_terrain(engine);
    engine.register_fn("world", |name: &str| {
        MapHandle(Rc::new(RefCell::new(MapState { scenario: Some(Scenario::new(name)), ..MapState::default() })))
    });
    engine.register_fn("agent_radius", |m: &mut MapHandle, r: Dynamic| -> Res<MapHandle> {
        let r = num(&r, "agent radius")?;
        if r <= 0.0 {
            return Err(format!("agent radius must be positive, found {r}").into());
        }
        if let Some(s) = m.0.borrow_mut().scenario.as_mut() {
            s.agent_radius = r;
        }
        Ok(m.clone())
    });
    engine.register_fn("time_limit", |m: &mut MapHandle, t: Dynamic| -> Res<MapHandle> {
        let t = num(&t, "time limit")?;
        if t <= 0.0 {
            return Err(format!("time limit must be positive, found {t}").into());
        }
        m.0.borrow_mut().time_limit_s = Some(t);
        Ok(m.clone())
    });
    engine.register_fn("heights", |m: &mut MapHandle, z0: Dynamic, z1: Dynamic| -> Res<MapHandle> {
        let (z0, z1) = (num(&z0, "z_min")?, num(&z1, "z_max")?);
        if z0 >= z1 {
            return Err(format!("heights need z_min < z_max, found {z0} and {z1}").into());
        }
        m.0.borrow_mut().z = Some((z0, z1));
        Ok(m.clone())
    });
    engine.register_fn("start", |m: &mut MapHandle, x: Dynamic, y: Dynamic, yaw_deg: Dynamic| -> Res<MapHandle> {
        let pose =
            Pose { position: DVec2::new(num(&x, "x")?, num(&y, "y")?), yaw: num(&yaw_deg, "heading")?.to_radians() };
        let mut st = m.0.borrow_mut();
        if st.pending_start.is_some() {
            return Err("two starts in a row: give the goal of the previous start first".into());
        }
        st.pending_start = Some(pose);
        Ok(m.clone())
    });
    engine.register_fn("goal", |m: &mut MapHandle, x: Dynamic, y: Dynamic, r: Dynamic| -> Res<MapHandle> {
        let goal = DVec2::new(num(&x, "x")?, num(&y, "y")?);
        let radius = num(&r, "goal radius")?;
        let mut st = m.0.borrow_mut();
        let start =
            st.pending_start.take().ok_or_else(|| -> Box<EvalAltResult> { "a goal needs a start before it".into() })?;
        let mut task = Task::new(start, goal);
        task.goal_radius = radius;
        if let Some(t) = st.time_limit_s {
            task.time_limit_s = t;
        }
        if let Some(s) = st.scenario.as_mut() {
            s.tasks.push(task);
            let k = s.tasks.len() - 1;
            st.agents.push(Err(k));
        }
        Ok(m.clone())
    });
    register_crowd(engine);
    engine.register_fn(
        "box",
        |m: &mut MapHandle, x: Dynamic, y: Dynamic, w: Dynamic, h: Dynamic, yaw_deg: Dynamic| -> Res<MapHandle> {
            m.add(ObstacleShape::Box {
                center: DVec2::new(num(&x, "x")?, num(&y, "y")?),
                width: num(&w, "width")?,
                height: num(&h, "height")?,
                yaw: num(&yaw_deg, "yaw")?.to_radians(),
            })
        },
    );
    engine.register_fn("cylinder", |m: &mut MapHandle, x: Dynamic, y: Dynamic, r: Dynamic| -> Res<MapHandle> {
        m.add(ObstacleShape::Cylinder { center: DVec2::new(num(&x, "x")?, num(&y, "y")?), radius: num(&r, "radius")? })
    });
    engine.register_fn("convex", |m: &mut MapHandle, pts: Array| -> Res<MapHandle> {
        m.add(ObstacleShape::Convex { points: points(&pts, "convex")? })
    });
    engine.register_fn("polygon", |m: &mut MapHandle, pts: Array| -> Res<MapHandle> {
        m.add(ObstacleShape::Polygon { outline: points(&pts, "polygon")? })
    });
}

/// Adds a goal to the last agent given.
fn push_goal(m: &MapHandle, kind: GoalKind, speed: &Dynamic, duration: &Dynamic) -> Res<MapHandle> {
    let goal = Goal { kind, desired_speed_mps: num(speed, "desired speed")?, duration_s: num(duration, "duration")? };
    let mut st = m.0.borrow_mut();
    match st.agents.iter_mut().rev().find_map(|a| a.as_mut().ok()) {
        Some(agent) => agent.goals.push(goal),
        None => return Err(format!("`{}` is a goal of an agent: call agent(…) first", goal.kind.keyword()).into()),
    }
    drop(st);
    Ok(m.clone())
}

/// An agent number from 1 as an index.
fn agent_index(n: rhai::INT) -> Res<usize> {
    usize::try_from(n)
        .ok()
        .filter(|&n| n >= 1)
        .map(|n| n - 1)
        .ok_or_else(|| format!("agent numbers start at 1, found {n}").into())
}

/// Registers the crowd functions (see the [module docs](self)).
fn register_crowd(engine: &mut rhai::Engine) {
    type D = Dynamic;
    engine.register_fn("crowd", |m: &mut MapHandle| {
        m.0.borrow_mut().crowd = Some(false);
        m.clone()
    });
    engine.register_fn("crowd_stay", |m: &mut MapHandle| {
        m.0.borrow_mut().crowd = Some(true);
        m.clone()
    });
    fn agent(m: &mut MapHandle, x: D, y: D, heading: D, radius: D, speed: D, name: &str) -> Res<MapHandle> {
        let a = CrowdAgent {
            name: name.to_string(),
            start: Pose {
                position: DVec2::new(num(&x, "x")?, num(&y, "y")?),
                yaw: num(&heading, "heading")?.to_radians(),
            },
            radius_m: num(&radius, "radius")?,
            speed_mps: num(&speed, "speed")?,
            goals: Vec::new(),
        };
        m.0.borrow_mut().agents.push(Ok(a));
        Ok(m.clone())
    }
    engine.register_fn("agent", |m: &mut MapHandle, x: D, y: D, h: D, r: D, v: D| agent(m, x, y, h, r, v, ""));
    engine.register_fn("agent", agent);
    engine.register_fn("seek", |m: &mut MapHandle, x: D, y: D, v: D, t: D| -> Res<MapHandle> {
        push_goal(m, GoalKind::SeekPoint(DVec2::new(num(&x, "x")?, num(&y, "y")?)), &v, &t)
    });
    engine.register_fn("flee", |m: &mut MapHandle, x: D, y: D, v: D, t: D| -> Res<MapHandle> {
        push_goal(m, GoalKind::FleePoint(DVec2::new(num(&x, "x")?, num(&y, "y")?)), &v, &t)
    });
    engine.register_fn("flow", |m: &mut MapHandle, x: D, y: D, v: D, t: D| -> Res<MapHandle> {
        push_goal(m, GoalKind::Flow(DVec2::new(num(&x, "dx")?, num(&y, "dy")?)), &v, &t)
    });
    engine.register_fn("seek_agent", |m: &mut MapHandle, n: rhai::INT, v: D, t: D| -> Res<MapHandle> {
        push_goal(m, GoalKind::SeekAgent(agent_index(n)?), &v, &t)
    });
    engine.register_fn("flee_agent", |m: &mut MapHandle, n: rhai::INT, v: D, t: D| -> Res<MapHandle> {
        push_goal(m, GoalKind::FleeAgent(agent_index(n)?), &v, &t)
    });
    engine.register_fn(
        "seek_region",
        |m: &mut MapHandle, x: D, y: D, x0: D, y0: D, x1: D, y1: D, v: D, t: D| -> Res<MapHandle> {
            let kind = GoalKind::SeekRegion {
                target: DVec2::new(num(&x, "x")?, num(&y, "y")?),
                min: DVec2::new(num(&x0, "xmin")?, num(&y0, "ymin")?),
                max: DVec2::new(num(&x1, "xmax")?, num(&y1, "ymax")?),
            };
            push_goal(m, kind, &v, &t)
        },
    );
    engine.register_fn("flow_dynamic", |m: &mut MapHandle, kind: &str, v: D, t: D| -> Res<MapHandle> {
        let k = FlowKind::parse(kind).ok_or_else(|| -> Box<EvalAltResult> {
            format!("flow kind `{kind}`: expected follow_crowd, boids, advect or other").into()
        })?;
        push_goal(m, GoalKind::FlowDynamic(k), &v, &t)
    });
    engine.register_fn("idle", |m: &mut MapHandle, v: D, t: D| push_goal(m, GoalKind::Idle, &v, &t));
}

impl MapHandle {
    /// The validated scenario of a finished map script; errors name `file`.
    pub fn scenario(&self, file: &str) -> Result<Scenario, SourceError> {
        let mut st = self.0.borrow_mut();
        if st.pending_start.is_some() {
            return Err(SourceError::new(file, 0, 0, "the last start has no goal"));
        }
        let mut scenario = st.scenario.take().unwrap_or_else(|| Scenario::new(file));
        scenario.terrain = Terrain::from_features(std::mem::take(&mut st.features));
        let agents = std::mem::take(&mut st.agents);
        if st.crowd.is_some() || agents.iter().any(Result::is_ok) {
            let agents = agents
                .into_iter()
                .map(|a| a.unwrap_or_else(|k| CrowdAgent::from_task(&scenario.tasks[k], scenario.agent_radius)))
                .collect();
            scenario.set_crowd(Crowd { agents, stay_on_arrival: st.crowd == Some(true) });
        }
        scenario.validate().map_err(|m| SourceError::new(file, 0, 0, m))?;
        Ok(scenario)
    }
}

#[cfg(test)]
mod tests {
    use crate::maps::text;
    use crate::scenario::crowd::{FlowKind, GoalKind};
    use crate::script::{Limits, ScriptLog, load_scenario};
    use glam::DVec2;

    #[test]
    fn a_script_builds_a_crowd_that_the_text_format_keeps() {
        let src = r#"
            let m = world("crowd");
            m.agent_radius(0.4);
            m.crowd_stay();
            m.agent(-5.0, 0.0, 90.0, 0.3, 0.5, "alice");
            m.seek(5.0, 0.0, 1.3, 60.0);
            m.seek_region(6.0, 6.0, 5.0, 5.0, 7.0, 7.0, 1.0, 30.0);
            m.idle(0, 2);
            m.start(0.0, -5.0, 0.0);
            m.goal(0.0, 5.0, 0.5);
            m.agent(3.0, 3.0, 0.0, 0.25, 0.0);
            m.seek_agent(1, 1.5, 20.0);
            m.flee_agent(2, 1.0, 5.0);
            m.flee(0.0, 0.0, 1.0, 5.0);
            m.flow(1.0, 0.0, 1.0, 5.0);
            m.flow_dynamic("FOLLOW_CROWD", 1.0, 5.0);
            m
        "#;
        let s = load_scenario(src, "c.rhai", Limits::default(), &ScriptLog::new()).unwrap();
        let c = s.crowd.as_ref().unwrap();
        assert!(c.stay_on_arrival);
        assert_eq!(c.agents.len(), 3);
        assert_eq!(c.agents[0].name, "alice");
        assert!((c.agents[0].start.yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "degrees");
        assert_eq!((c.agents[1].radius_m, c.agents[1].goals[0].kind), (0.4, GoalKind::SeekPoint(DVec2::new(0.0, 5.0))));
        let kinds: Vec<_> = c.agents[2].goals.iter().map(|g| g.kind).collect();
        assert_eq!(kinds[..2], [GoalKind::SeekAgent(0), GoalKind::FleeAgent(1)]);
        assert_eq!(kinds[4], GoalKind::FlowDynamic(FlowKind::FollowCrowd));
        assert_eq!(s.tasks.len(), 3);
        let again = text::parse(&text::write(&s), "c.txt").unwrap();
        assert_eq!(again.crowd, s.crowd);
        // Goals need an agent before them; agent numbers start at 1; the crowd is validated.
        for (bad, says) in [
            ("let m = world(\"w\"); m.seek(1, 1, 1, 1); m", "agent(…) first"),
            ("let m = world(\"w\"); m.agent(0, 0, 0, 0.3, 0); m.seek_agent(0, 1, 1); m", "start at 1"),
            ("let m = world(\"w\"); m.agent(0, 0, 0, 0.3, 0); m", "no goal"),
        ] {
            let e = load_scenario(bad, "b.rhai", Limits::default(), &ScriptLog::new()).unwrap_err();
            assert!(e.message.contains(says), "{e}");
        }
    }
}
