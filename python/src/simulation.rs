//! `strider.Simulation`: one episode of a run, stepped from Python, its agents' state read as
//! NumPy arrays and its top-down view as an RGB array. Episode `i` of a simulation is episode
//! `i` of `strider.run` on the same arguments, step for step.

use glam::DVec2;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

use strider::cli::run::PreparedRun;
use strider::render::png::render_png;
use strider::render::sim_view::scene_of;
use strider::sim::{self, Body, Command, Outcome};

use crate::{StriderError, error, run_args};

/// Most steps one `step` call may take.
const MAX_STEPS: u64 = 100_000_000;

/// Steps between two checks for Ctrl-C.
const STEPS_PER_SLICE: u64 = 200;

/// Most pixels along one side of `frame`.
const MAX_FRAME_SIDE: u32 = 4096;

/// One episode of a navigation run, stepped at the run's fixed time step.
#[pyclass(module = "strider._strider")]
pub struct Simulation {
    run: PreparedRun,
    sim: sim::Simulation,
    episode: usize,
    seed: u64,
    scratch: Vec<usize>,
}

/// The simulation of episode `episode` of `run` seeded with `seed`, as `strider run` sets it up.
fn episode_simulation(run: &PreparedRun, episode: usize, seed: u64) -> sim::Simulation {
    let job = strider::load::job(&run.source, episode, seed);
    let mut params = run.params.clone();
    params.limits.radius = job.scenario.agent_radius;
    let mut s = sim::Simulation::new(job.scenario.world(), params);
    s.add_agent(job.scenario.tasks[job.task], &run.controller);
    s
}

impl Simulation {
    fn agent(&self, agent: usize) -> PyResult<&sim::Agent> {
        self.sim.agents.get(agent).ok_or_else(|| {
            StriderError::new_err(format!("agent {agent} does not exist ({} agents)", self.sim.agents.len()))
        })
    }

    fn agent_mut(&mut self, agent: usize) -> PyResult<&mut sim::Agent> {
        let n = self.sim.agents.len();
        self.sim
            .agents
            .get_mut(agent)
            .ok_or_else(|| StriderError::new_err(format!("agent {agent} does not exist ({n} agents)")))
    }

    fn per_agent<'py>(&self, py: Python<'py>, f: impl Fn(&sim::Agent) -> f64) -> Bound<'py, PyArray1<f64>> {
        Array1::from_iter(self.sim.agents.iter().map(f)).into_pyarray(py)
    }

    fn per_agent_2<'py>(&self, py: Python<'py>, f: impl Fn(&sim::Agent) -> DVec2) -> Bound<'py, PyArray2<f64>> {
        let mut a = Array2::zeros((self.sim.agents.len(), 2));
        for (i, agent) in self.sim.agents.iter().enumerate() {
            let p = f(agent);
            a[[i, 0]] = p.x;
            a[[i, 1]] = p.y;
        }
        a.into_pyarray(py)
    }
}

#[pymethods]
impl Simulation {
    /// Sets up episode `episode` of a run of `map` (as `strider.run` with the same arguments
    /// would run it).
    #[new]
    #[pyo3(signature = (map, *, body="animated", seed=1, rules=None, scen=None, episode=0))]
    fn new(
        py: Python<'_>,
        map: PathBuf,
        body: &str,
        seed: u64,
        rules: Option<PathBuf>,
        scen: Option<PathBuf>,
        episode: usize,
    ) -> PyResult<Self> {
        let args = run_args(&map.to_string_lossy(), None, body, seed, rules, scen, None, None)?;
        let run = py.detach(|| PreparedRun::new(&args)).map_err(error(py))?;
        let sim = py.detach(|| episode_simulation(&run, episode, seed));
        Ok(Simulation { run, sim, episode, seed, scratch: Vec::new() })
    }

    /// Starts episode `episode` (default: the current one) of the run seeded with `seed`
    /// (default: the current seed) afresh, reusing the loaded map, rules and body.
    #[pyo3(signature = (*, episode=None, seed=None))]
    fn reset(&mut self, py: Python<'_>, episode: Option<usize>, seed: Option<u64>) {
        self.episode = episode.unwrap_or(self.episode);
        self.seed = seed.unwrap_or(self.seed);
        let (run, episode, seed) = (&self.run, self.episode, self.seed);
        self.sim = py.detach(|| episode_simulation(run, episode, seed));
    }

    /// Advances the simulation by up to `n` time steps (fewer when every agent is done) and
    /// returns `done`. Releases the GIL; Ctrl-C stops it between steps.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<bool> {
        if n > MAX_STEPS {
            return Err(StriderError::new_err(format!("n must be at most {MAX_STEPS}, found {n}")));
        }
        // Steps go in slices with the GIL released, Ctrl-C checked between them.
        let mut left = n;
        while left > 0 && !self.sim.all_done() {
            let slice = left.min(STEPS_PER_SLICE);
            let sim = &mut self.sim;
            py.detach(|| {
                for _ in 0..slice {
                    if sim.all_done() {
                        break;
                    }
                    sim.step();
                }
            });
            left -= slice;
            py.check_signals()?;
        }
        Ok(self.sim.all_done())
    }

    /// True when every agent has reached its goal or run out of time.
    #[getter]
    fn done(&self) -> bool {
        self.sim.all_done()
    }

    /// Simulated time, seconds.
    #[getter]
    fn time_s(&self) -> f64 {
        self.sim.time_s
    }

    /// The time step, seconds.
    #[getter]
    fn dt_s(&self) -> f64 {
        self.sim.params.dt_s
    }

    /// The episode being simulated.
    #[getter]
    fn episode(&self) -> usize {
        self.episode
    }

    /// The run's seed.
    #[getter]
    fn seed(&self) -> u64 {
        self.seed
    }

    /// The name of the episode's scenario.
    #[getter]
    fn scenario(&self) -> String {
        strider::load::job(&self.run.source, self.episode, self.seed).scenario.name.clone()
    }

    /// Agent positions, metres: an array of shape (agents, 2).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.per_agent_2(py, |a| a.body.pose().position)
    }

    /// Agent headings, radians counter-clockwise from +X: shape (agents,).
    #[getter]
    fn headings<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.per_agent(py, |a| a.body.pose().yaw)
    }

    /// Agent speeds, m/s: shape (agents,).
    #[getter]
    fn speeds<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.per_agent(py, |a| a.body.speed())
    }

    /// Goal points, metres: shape (agents, 2).
    #[getter]
    fn goals<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.per_agent_2(py, |a| a.task.goal)
    }

    /// Each agent's last all-around scan: the free distance for its disc along rays evenly
    /// spaced from the world's +X axis, metres, shape (agents, rays); (agents, 0) before the
    /// first step.
    #[getter]
    fn scan<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let rays = self.sim.agents.iter().map(|a| a.scan().len()).max().unwrap_or(0);
        let mut a = Array2::from_elem((self.sim.agents.len(), rays), f64::NAN);
        for (i, agent) in self.sim.agents.iter().enumerate() {
            for (k, d) in agent.scan().iter().enumerate() {
                a[[i, k]] = *d;
            }
        }
        a.into_pyarray(py)
    }

    /// How each agent's episode ended: `"reached"`, `"timed_out"`, `"refused"` (the body has
    /// no way round what it cannot pass under or step across) or `None` while it runs.
    #[getter]
    fn outcomes(&self) -> Vec<Option<&'static str>> {
        self.sim
            .agents
            .iter()
            .map(|a| match a.outcome {
                Some(Outcome::Reached) => Some("reached"),
                Some(Outcome::TimedOut) => Some("timed_out"),
                Some(Outcome::Refused) => Some("refused"),
                None => None,
            })
            .collect()
    }

    /// Each agent's running measurements (`time_s`, `path_length_m`, `min_clearance_m`,
    /// `collisions`, `stalls`, `steps`, `boundary_follows`), as in the run's episode record.
    #[getter]
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.sim
            .agents
            .iter()
            .map(|a| {
                let m = a.metrics;
                let d = PyDict::new(py);
                d.set_item("time_s", strider::experiment::on_step(m.time_s, self.sim.params.dt_s))?;
                d.set_item("path_length_m", m.path_length_m)?;
                d.set_item("min_clearance_m", m.min_clearance_m)?;
                d.set_item("collisions", m.collisions)?;
                d.set_item("stalls", m.stalled_steps)?;
                d.set_item("steps", m.steps)?;
                d.set_item("boundary_follows", m.follows)?;
                Ok(d)
            })
            .collect()
    }

    /// Agent `agent`'s task: `start` (x, y), `start_heading` (radians), `goal` (x, y),
    /// `goal_radius` (m), `time_limit_s`.
    #[pyo3(signature = (agent=0))]
    fn task<'py>(&self, py: Python<'py>, agent: usize) -> PyResult<Bound<'py, PyDict>> {
        let t = self.agent(agent)?.task;
        let d = PyDict::new(py);
        d.set_item("start", (t.start.position.x, t.start.position.y))?;
        d.set_item("start_heading", t.start.yaw)?;
        d.set_item("goal", (t.goal.x, t.goal.y))?;
        d.set_item("goal_radius", t.goal_radius)?;
        d.set_item("time_limit_s", t.time_limit_s)?;
        Ok(d)
    }

    /// The agents' limits and sensing: `radius_m`, `max_speed_mps`, `max_turn_rate_rad_s`,
    /// `range_m` (of the range sensor), `dt_s`.
    #[getter]
    fn limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let p = &self.sim.params;
        let d = PyDict::new(py);
        d.set_item("radius_m", p.limits.radius)?;
        d.set_item("max_speed_mps", p.limits.max_speed)?;
        d.set_item("max_turn_rate_rad_s", p.limits.max_turn_rate)?;
        d.set_item("range_m", p.layout.range)?;
        d.set_item("dt_s", p.dt_s)?;
        Ok(d)
    }

    /// Drives agent `agent` by hand: from the next step on it follows this turn rate (rad/s,
    /// positive to the left) and speed (m/s) instead of its fuzzy planner, within its body's
    /// limits, as the live view's manual mode does.
    #[pyo3(signature = (turn_rate, speed, agent=0))]
    fn drive(&mut self, turn_rate: f64, speed: f64, agent: usize) -> PyResult<()> {
        if !(turn_rate.is_finite() && speed.is_finite()) {
            return Err(StriderError::new_err(format!(
                "a command must be finite, found turn rate {turn_rate} and speed {speed}"
            )));
        }
        self.agent_mut(agent)?.manual = Some(Command { turn_rate, speed, toward: None });
        Ok(())
    }

    /// Hands agent `agent` back to its fuzzy planner.
    #[pyo3(signature = (agent=0))]
    fn release(&mut self, agent: usize) -> PyResult<()> {
        self.agent_mut(agent)?.manual = None;
        Ok(())
    }

    /// A fresh range scan of the world's obstacles around agent `agent`, relative to its
    /// heading: `rays` rays evenly spaced from straight ahead counter-clockwise, each the free
    /// distance for the agent's disc (from its centre less its radius), capped at the sensor
    /// range, metres.
    #[pyo3(signature = (rays, agent=0))]
    fn range_scan<'py>(&mut self, py: Python<'py>, rays: usize, agent: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        if !(1..=4096).contains(&rays) {
            return Err(StriderError::new_err(format!("rays must be in 1..=4096, found {rays}")));
        }
        let a = self.agent(agent)?;
        let (pose, radius) = (a.body.pose(), a.body.radius());
        let range = self.sim.params.layout.range;
        let (world, scratch) = (&self.sim.world, &mut self.scratch);
        let out = Array1::from_iter((0..rays).map(|k| {
            let dir = DVec2::from_angle(pose.yaw + std::f64::consts::TAU * k as f64 / rays as f64);
            let hit = world.ray_cast(pose.position, dir, range + radius, scratch).unwrap_or(range + radius);
            (hit - radius).clamp(0.0, range)
        }));
        Ok(out.into_pyarray(py))
    }

    /// The top-down view (obstacles, goals, agents with their trails and sensor sectors) as an
    /// RGB array of shape (height, width, 3), dtype uint8: the picture `strider render` draws.
    #[pyo3(signature = (width=480, height=480))]
    fn frame<'py>(&self, py: Python<'py>, width: u32, height: u32) -> PyResult<Bound<'py, PyArray3<u8>>> {
        if !(1..=MAX_FRAME_SIDE).contains(&width) || !(1..=MAX_FRAME_SIDE).contains(&height) {
            return Err(StriderError::new_err(format!(
                "a frame's sides must be in 1..={MAX_FRAME_SIDE} pixels, found {width}x{height}"
            )));
        }
        let sim = &self.sim;
        let rgb = py.detach(|| {
            let pixmap = render_png(&scene_of(sim, None), width, height);
            let (w, h) = (pixmap.width() as usize, pixmap.height() as usize);
            let mut rgb = Vec::with_capacity(w * h * 3);
            for px in pixmap.data().chunks_exact(4) {
                rgb.extend_from_slice(&px[..3]);
            }
            (rgb, w, h)
        });
        let (data, w, h) = rgb;
        let a = Array3::from_shape_vec((h, w, 3), data).map_err(|e| StriderError::new_err(e.to_string()))?;
        Ok(a.into_pyarray(py))
    }
}
