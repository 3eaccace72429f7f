//! Trajectory snapshots: pin a character's behaviour on a map with PNG frames and a text
//! trajectory, so that a change to a rule set, a map or the animation database shows up as a
//! failed check with a picture of what moved.
//!
//! A snapshot runs one episode (the one `strider render` draws for the same map, seed and
//! episode number), draws a top-down frame every [`Settings::every`] steps and a final
//! trajectory frame, and records the character's position, heading and animation interval at
//! every step. Every frame shows the same region: the whole run's when the goldens are written,
//! and the golden's (kept in the trajectory file) when they are checked, so a diff marks what
//! moved rather than a shifted view. [`check`] compares all of it with a golden directory:
//!
//! - `frame_NNNNNN.png` (the step number) and `final.png`: the goldens;
//! - `trajectory.txt`: the golden trajectory ([`trajectory`]);
//! - after a failed check, `NAME.actual.png` and `NAME.diff.png` (changed pixels in red over a
//!   faded copy of the actual frame) beside each differing golden, and
//!   `trajectory.actual.txt` when the trajectories part.
//!
//! With [`Settings::update`] (or `STRIDER_UPDATE_GOLDEN=1` in the environment) the goldens are
//! written instead: the new set in a folder beside the old one, which it then replaces whole
//! ([`crate::files::replace_dir`]: frames left over from a longer earlier run go with it, the
//! folder's other files are kept), so an update cut short leaves the old set as it was. The
//! command
//! `strider snapshot`, the Rhai function `snapshot(map, rules, seed, dir)` of experiment
//! scripts and [`check`] from a user's `cargo test` all end in [`check_episode`].
//!
//! ```no_run
//! use strider::snapshot::{Spec, check};
//! let report = check(&Spec::new("maps/u_trap.rhai").rules("my_rules.rhai"), "tests/snapshots/u_trap").unwrap();
//! assert!(report.passed(), "{report}");
//! ```
//!
//! Determinism: the simulation has no clock, no global random state and no hash-order
//! dependence, and every frame is drawn by tiny-skia's software rasteriser from that frame's
//! state alone. Frames are drawn and compared in parallel, but each is a pure function of its
//! state, so the same strider build and inputs give bit-identical pictures and trajectory files
//! whatever the machine or the number of threads. The default tolerance is therefore exact.
//! (Trigonometric functions come from the platform's math library; a machine whose library
//! rounds a last bit differently could, rarely, steer a run elsewhere.)
//!
//! With [`Settings::side`] (`--side`) the side views `strider render --side` draws are pinned
//! too, as goldens beside the frames: `side.png` (the legs on the ground profile, on a map with
//! terrain) and `upper_side.png` (the upper body among obstacles it can touch); a map with
//! neither, or the disc, has none, and the report says so.

pub mod pixels;
pub mod trajectory;

use std::collections::BTreeSet;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use rayon::prelude::*;
use tiny_skia::Pixmap;

use crate::files::{self, write_atomic};
use crate::geom::Aabb;
use crate::load::{BodyArgs, Failure};
use crate::render::png::render_png;
use crate::render::scene::Scene;
use crate::render::sim_view::{SideViews, scene_of};
use crate::scenario::Scenario;
use crate::sim::{AnimationHandle, Body, LayeredController, Simulation, StepParameters};
use crate::world::{Terrain, World};

pub use pixels::{PixelDiff, Tolerance};
pub use trajectory::{Divergence, Parting, Record, Sample};

/// Name of the golden trajectory in a snapshot directory.
pub const TRAJECTORY_FILE: &str = "trajectory.txt";
/// Name of the actual trajectory written beside it when the two part.
pub const ACTUAL_TRAJECTORY_FILE: &str = "trajectory.actual.txt";
/// Name of the final trajectory frame.
pub const FINAL_FRAME: &str = "final.png";
/// Environment variable that turns every check into an update when set to `1`.
pub const UPDATE_ENV: &str = "STRIDER_UPDATE_GOLDEN";

/// How a snapshot is drawn and compared.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// A frame every this many simulation steps (0: only the final frame); default 20.
    pub every: usize,
    /// Frame size in pixels, `(width, height)`; default 800×800.
    pub size: (u32, u32),
    /// Pin the side views too (`side.png`, `upper_side.png`, where the map has them); default
    /// off.
    pub side: bool,
    /// When frames match; default exact.
    pub tolerance: Tolerance,
    /// Write the goldens instead of comparing; default off (`STRIDER_UPDATE_GOLDEN=1` turns it
    /// on too).
    pub update: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings { every: 20, size: (800, 800), side: false, tolerance: Tolerance::EXACT, update: false }
    }
}

/// A snapshot described the way the command line describes it: files and numbers.
#[derive(Debug, Clone)]
pub struct Spec {
    /// A `.rhai` map, a plain text world, a MovingAI `.map` or `random:KIND`, as for
    /// `strider run`.
    pub map: String,
    /// The MovingAI scenario file (default: MAP.scen).
    pub scen: Option<PathBuf>,
    /// The navigation rules script (default: the built-in rules).
    pub rules: Option<PathBuf>,
    /// Seed of the run (default 1).
    pub seed: u64,
    /// Episode of the run (default 0).
    pub episode: usize,
    /// The character's body (default: the animated character with the built-in database).
    pub body: BodyArgs,
    /// Drawing and comparison.
    pub settings: Settings,
}

impl Spec {
    /// Episode 0 of `map` with seed 1, the built-in rules, the animated character and the
    /// default [`Settings`].
    pub fn new(map: impl Into<String>) -> Spec {
        Spec {
            map: map.into(),
            scen: None,
            rules: None,
            seed: 1,
            episode: 0,
            body: BodyArgs::default(),
            settings: Settings::default(),
        }
    }

    /// The navigation rules script.
    pub fn rules(mut self, path: impl Into<PathBuf>) -> Spec {
        self.rules = Some(path.into());
        self
    }

    /// The seed of the run.
    pub fn seed(mut self, seed: u64) -> Spec {
        self.seed = seed;
        self
    }

    /// The episode of the run.
    pub fn episode(mut self, episode: usize) -> Spec {
        self.episode = episode;
        self
    }

    /// Drawing and comparison settings.
    pub fn settings(mut self, settings: Settings) -> Spec {
        self.settings = settings;
        self
    }
}

/// One episode ready to run: what [`check_episode`] needs.
#[derive(Debug, Clone)]
pub struct Episode {
    /// The scenario.
    pub scenario: Arc<Scenario>,
    /// Its task to run.
    pub task: usize,
    /// The episode's seed (written in the trajectory header).
    pub seed: u64,
    /// The navigation controller.
    pub controller: LayeredController,
    /// Simulation parameters (the body among them).
    pub params: StepParameters,
}

impl Episode {
    /// Task `task` of `scenario` with `controller`, driving the animated character of
    /// `animation` (the disc when `None`); the body radius is the scenario's.
    pub fn new(
        scenario: Arc<Scenario>,
        task: usize,
        seed: u64,
        controller: LayeredController,
        animation: Option<AnimationHandle>,
    ) -> Episode {
        let mut params = StepParameters { animation, ..StepParameters::default() };
        params.limits.radius = scenario.agent_radius;
        Episode { scenario, task, seed, controller, params }
    }
}

/// Why a snapshot could not be taken or compared (a mismatch is not an error: see
/// [`Report::passed`]).
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A map, rules script, database or policy could not be loaded.
    #[error("{0:#}")]
    Input(anyhow::Error),
    /// The golden directory holds no snapshot.
    #[error(
        "no snapshot goldens in {} ({TRAJECTORY_FILE} is missing): create them by running the snapshot once with --update (or with {UPDATE_ENV}=1), then look at the pictures before committing them",
        dir.display()
    )]
    MissingGoldens {
        /// The golden directory.
        dir: PathBuf,
    },
    /// A file could not be read, decoded or written.
    #[error("{}: {message}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl From<Failure> for Error {
    fn from(f: Failure) -> Self {
        match f {
            Failure::Input(e) | Failure::Task(e) => Error::Input(e),
        }
    }
}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error::Input(e.into())
    }
}

fn file_error(path: &Path, message: impl fmt::Display) -> Error {
    Error::File { path: path.to_path_buf(), message: message.to_string() }
}

/// How one frame compares with its golden.
#[derive(Debug, Clone, PartialEq)]
pub enum FrameStatus {
    /// Equal within the tolerance (the difference says how close).
    Matches(PixelDiff),
    /// More pixels changed than the tolerance allows.
    Differs(PixelDiff),
    /// The frame and the golden have different sizes, `(width, height)`.
    SizeDiffers {
        /// The golden's size.
        golden: (u32, u32),
        /// This frame's size.
        actual: (u32, u32),
    },
    /// This run drew a frame the goldens do not have (it ran longer).
    NoGolden,
    /// The goldens have a frame this run did not draw (it ended sooner).
    NotDrawn,
    /// The golden was written (update).
    Written,
}

/// One frame of a snapshot.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameResult {
    /// File name of the golden (`frame_000020.png`, `final.png`).
    pub name: String,
    /// How it compares.
    pub status: FrameStatus,
    /// The actual frame, written beside the golden when it differs.
    pub actual_file: Option<PathBuf>,
    /// The diff picture, written beside the golden when it differs.
    pub diff_file: Option<PathBuf>,
}

impl FrameResult {
    /// True when the frame matches its golden (or the golden was just written).
    pub fn matches(&self) -> bool {
        matches!(self.status, FrameStatus::Matches(_) | FrameStatus::Written)
    }
}

impl fmt::Display for FrameResult {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.name)?;
        match &self.status {
            FrameStatus::Written => write!(f, "written")?,
            FrameStatus::Matches(d) if d.changed == 0 => write!(f, "matches")?,
            FrameStatus::Matches(d) => write!(
                f,
                "matches within the tolerance ({} pixels changed, largest difference {})",
                d.changed, d.largest
            )?,
            FrameStatus::Differs(d) => {
                write!(
                    f,
                    "{} of {} pixels changed ({:.3} %), largest difference {}",
                    d.changed,
                    d.total(),
                    100.0 * d.changed_share(),
                    d.largest
                )?;
                if let Some((x, y)) = d.largest_at {
                    write!(f, " at ({x}, {y})")?;
                }
                if let Some((x0, y0, x1, y1)) = d.changed_box {
                    write!(f, ", changes within x {x0}–{x1}, y {y0}–{y1}")?;
                }
            }
            FrameStatus::SizeDiffers { golden, actual } => {
                write!(f, "the frame is {}x{}, the golden {}x{}", actual.0, actual.1, golden.0, golden.1)?
            }
            FrameStatus::NoGolden => write!(f, "no golden (this run drew more frames)")?,
            FrameStatus::NotDrawn if SIDE_PICTURES.contains(&self.name.as_str()) => {
                write!(f, "not drawn (a side view: the goldens were written with --side)")?
            }
            FrameStatus::NotDrawn => write!(f, "not drawn (this run ended before this frame)")?,
        }
        let files: Vec<String> =
            [&self.actual_file, &self.diff_file].into_iter().flatten().map(|p| p.display().to_string()).collect();
        if !files.is_empty() {
            write!(f, " → {}", files.join(", "))?;
        }
        Ok(())
    }
}

/// The result of a snapshot check (or update).
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// The golden directory.
    pub dir: PathBuf,
    /// True when the goldens were written rather than compared.
    pub updated: bool,
    /// Every frame in step order, the final frame last (frames without a golden included).
    pub frames: Vec<FrameResult>,
    /// Where this run's trajectory leaves the golden one, if it does.
    pub divergence: Option<Divergence>,
    /// Things worth knowing that are not failures (for example about `--side`).
    pub notes: Vec<String>,
    /// Stale files removed from the directory by an update.
    pub removed: usize,
    /// The run reached its goal.
    pub reached: bool,
    /// Simulated time of the run, seconds.
    pub time_s: f64,
    /// Path length of the run, metres.
    pub path_length_m: f64,
}

impl Report {
    /// True when every frame matches its golden within the tolerance.
    pub fn passed(&self) -> bool {
        self.frames.iter().all(FrameResult::matches)
    }

    /// The frames that do not match.
    pub fn failures(&self) -> impl Iterator<Item = &FrameResult> {
        self.frames.iter().filter(|f| !f.matches())
    }

    /// One line: what was done and how it went.
    pub fn summary(&self) -> String {
        let dir = self.dir.display();
        let run = format!(
            "{} after {:.2} s, path {:.2} m",
            if self.reached { "goal reached" } else { "goal not reached" },
            self.time_s,
            self.path_length_m
        );
        if self.updated {
            let removed = match self.removed {
                0 => String::new(),
                n => format!(", {n} stale file(s) removed"),
            };
            return format!(
                "wrote {} golden frame(s) and {TRAJECTORY_FILE} to {dir} ({run}{removed})",
                self.frames.len()
            );
        }
        let failed = self.failures().count();
        if failed == 0 {
            format!("all {} frame(s) match the goldens in {dir} ({run})", self.frames.len())
        } else {
            format!("{failed} of {} frame(s) differ from the goldens in {dir} ({run})", self.frames.len())
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for n in &self.notes {
            writeln!(f, "note: {n}")?;
        }
        // Frames one run has and the other lacks come in runs: one line per run.
        for group in self
            .frames
            .chunk_by(|a, b| a.status == b.status && matches!(a.status, FrameStatus::NoGolden | FrameStatus::NotDrawn))
        {
            match group {
                [one] => {
                    if !matches!(one.status, FrameStatus::Written | FrameStatus::Matches(PixelDiff { changed: 0, .. }))
                    {
                        writeln!(f, "{one}")?;
                    }
                }
                [first, .., last] => {
                    write!(f, "{} … {} ({} frames): ", first.name, last.name, group.len())?;
                    if first.status == FrameStatus::NoGolden {
                        writeln!(f, "no golden (this run drew more frames); their .actual.png pictures are written")?;
                    } else {
                        writeln!(f, "not drawn (this run ended before these frames)")?;
                    }
                }
                [] => {}
            }
        }
        if let Some(d) = &self.divergence {
            writeln!(f, "{d} → {}", self.dir.join(ACTUAL_TRAJECTORY_FILE).display())?;
        }
        write!(f, "{}", self.summary())
    }
}

/// True when `STRIDER_UPDATE_GOLDEN=1` asks for goldens to be written.
pub fn update_requested() -> bool {
    std::env::var(UPDATE_ENV).is_ok_and(|v| v == "1")
}

/// Loads the episode a [`Spec`] describes (map, rules, body; the episode numbered as in
/// `strider run`). Errors name the file at fault.
pub fn load(spec: &Spec) -> Result<Episode, Error> {
    use crate::load::{MapSpec, job, load_animation, load_map, load_rules};
    let map = MapSpec::parse(Some(&spec.map)).map_err(|e| Error::Input(e.into()))?.with_scen(spec.scen.clone());
    let source = load_map(&map).logged().map_err(|e| Error::Input(e.into()))?;
    let controller = load_rules(spec.rules.as_deref()).logged().map_err(|e| Error::Input(e.into()))?;
    let job = job(&source, spec.episode, spec.seed);
    let animation = load_animation(&spec.body)?;
    Ok(Episode::new(job.scenario, job.task, job.seed, controller, animation))
}

/// Runs the snapshot `spec` describes and compares it with the goldens in `dir` (or writes
/// them: [`Settings::update`], `STRIDER_UPDATE_GOLDEN=1`).
pub fn check(spec: &Spec, dir: impl AsRef<Path>) -> Result<Report, Error> {
    check_episode(&load(spec)?, &spec.settings, dir.as_ref())
}

/// What one run of the episode looks like: its frames, side views and trajectory.
struct Recording<'w> {
    frames: Vec<(String, Scene<'w>)>,
    pictures: Vec<(String, Pixmap)>,
    samples: Vec<Sample>,
    reached: bool,
    time_s: f64,
    path_length_m: f64,
}

/// Runs `episode` in `world` (its scenario's world), keeping a scene every `every` steps, the
/// final scene, a sample at every step and, with `side`, the side views.
fn record<'w>(episode: &Episode, world: &'w World, every: usize, side: bool) -> Recording<'w> {
    let mut sim = Simulation::new(world.clone(), episode.params.clone());
    sim.add_agent(episode.scenario.tasks[episode.task], &episode.controller);
    let mut side_views = side.then(|| SideViews::new(&sim));
    let name = &episode.scenario.name;
    let scene = |sim: &Simulation| -> Scene<'w> {
        let caption = format!("{name}  t = {:.2} s", sim.time_s);
        scene_of(sim, Some(caption)).in_world(world)
    };
    let sample = |sim: &Simulation, step: usize| {
        let a = &sim.agents[0];
        let pose = a.body.pose();
        Sample {
            step,
            time_s: sim.time_s,
            position: pose.position,
            heading: pose.yaw,
            interval: a.body.animated().map(|b| b.player().interval()),
        }
    };
    let mut frames = Vec::new();
    let mut samples = Vec::new();
    let mut step = 0usize;
    while !sim.all_done() {
        samples.push(sample(&sim, step));
        if every > 0 && step.is_multiple_of(every) {
            frames.push((format!("frame_{step:06}.png"), scene(&sim)));
        }
        if let Some(v) = &mut side_views {
            v.before_step(&sim, step);
        }
        sim.step();
        step += 1;
        if let Some(v) = &mut side_views {
            v.after_step(&sim);
        }
    }
    samples.push(sample(&sim, step));
    frames.push((FINAL_FRAME.to_string(), scene(&sim)));
    let pictures = side_views.map_or_else(Vec::new, |v| {
        v.pictures(&sim, name, true, false).into_iter().map(|(file, p)| (file.to_string(), p)).collect()
    });
    let a = &sim.agents[0];
    Recording {
        frames,
        pictures,
        samples,
        reached: a.outcome == Some(crate::sim::Outcome::Reached),
        time_s: a.metrics.time_s,
        path_length_m: a.metrics.path_length_m,
    }
}

/// Names of the side views a snapshot may pin ([`Settings::side`]).
pub const SIDE_PICTURES: [&str; 2] = ["side.png", "upper_side.png"];

/// True for the names of golden frames (`frame_*.png`, `final.png`, the side views), not of
/// actual or diff pictures.
fn is_golden_frame(name: &str) -> bool {
    name.ends_with(".png")
        && !name.ends_with(".actual.png")
        && !name.ends_with(".diff.png")
        && (name == FINAL_FRAME || name.starts_with("frame_") || SIDE_PICTURES.contains(&name))
}

/// True for the files of a snapshot directory: golden frames and trajectory, and what a failed
/// check leaves behind.
fn is_snapshot_file(name: &str) -> bool {
    is_golden_frame(name) || name == TRAJECTORY_FILE || is_failure_output(name)
}

/// True for what a failed check leaves behind.
fn is_failure_output(name: &str) -> bool {
    name.ends_with(".actual.png") || name.ends_with(".diff.png") || name == ACTUAL_TRAJECTORY_FILE
}

/// File names in `dir` (sorted), or none if it does not exist.
fn names_in(dir: &Path) -> Result<Vec<String>, Error> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(file_error(dir, format!("cannot list: {e}"))),
    };
    let mut names = Vec::new();
    for e in entries {
        let e = e.map_err(|e| file_error(dir, format!("cannot list: {e}")))?;
        if e.file_type().is_ok_and(|t| t.is_file()) {
            names.push(e.file_name().to_string_lossy().into_owned());
        }
    }
    names.sort();
    Ok(names)
}

fn remove(path: &Path) -> Result<(), Error> {
    std::fs::remove_file(path).map_err(|e| file_error(path, format!("cannot remove: {e}")))
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    write_atomic(path, bytes).map_err(|e| file_error(path, format!("cannot write: {e}")))
}

/// Encodes straight RGBA pixels as PNG. Every row is stored with the "up" filter: about as
/// small as an adaptive choice for these pictures, and several times faster to decode, which
/// is most of the cost of checking a frame.
pub fn encode_png(width: u32, height: u32, rgba: &[u8]) -> Result<Vec<u8>, String> {
    use image::ImageEncoder;
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    let mut out = Vec::new();
    PngEncoder::new_with_quality(&mut out, CompressionType::Default, FilterType::Up)
        .write_image(rgba, width, height, image::ExtendedColorType::Rgba8)
        .map_err(|e| format!("cannot encode PNG: {e}"))?;
    Ok(out)
}

/// Writes `pixmap` to `path` as PNG ([`encode_png`]), atomically.
pub fn write_png(path: &Path, pixmap: &Pixmap) -> Result<(), Error> {
    let png =
        encode_png(pixmap.width(), pixmap.height(), &pixels::straight_rgba(pixmap)).map_err(|e| file_error(path, e))?;
    write(path, &png)
}

/// Reads a PNG as straight RGBA: `(width, height, pixels)`, or `None` when there is no file.
pub fn read_png(path: &Path) -> Result<Option<(u32, u32, Vec<u8>)>, Error> {
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(file_error(path, format!("cannot read: {e}"))),
    };
    let image = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
        .map_err(|e| file_error(path, format!("not a readable PNG: {e}")))?
        .into_rgba8();
    let (w, h) = image.dimensions();
    Ok(Some((w, h, image.into_raw())))
}

/// Compares `actual` with the golden PNG `golden` within `tolerance`. When they differ, writes
/// `STEM.actual.png` and `STEM.diff.png` into `out_dir`, `STEM` being the golden's file stem
/// (only the actual picture when the golden is missing or has another size). The one picture
/// comparison behind every snapshot.
pub fn check_image(
    golden: &Path,
    actual: &Pixmap,
    tolerance: &Tolerance,
    out_dir: &Path,
) -> Result<FrameResult, Error> {
    let name = golden.file_name().map_or_else(|| golden.display().to_string(), |n| n.to_string_lossy().into_owned());
    let stem = golden.file_stem().map_or_else(|| "frame".to_string(), |n| n.to_string_lossy().into_owned());
    let (w, h) = (actual.width(), actual.height());
    let got = pixels::straight_rgba(actual);
    let (status, expected) = match read_png(golden)? {
        None => (FrameStatus::NoGolden, None),
        Some((gw, gh, _)) if (gw, gh) != (w, h) => {
            (FrameStatus::SizeDiffers { golden: (gw, gh), actual: (w, h) }, None)
        }
        Some((_, _, pixels)) => {
            let d = pixels::compare(&pixels, &got, w, h, tolerance.channel);
            if d.within(tolerance) {
                return Ok(FrameResult { name, status: FrameStatus::Matches(d), actual_file: None, diff_file: None });
            }
            (FrameStatus::Differs(d), Some(pixels))
        }
    };
    let actual_file = out_dir.join(format!("{stem}.actual.png"));
    write_png(&actual_file, actual)?;
    // Without a golden of the same size there is nothing to mark changes against.
    let Some(expected) = expected else {
        return Ok(FrameResult { name, status, actual_file: Some(actual_file), diff_file: None });
    };
    let diff_file = out_dir.join(format!("{stem}.diff.png"));
    let diff = pixels::diff_image(&got, &expected, tolerance.channel);
    write(&diff_file, &encode_png(w, h, &diff).map_err(|e| file_error(&diff_file, e))?)?;
    Ok(FrameResult { name, status, actual_file: Some(actual_file), diff_file: Some(diff_file) })
}

fn set_view(frames: &mut [(String, Scene<'_>)], view: Option<Aabb>) {
    for (_, scene) in frames {
        scene.view = view;
    }
}

/// The note `--side` adds to a report when there are no side views to pin: none on `world`,
/// or a body (the disc) that has none.
fn side_note(world: &World, animated: bool) -> Option<String> {
    if !animated {
        return Some("side views: the disc has no legs or upper body to show from the side; none pinned".to_string());
    }
    let flat = matches!(world.terrain, Terrain::Flat);
    (flat && !world.upper_body_matters()).then(|| {
        "side views: the map has no terrain or obstacles the upper body can touch (flat ground, every obstacle a \
         full-height wall); none pinned"
            .to_string()
    })
}

/// Runs `episode` and compares its frames and trajectory with the goldens in `dir`, or writes
/// them when `settings.update` is set or `STRIDER_UPDATE_GOLDEN=1`. Frames are drawn and
/// compared in parallel (on the current rayon pool); the report does not depend on the
/// thread count.
pub fn check_episode(episode: &Episode, settings: &Settings, dir: &Path) -> Result<Report, Error> {
    let tasks = episode.scenario.tasks.len();
    if episode.task >= tasks {
        return Err(Error::Input(anyhow::anyhow!(
            "{}: task {} out of range (the map has {tasks})",
            episode.scenario.name,
            episode.task
        )));
    }
    let update = settings.update || update_requested();
    let world = episode.scenario.world();
    let mut rec = record(episode, &world, settings.every, settings.side);
    // Every frame shows the same region (all of this run's), so that a diff shows what moved
    // rather than a shifted view; a check draws with the golden's region.
    let own_view = rec.frames.iter().map(|(_, s)| s.auto_view()).reduce(|a, b| a.union(&b)).map(trajectory::as_written);
    let (w, h) = settings.size;
    let about = format!(
        "scenario {}, task {}, seed {}, body {}, time step {} s",
        episode.scenario.name,
        episode.task,
        episode.seed,
        if episode.params.animation.is_some() { "animated" } else { "disc" },
        episode.params.dt_s
    );
    let mut report = Report {
        dir: dir.to_path_buf(),
        updated: update,
        frames: Vec::new(),
        divergence: None,
        notes: Vec::new(),
        removed: 0,
        reached: rec.reached,
        time_s: rec.time_s,
        path_length_m: rec.path_length_m,
    };
    if settings.side {
        report.notes.extend(side_note(&world, episode.params.animation.is_some()));
    }
    let existing = names_in(dir)?;
    let drawn: BTreeSet<String> =
        rec.frames.iter().map(|(n, _)| n.clone()).chain(rec.pictures.iter().map(|(n, _)| n.clone())).collect();
    if update {
        set_view(&mut rec.frames, own_view);
        let traj_text = trajectory::to_text(&about, &Record { view: own_view, samples: rec.samples });
        // The new set is written beside the old one and takes its place whole, so that an
        // update cut short leaves the old goldens as they were; the folder's other files
        // come along.
        let ours = |rel: &Path| rel.parent() == Some(Path::new("")) && rel.to_str().is_some_and(is_snapshot_file);
        files::replace_dir(dir, &ours, files::Others::Keep, |new: &Path| {
            report.frames = rec
                .frames
                .par_iter()
                .map(|(name, scene)| {
                    write_png(&new.join(name), &render_png(scene, w, h))?;
                    Ok(FrameResult {
                        name: name.clone(),
                        status: FrameStatus::Written,
                        actual_file: None,
                        diff_file: None,
                    })
                })
                .collect::<Result<_, Error>>()?;
            for (name, pixmap) in &rec.pictures {
                write_png(&new.join(name), pixmap)?;
                report.frames.push(FrameResult {
                    name: name.clone(),
                    status: FrameStatus::Written,
                    actual_file: None,
                    diff_file: None,
                });
            }
            write(&new.join(TRAJECTORY_FILE), traj_text.as_bytes())
        })?;
        let stale = |name: &&String| (is_golden_frame(name) && !drawn.contains(*name)) || is_failure_output(name);
        report.removed = existing.iter().filter(stale).count();
        return Ok(report);
    }
    let traj_path = dir.join(TRAJECTORY_FILE);
    let golden_text = match std::fs::read_to_string(&traj_path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(Error::MissingGoldens { dir: dir.to_path_buf() });
        }
        Err(e) => return Err(file_error(&traj_path, format!("cannot read: {e}"))),
    };
    let golden = trajectory::parse(&golden_text, &traj_path.display().to_string())
        .map_err(|e| Error::Input(anyhow::Error::new(e)))?;
    let view = golden.view.or(own_view);
    set_view(&mut rec.frames, view);
    for name in existing.iter().filter(|n| is_failure_output(n)) {
        remove(&dir.join(name))?;
    }
    let mut frames: Vec<FrameResult> = rec
        .frames
        .par_iter()
        .map(|(name, scene)| check_image(&dir.join(name), &render_png(scene, w, h), &settings.tolerance, dir))
        .collect::<Result<_, Error>>()?;
    for (name, pixmap) in &rec.pictures {
        frames.push(check_image(&dir.join(name), pixmap, &settings.tolerance, dir)?);
    }
    for name in existing.iter().filter(|n| is_golden_frame(n) && !drawn.contains(*n)) {
        frames.push(FrameResult {
            name: name.clone(),
            status: FrameStatus::NotDrawn,
            actual_file: None,
            diff_file: None,
        });
    }
    frames.sort_by(|a, b| (a.name == FINAL_FRAME, &a.name).cmp(&(b.name == FINAL_FRAME, &b.name)));
    report.frames = frames;
    report.divergence = trajectory::first_divergence(&golden.samples, &rec.samples);
    if report.divergence.is_some() {
        let traj_text = trajectory::to_text(&about, &Record { view, samples: rec.samples });
        write(&dir.join(ACTUAL_TRAJECTORY_FILE), traj_text.as_bytes())?;
        if report.passed() {
            report.notes.push("the trajectories part, but every frame matches within the tolerance".to_string());
        }
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn golden_frame_names() {
        assert!(is_golden_frame("frame_000020.png"));
        assert!(is_golden_frame("final.png"));
        assert!(!is_golden_frame("final.actual.png"));
        assert!(!is_golden_frame("frame_000020.diff.png"));
        assert!(!is_golden_frame("notes.png"));
        assert!(!is_golden_frame("trajectory.txt"));
        assert!(is_failure_output("trajectory.actual.txt"));
    }
}
