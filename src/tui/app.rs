//! The state of the live view and everything it does in response to time and input
//! (DESIGN.md §6, seed 002 §3.1 for manual driving): fixed-step simulation behind a real-time
//! accumulator, pause / single step / speed, reset and new random worlds, agent selection,
//! manual and autopilot modes, goal setting by mouse, zoom and pan, hot reload and the log.
//!
//! Nothing here touches the terminal: events come in as crossterm values and the screen is
//! drawn by [`super::ui`] from this state, so tests drive an [`App`] directly.
//!
//! Invariants: the simulation always advances by whole steps of `params.dt_s`, in the same
//! order as [`Simulation::step`], so an undisturbed autopilot run is the run `strider run`
//! makes with the same map, rules and seed; how much real time passes only decides *when*
//! the steps happen. A failed reload changes nothing but the log.

use std::collections::VecDeque;
use std::path::PathBuf;

use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers, MouseButton, MouseEvent, MouseEventKind};
use glam::DVec2;
use ratatui::layout::Rect;

use super::canvas::TermCanvas;
use super::source::{self, MapSpec, Watched};
use crate::geom::Aabb;
use crate::maps::kind::{self, WorldKind};
use crate::render::scene::{Scene, ViewTransform};
use crate::render::sim_view::scene_of;
use crate::scenario::Scenario;
use crate::sim::{Body, Command, LayeredController, Outcome, Simulation, StepParameters};
use crate::world::Task;

/// Simulation speeds offered by `+` and `-`, multiples of real time.
pub const SPEEDS: [f64; 9] = [0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0];
/// Index of 1× in [`SPEEDS`].
const REAL_TIME: usize = 3;
/// Most simulated time one call of [`App::advance`] may catch up on, in real seconds; beyond
/// that the simulation falls behind instead of stalling the screen.
const MAX_CATCH_UP_S: f64 = 0.25;
/// Lines kept in the log.
pub const LOG_CAPACITY: usize = 500;
/// How often watched files are checked, seconds of real time.
pub const WATCH_PERIOD_S: f64 = 0.5;
/// Change of the manual forward speed per key press, m/s.
pub const MANUAL_SPEED_STEP: f64 = 0.25;
/// How long one turn key press keeps turning, seconds of simulated time.
pub const MANUAL_TURN_HOLD_S: f64 = 0.3;

/// How the run was started: map, rules and seed.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// The world.
    pub map: MapSpec,
    /// The rule script (`None`: built-in rules).
    pub rules: Option<PathBuf>,
    /// Seed of the run (random worlds).
    pub seed: u64,
    /// Animated character for every agent (`None`: kinematic discs).
    pub animation: Option<crate::sim::AnimationHandle>,
}

/// How important a log line is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogLevel {
    /// Ordinary message or script output.
    Info,
    /// A failed load or action.
    Error,
}

/// One line of the log panel.
#[derive(Debug, Clone, PartialEq)]
pub struct LogLine {
    /// Importance.
    pub level: LogLevel,
    /// Text.
    pub text: String,
}

/// Zoom and pan of the world view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewState {
    /// Region fitted at zoom 1: the whole scenario when the run started, metres.
    pub base: Aabb,
    /// Centre of the view when not following, metres.
    pub center: DVec2,
    /// Magnification over `base` (1 = all of it).
    pub zoom: f64,
    /// Keep the selected agent in the middle.
    pub follow: bool,
}

impl ViewState {
    fn new(base: Aabb) -> ViewState {
        ViewState { base, center: base.center(), zoom: 1.0, follow: false }
    }

    /// The world region to show, metres, centred on `agent` when following.
    pub fn region(&self, agent: Option<DVec2>) -> Aabb {
        let c = match agent {
            Some(p) if self.follow && p.is_finite() => p,
            _ => self.center,
        };
        let half = self.base.size() * 0.5 / self.zoom;
        Aabb::new(c - half, c + half)
    }

    /// Zooms by `factor` keeping world point `fixed` where it is on screen.
    fn zoom_about(&mut self, factor: f64, fixed: DVec2) {
        let z = (self.zoom * factor).clamp(0.25, 64.0);
        let f = z / self.zoom;
        if !self.follow && fixed.is_finite() {
            self.center = fixed + (self.center - fixed) / f;
        }
        self.zoom = z;
    }
}

/// A mouse drag in manual mode: where it started (cell) and the command it gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drag {
    /// Cell where the button went down.
    pub from: (u16, u16),
    /// Cell under the pointer now.
    pub to: (u16, u16),
}

/// Everything the live view knows.
#[derive(Debug)]
pub struct App {
    /// Map, rules and seed of the run.
    pub config: Config,
    /// The scenario the simulation was built from.
    pub scenario: Scenario,
    /// The rules every agent's controller starts from.
    pub controller: LayeredController,
    /// The running simulation (one agent per task of the scenario).
    pub sim: Simulation,
    /// Agent the panels show (and manual mode drives).
    pub selected: usize,
    /// True while the simulation is paused.
    pub paused: bool,
    /// Index into [`SPEEDS`].
    pub speed_index: usize,
    /// True in manual mode: the selected agent follows [`App::manual_command`].
    pub manual: bool,
    /// The user's command in manual mode.
    pub manual_command: Command,
    /// What the autopilot would command for the selected agent in manual mode.
    pub autopilot_command: Command,
    /// The drag being made in manual mode.
    pub drag: Option<Drag>,
    /// Zoom and pan.
    pub view: ViewState,
    /// True while the help overlay is shown.
    pub show_help: bool,
    /// True once the user asked to quit.
    pub quit: bool,
    /// True when the simulation could not keep up with the requested speed lately.
    pub behind: bool,
    /// Log panel lines, oldest first.
    pub log: VecDeque<LogLine>,
    /// Where the world was drawn last (screen area) and with which transform.
    pub canvas_view: Option<(Rect, ViewTransform)>,
    /// The canvas reused from frame to frame.
    pub canvas: TermCanvas,
    accumulator_s: f64,
    watch_clock_s: f64,
    turn_hold_s: f64,
    watch_map: Option<Watched>,
    watch_rules: Option<Watched>,
    scratch: Vec<usize>,
}

/// The simulation of `scenario`: one agent per task, each with its own copy of `controller`,
/// and the parameters `strider run` uses (the scenario's agent radius, the body).
pub fn simulation_of(
    scenario: &Scenario,
    controller: &LayeredController,
    animation: Option<crate::sim::AnimationHandle>,
) -> Simulation {
    let mut params = StepParameters { animation, ..StepParameters::default() };
    params.limits.radius = scenario.agent_radius;
    let mut sim = Simulation::new(scenario.world(), params);
    for task in &scenario.tasks {
        sim.add_agent(*task, controller);
    }
    sim
}

impl App {
    /// Loads the map and rules of `config`; fails with the load error (`file:line:col`).
    pub fn load(config: Config) -> Result<App, String> {
        let rules = source::load_rules(config.rules.as_deref());
        let map = source::load_scenario(&config.map, config.seed);
        let controller = rules.result.map_err(|e| e.to_string())?;
        let scenario = map.result.map_err(|e| e.to_string())?;
        let mut app = App::new(config, scenario, controller);
        for line in rules.log.into_iter().chain(map.log) {
            app.info(line);
        }
        Ok(app)
    }

    /// A view of `scenario` driven by `controller`, paused at time 0.
    pub fn new(config: Config, scenario: Scenario, controller: LayeredController) -> App {
        let sim = simulation_of(&scenario, &controller, config.animation.clone());
        let watch_map = config.map.path().map(Watched::new);
        let watch_rules = config.rules.as_deref().map(Watched::new);
        let mut app = App {
            config,
            scenario,
            controller,
            sim,
            selected: 0,
            paused: false,
            speed_index: REAL_TIME,
            manual: false,
            manual_command: Command::default(),
            autopilot_command: Command::default(),
            drag: None,
            view: ViewState::new(Aabb::around(DVec2::ZERO, 5.0)),
            show_help: false,
            quit: false,
            behind: false,
            log: VecDeque::new(),
            canvas_view: None,
            canvas: TermCanvas::new(0, 0),
            accumulator_s: 0.0,
            watch_clock_s: 0.0,
            turn_hold_s: 0.0,
            watch_map,
            watch_rules,
            scratch: Vec::new(),
        };
        app.fit_view();
        app.info(format!("{}: {} agent(s); press ? for help", app.map_name(), app.sim.agents.len()));
        app
    }

    /// Appends an ordinary line to the log.
    pub fn info(&mut self, text: impl Into<String>) {
        self.push_log(LogLevel::Info, text.into());
    }

    /// Appends an error line to the log.
    pub fn error(&mut self, text: impl Into<String>) {
        self.push_log(LogLevel::Error, text.into());
    }

    fn push_log(&mut self, level: LogLevel, text: String) {
        for line in text.lines() {
            if self.log.len() == LOG_CAPACITY {
                self.log.pop_front();
            }
            self.log.push_back(LogLine { level, text: line.to_string() });
        }
    }

    /// Simulation speed, multiple of real time.
    pub fn speed(&self) -> f64 {
        SPEEDS[self.speed_index]
    }

    /// What the world is called on screen: the scenario's name, or the density of a random
    /// world (its seed is shown beside it).
    pub fn map_name(&self) -> String {
        match self.config.map {
            MapSpec::Random(d) => format!("random {d} world"),
            _ => self.scenario.name.clone(),
        }
    }

    /// The selected agent's position, if there is an agent.
    fn selected_position(&self) -> Option<DVec2> {
        self.sim.agents.get(self.selected).map(|a| a.body.pose().position)
    }

    /// The scene to draw now: the simulation's, with this view's region, the caption and the
    /// selected agent labelled when there are several.
    pub fn scene(&self) -> Scene<'_> {
        let mut scene = scene_of(&self.sim, Some(self.map_name()));
        scene.view = Some(self.view.region(self.selected_position()));
        // The panels explain the picture.
        scene.legend = false;
        if scene.agents.len() > 1
            && let Some(a) = scene.agents.get_mut(self.selected)
        {
            a.label = Some(format!("{}", self.selected + 1));
        }
        scene
    }

    /// Fits the view to the scenario (zoom 1, no pan).
    pub fn fit_view(&mut self) {
        let follow = self.view.follow;
        self.view = ViewState::new(scene_of(&self.sim, None).auto_view());
        self.view.follow = follow;
    }

    /// Lets `real_dt_s` seconds of real time pass: runs as many fixed steps as the speed asks
    /// for (none while paused or when every agent is done), and polls watched files.
    pub fn advance(&mut self, real_dt_s: f64) {
        let real_dt_s = if real_dt_s.is_finite() { real_dt_s.max(0.0) } else { 0.0 };
        self.watch_clock_s += real_dt_s;
        if self.watch_clock_s >= WATCH_PERIOD_S {
            self.watch_clock_s = 0.0;
            self.poll_files();
        }
        if self.paused || self.finished() {
            self.accumulator_s = 0.0;
            self.behind = false;
            return;
        }
        let dt = self.sim.params.dt_s;
        self.accumulator_s += real_dt_s.min(MAX_CATCH_UP_S) * self.speed();
        let max_steps = (MAX_CATCH_UP_S * self.speed() / dt).ceil().max(1.0) as usize;
        let mut steps = 0;
        // A step is due when the accumulator holds a whole step, up to rounding.
        while self.accumulator_s >= dt - 1e-9 && steps < max_steps && !self.finished() {
            self.step();
            self.accumulator_s -= dt;
            steps += 1;
        }
        self.behind = self.accumulator_s >= dt && steps == max_steps;
        if self.behind {
            self.accumulator_s = 0.0;
        }
    }

    /// True when nothing is left to simulate: every agent is done and no agent is driven.
    pub fn finished(&self) -> bool {
        self.sim.all_done() && !(self.manual && self.selected < self.sim.agents.len())
    }

    /// Advances the simulation by exactly one fixed step.
    pub fn step(&mut self) {
        if self.manual && self.selected < self.sim.agents.len() {
            let mut cmd = self.manual_command;
            if self.turn_hold_s <= 0.0 && self.drag.is_none() {
                cmd.turn_rate = 0.0;
            }
            self.turn_hold_s -= self.sim.params.dt_s;
            self.manual_step(cmd);
        } else {
            for a in &mut self.sim.agents {
                a.manual = None;
            }
            self.sim.step();
        }
    }

    /// One step in which the selected agent follows `command` (the simulation's manual
    /// override) and every other agent its controller; the driven agent's controller still
    /// decides, so the panels stay live and show what the autopilot would do.
    fn manual_step(&mut self, command: Command) {
        let i = self.selected;
        for (j, a) in self.sim.agents.iter_mut().enumerate() {
            a.manual = (j == i).then_some(command);
        }
        // A driven agent keeps going after its episode would have ended.
        let before = self.sim.agents[i].outcome.take();
        self.sim.step();
        let agent = &mut self.sim.agents[i];
        self.autopilot_command = agent.autopilot;
        agent.outcome = before.or(agent.outcome.filter(|o| *o == Outcome::Reached));
    }

    /// Starts the run again from the scenario (same rules, same view).
    pub fn reset(&mut self) {
        self.sim = simulation_of(&self.scenario, &self.controller, self.config.animation.clone());
        self.selected = self.selected.min(self.sim.agents.len().saturating_sub(1));
        self.accumulator_s = 0.0;
        self.manual_command = Command::default();
        self.drag = None;
    }

    /// Replaces the scenario (new map) and starts again with a fitted view.
    fn set_scenario(&mut self, scenario: Scenario) {
        self.scenario = scenario;
        self.reset();
        self.selected = 0;
        self.fit_view();
    }

    /// A new random world: the next seed, the kind of the current random world (semi-
    /// cluttered when the map is a file or the built-in scenario).
    pub fn new_random_world(&mut self) {
        let k = match self.config.map {
            MapSpec::Random(k) => k,
            _ => WorldKind::Semi,
        };
        self.config.seed = self.config.seed.wrapping_add(1);
        self.config.map = MapSpec::Random(k);
        let s = kind::generate(k, crate::experiment::world_seed(self.config.seed, 0));
        self.info(format!("new {k} world, seed {}", self.config.seed));
        self.set_scenario(s);
    }

    /// Checks the watched map and rule files and reloads what changed.
    pub fn poll_files(&mut self) {
        if self.watch_rules.as_mut().is_some_and(Watched::changed) {
            self.reload_rules();
        }
        let map_changed = self.watch_map.as_mut().is_some_and(Watched::changed);
        if map_changed {
            self.reload_map();
        }
    }

    /// Reloads the rule script; on success every agent gets the new rules where it stands.
    pub fn reload_rules(&mut self) {
        let loaded = source::load_rules(self.config.rules.as_deref());
        for line in loaded.log {
            self.info(line);
        }
        match loaded.result {
            Ok(c) => {
                for a in &mut self.sim.agents {
                    a.controller = c.clone();
                }
                self.controller = c;
                let name = self.watch_rules.as_ref().map_or("rules".into(), |w| w.path().display().to_string());
                self.info(format!("{name}: reloaded"));
            }
            Err(e) => self.error(format!("{e} (keeping the previous rules)")),
        }
    }

    /// Reloads the map file; on success the run starts again on the new world.
    pub fn reload_map(&mut self) {
        let Some(path) = self.watch_map.as_ref().map(|w| w.path().to_path_buf()) else { return };
        let spec = MapSpec::file(path.clone());
        let loaded = source::load_scenario(&spec, self.config.seed);
        for line in loaded.log {
            self.info(line);
        }
        match loaded.result {
            Ok(s) => {
                self.config.map = spec;
                self.info(format!("{}: reloaded", path.display()));
                self.set_scenario(s);
            }
            Err(e) => self.error(format!("{e} (keeping the previous map)")),
        }
    }

    /// Handles a key press.
    pub fn on_key(&mut self, key: KeyEvent) {
        if key.kind == KeyEventKind::Release {
            return;
        }
        let ctrl = key.modifiers.contains(KeyModifiers::CONTROL);
        let shift = key.modifiers.contains(KeyModifiers::SHIFT);
        match key.code {
            KeyCode::Char('c') if ctrl => self.quit = true,
            KeyCode::Char('q') => self.quit = true,
            KeyCode::Char('?') => self.show_help = !self.show_help,
            KeyCode::Esc => self.show_help = false,
            KeyCode::Char(' ') => self.paused = !self.paused,
            KeyCode::Char('.') => {
                self.paused = true;
                if !self.finished() {
                    self.step();
                }
            }
            KeyCode::Char('+') | KeyCode::Char('=') => self.speed_index = (self.speed_index + 1).min(SPEEDS.len() - 1),
            KeyCode::Char('-') | KeyCode::Char('_') => self.speed_index = self.speed_index.saturating_sub(1),
            KeyCode::Char('r') => {
                self.reset();
                self.info("reset");
            }
            KeyCode::Char('n') => self.new_random_world(),
            KeyCode::Tab | KeyCode::BackTab => {
                let n = self.sim.agents.len().max(1);
                self.selected =
                    if key.code == KeyCode::Tab { (self.selected + 1) % n } else { (self.selected + n - 1) % n };
                self.manual_command = Command::default();
            }
            KeyCode::Char('m') => {
                self.manual = !self.manual;
                self.manual_command = Command::default();
                self.drag = None;
                self.info(if self.manual { "manual: arrows/WASD or drag to drive" } else { "autopilot" });
            }
            KeyCode::Char('z') => self.zoom(1.25),
            KeyCode::Char('x') => self.zoom(0.8),
            KeyCode::Char('0') => {
                self.view.follow = false;
                self.fit_view();
            }
            KeyCode::Char('f') => {
                self.view.follow = !self.view.follow;
                if !self.view.follow
                    && let Some(p) = self.selected_position()
                {
                    self.view.center = p;
                }
            }
            KeyCode::Up | KeyCode::Down | KeyCode::Left | KeyCode::Right if !self.manual || shift => {
                let d = match key.code {
                    KeyCode::Up => DVec2::Y,
                    KeyCode::Down => DVec2::NEG_Y,
                    KeyCode::Left => DVec2::NEG_X,
                    _ => DVec2::X,
                };
                self.pan(d);
            }
            code if self.manual => self.drive_key(code),
            _ => {}
        }
    }

    fn drive_key(&mut self, code: KeyCode) {
        let l = self.sim.params.limits;
        let c = &mut self.manual_command;
        match code {
            KeyCode::Up | KeyCode::Char('w') => c.speed = (c.speed + MANUAL_SPEED_STEP).min(l.max_speed),
            KeyCode::Down | KeyCode::Char('s') => c.speed = (c.speed - MANUAL_SPEED_STEP).max(0.0),
            KeyCode::Left | KeyCode::Char('a') => {
                c.turn_rate = l.max_turn_rate;
                self.turn_hold_s = MANUAL_TURN_HOLD_S;
            }
            KeyCode::Right | KeyCode::Char('d') => {
                c.turn_rate = -l.max_turn_rate;
                self.turn_hold_s = MANUAL_TURN_HOLD_S;
            }
            _ => {}
        }
    }

    /// Zooms about the view centre.
    pub fn zoom(&mut self, factor: f64) {
        let c = self.view.center;
        self.view.zoom_about(factor, c);
    }

    /// Pans by a tenth of the visible region in direction `dir` (world axes).
    pub fn pan(&mut self, dir: DVec2) {
        if let Some(p) = self.selected_position().filter(|_| self.view.follow) {
            self.view.center = p;
        }
        self.view.follow = false;
        let size = self.view.base.size() / self.view.zoom;
        self.view.center += dir * size * 0.1;
    }

    /// The world point under screen cell `(col, row)`, if it is inside the world view.
    pub fn world_at(&self, col: u16, row: u16) -> Option<DVec2> {
        let (area, tf) = self.canvas_view?;
        let inside = col >= area.x && col < area.x + area.width && row >= area.y && row < area.y + area.height;
        inside.then(|| tf.to_world(TermCanvas::cell_center(col - area.x, row - area.y)))
    }

    /// Handles a mouse event: a click sets the selected agent's goal, a drag in manual mode
    /// drives (seed 002 §3.1: up is forward speed, sideways is turn rate), the wheel zooms.
    pub fn on_mouse(&mut self, ev: MouseEvent) {
        let (col, row) = (ev.column, ev.row);
        match ev.kind {
            MouseEventKind::ScrollUp | MouseEventKind::ScrollDown => {
                let f = if ev.kind == MouseEventKind::ScrollUp { 1.25 } else { 0.8 };
                let at = self.world_at(col, row).unwrap_or(self.view.center);
                self.view.zoom_about(f, at);
            }
            MouseEventKind::Down(MouseButton::Left) if self.world_at(col, row).is_some() => {
                self.drag = Some(Drag { from: (col, row), to: (col, row) });
            }
            MouseEventKind::Drag(MouseButton::Left) => {
                if let Some(d) = &mut self.drag {
                    d.to = (col, row);
                    if self.manual {
                        self.manual_command = self.drag_command();
                    }
                }
            }
            MouseEventKind::Up(MouseButton::Left) => {
                if let Some(d) = self.drag.take() {
                    if d.from == d.to {
                        if let Some(p) = self.world_at(col, row) {
                            self.set_goal(p);
                        }
                    } else if self.manual {
                        self.manual_command = Command::default();
                    }
                }
            }
            _ => {}
        }
    }

    /// The command of the current drag: a quarter of the world view's height upward is full
    /// speed, a quarter of its width sideways is the full turn rate (to the right: clockwise).
    pub fn drag_command(&self) -> Command {
        let (Some(d), Some((area, _))) = (self.drag, self.canvas_view) else { return Command::default() };
        let l = self.sim.params.limits;
        // Cells are about twice as tall as wide.
        let dx = f64::from(d.to.0) - f64::from(d.from.0);
        let dy = f64::from(d.from.1) - f64::from(d.to.1);
        let speed = (dy / (f64::from(area.height) / 4.0).max(1.0)).clamp(0.0, 1.0) * l.max_speed;
        let turn = -(dx / (f64::from(area.width) / 4.0).max(1.0)).clamp(-1.0, 1.0) * l.max_turn_rate;
        Command { turn_rate: turn, speed, toward: None }
    }

    /// Moves the selected agent's goal to `p` (metres), if a disc of the agent's size fits
    /// there; the agent's episode goes on toward it.
    pub fn set_goal(&mut self, p: DVec2) {
        let Some(agent) = self.sim.agents.get_mut(self.selected) else { return };
        let r = agent.body.radius();
        if !self.sim.world.is_free(p, r, &mut self.scratch) {
            self.error(format!("({:.1}, {:.1}) is inside an obstacle: goal not moved", p.x, p.y));
            return;
        }
        let fresh = Task::new(agent.body.pose(), p);
        agent.task.goal = p;
        agent.task.time_limit_s = agent.metrics.time_s + fresh.time_limit_s;
        agent.outcome = None;
        agent.controller.reset();
        self.info(format!("goal of agent {} set to ({:.1}, {:.1})", self.selected + 1, p.x, p.y));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn app() -> App {
        App::load(Config { map: MapSpec::BuiltIn, rules: None, seed: 1, animation: None }).unwrap()
    }

    fn key(c: char) -> KeyEvent {
        KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE)
    }

    #[test]
    fn accumulator_runs_whole_steps_at_real_time() {
        let mut a = app();
        a.advance(0.12);
        assert!((a.sim.time_s - 0.10).abs() < 1e-9, "{}", a.sim.time_s);
        a.advance(0.03);
        assert!((a.sim.time_s - 0.15).abs() < 1e-9);
        a.on_key(key(' '));
        a.advance(1.0);
        assert!((a.sim.time_s - 0.15).abs() < 1e-9);
        a.on_key(key('.'));
        assert!((a.sim.time_s - 0.20).abs() < 1e-9);
    }

    #[test]
    fn live_run_matches_headless_run() {
        let mut a = app();
        for _ in 0..40 {
            a.advance(0.37);
        }
        let mut b = simulation_of(&a.scenario, &a.controller, None);
        let steps = (a.sim.time_s / b.params.dt_s).round() as usize;
        for _ in 0..steps {
            b.step();
        }
        assert_eq!(a.sim.agents[0].trail, b.agents[0].trail);
    }

    #[test]
    fn manual_mode_follows_the_user() {
        let mut a = app();
        a.on_key(key('m'));
        let yaw0 = a.sim.agents[0].body.pose().yaw;
        a.on_key(key('w'));
        a.on_key(key('w'));
        for _ in 0..20 {
            a.step();
        }
        let moved = a.sim.agents[0].metrics.path_length_m;
        assert!(moved > 0.3, "moved {moved}");
        assert!((a.sim.agents[0].body.pose().yaw - yaw0).abs() < 1e-12);
        a.on_key(key('a'));
        a.step();
        assert!(a.sim.agents[0].body.pose().yaw > yaw0);
    }

    #[test]
    fn speed_keys_clamp() {
        let mut a = app();
        for _ in 0..20 {
            a.on_key(key('+'));
        }
        assert_eq!(a.speed(), SPEEDS[SPEEDS.len() - 1]);
        for _ in 0..20 {
            a.on_key(key('-'));
        }
        assert_eq!(a.speed(), SPEEDS[0]);
    }

    #[test]
    fn new_world_changes_seed_and_scenario() {
        let mut a = app();
        a.on_key(key('n'));
        assert_eq!(a.config.seed, 2);
        assert_eq!(a.config.map, MapSpec::Random(WorldKind::Semi));
        assert_eq!(a.sim.time_s, 0.0);
    }
}
