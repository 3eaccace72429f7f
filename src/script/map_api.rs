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
//! Obstacles at most 0.45 m high (see `heights`) are ground to step onto or over.
//! Each `start` opens a task; the next `goal` closes it. Angles are degrees. The script ends
//! with the world; the core validates it.

use std::cell::RefCell;
use std::rc::Rc;

use glam::DVec2;
use rhai::{Array, Dynamic, EvalAltResult};

use crate::diagnostic::SourceError;
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
        }
        Ok(m.clone())
    });
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

impl MapHandle {
    /// The validated scenario of a finished map script; errors name `file`.
    pub fn scenario(&self, file: &str) -> Result<Scenario, SourceError> {
        let mut st = self.0.borrow_mut();
        if st.pending_start.is_some() {
            return Err(SourceError::new(file, 0, 0, "the last start has no goal"));
        }
        let mut scenario = st.scenario.take().unwrap_or_else(|| Scenario::new(file));
        scenario.terrain = Terrain::from_features(std::mem::take(&mut st.features));
        scenario.validate().map_err(|m| SourceError::new(file, 0, 0, m))?;
        Ok(scenario)
    }
}
