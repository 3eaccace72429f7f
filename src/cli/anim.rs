//! `strider db build|info|export` and `strider train` (seed 000 §3.2): animation databases from
//! BVH files, their description, the built-in generated clips, and SARSA training of the
//! interval policy.
//!
//! A database directory holds `database.json` (format, version, parameters, the clip files and
//! the interval list) and the clips as BVH under `clips/` ([`crate::load::load_database`],
//! [`crate::load::save_database`]). Rebuilding from it reproduces the same intervals, so
//! policies trained on it stay valid.

use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use clap::{Args, Subcommand};

use crate::anim::bvh::{self, BvhOptions};
use crate::anim::db::DbError;
use crate::anim::policy::{LearnParams, Policy, StateGrid, Strategy};
use crate::anim::rig;
use crate::anim::{Clip, Database, DbParams, IntervalSpec, Skeleton};
use crate::diagnostic::SourceError;
use crate::files::{self, outln, write_atomic};
use crate::lex::{Tok, tokenize};
use crate::load::{
    BodyArgs, BodyKind, Failure, Outcome, TransitionArg, builtin_database, load_animation, load_database, parse_bvh,
    same_skeleton, write_database,
};

/// `strider db` subcommands.
#[derive(Debug, Subcommand)]
pub enum DbCommand {
    /// Build a database from BVH files into a directory.
    Build(BuildArgs),
    /// Describe a database (the built-in one without DIR).
    Info {
        /// Database directory.
        dir: Option<PathBuf>,
    },
    /// Measure command tracking of the animated character (90° turns, speed changes, path).
    Track {
        /// Database directory (default: built-in).
        dir: Option<PathBuf>,
        /// Trained policy (default: the shipped one for the built-in database).
        #[arg(long)]
        policy: Option<PathBuf>,
        /// How intervals hand over.
        #[arg(long, value_enum, default_value_t = TransitionArg::Crossfade)]
        transition: TransitionArg,
    },
    /// Draw a side-view strip of a clip's frames as a PNG.
    Strip(super::db_strip::StripArgs),
    /// Write the built-in generated clips as a database directory of BVH files.
    Export {
        /// Output directory: new, empty, or a strider database, which is replaced whole.
        #[arg(long)]
        out: PathBuf,
    },
}

/// `strider db build` options.
#[derive(Debug, Args)]
pub struct BuildArgs {
    /// BVH files, one clip each.
    #[arg(long, num_args = 1.., required = true)]
    pub bvh: Vec<PathBuf>,
    /// Output directory: new, empty, or a strider database, which is replaced whole.
    #[arg(long)]
    pub out: PathBuf,
    /// Length unit of the files in metres (CMU files: 0.056444). Without it the unit is read
    /// from the skeleton's leg length (metres, CMU units, inches, centimetres or millimetres).
    #[arg(long)]
    pub scale: Option<f64>,
    /// The two foot joints, left first (`--feet LeftFoot,RightFoot`). Without it they are found
    /// by name (namespace prefixes such as `mixamorig:` ignored), else by the hierarchy's shape.
    #[arg(long, value_delimiter = ',')]
    pub feet: Option<Vec<String>>,
    /// Neighbours per interval (default 6, fewer when the files give too few intervals).
    #[arg(long)]
    pub k: Option<usize>,
    /// Hand-written intervals instead of detected ones: lines `CLIP START END` (frames).
    #[arg(long)]
    pub intervals: Option<PathBuf>,
}

/// `strider train` options.
#[derive(Debug, Args)]
pub struct TrainArgs {
    /// Database directory (default: built-in).
    #[arg(long)]
    pub db: Option<PathBuf>,
    /// Training episodes (rounded up to whole rounds of 64).
    #[arg(long, default_value_t = 3_000_000)]
    pub episodes: u64,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Policy file to write (atomically; checkpoints go to the same file).
    #[arg(long)]
    pub out: PathBuf,
    /// Continue training the policy in `--out` instead of starting afresh.
    #[arg(long)]
    pub resume: bool,
}

/// The lines of `db info` on the moves for tight places, measured from the clips: turns on the
/// spot (and the angles warping reaches), side steps and steps back, the sharpest turn within
/// one stride at walking pace, and the stops that come to rest within one step.
fn tight_places(s: &mut String, db: &Database, w: &crate::anim::warp::WarpLimits) {
    use std::fmt::Write as _;
    let of_clip = |c: usize| db.intervals.iter().enumerate().filter(move |(_, iv)| iv.clip == c).map(|(i, _)| i);
    let degrees = |v: &[f64]| v.iter().map(|d| format!("{d:.0}°")).collect::<Vec<_>>().join(", ");
    let (mut spot, mut aside, mut back) = (Vec::new(), [Vec::new(), Vec::new()], Vec::new());
    let (mut stride_turn, mut quick_stops) = ((0.0f64, String::new()), Vec::new());
    for (c, clip) in db.clips.iter().enumerate() {
        let ivs: Vec<usize> = of_clip(c).collect();
        let Some(&first) = ivs.first() else { continue };
        let turn: f64 = ivs.iter().map(|&i| db.intervals[i].turn()).sum();
        if ivs.iter().all(|&i| db.kinds[i].in_place) && turn.abs() >= crate::anim::db::SPOT_TURN_RAD && turn > 0.0 {
            spot.push(turn.to_degrees());
        }
        let moved = || match (clip.frames.first(), clip.frames.last()) {
            (Some(a), Some(b)) => (b.root - a.root).truncate().length(),
            _ => 0.0,
        };
        match db.kinds[first].shuffle {
            1 => aside[0].push(moved()),
            -1 => aside[1].push(moved()),
            2 => back.push(moved()),
            _ => {}
        }
        // Walking pace: two consecutive steps of a clip that both go at 0.6–2 m/s.
        let walking = |i: usize| db.kinds[i].goes && (0.6..2.0).contains(&db.intervals[i].speed);
        for p in ivs.windows(2) {
            let t = (db.intervals[p[0]].turn() + db.intervals[p[1]].turn()).abs();
            if walking(p[0]) && walking(p[1]) && t > stride_turn.0 + 1e-9 {
                stride_turn = (t, clip.name.clone());
            }
        }
        // From a plant at walking pace to at rest within one step (then settling in place).
        if walking(first) || db.kinds[first].goes && db.intervals[first].speed >= 0.6 {
            let rest = ivs.iter().position(|&i| db.kinds[i].ends_at_rest);
            let steps = rest.map(|r| ivs[..=r].iter().filter(|&&i| !db.kinds[i].in_place).count());
            if steps == Some(1) {
                quick_stops.push(clip.name.clone());
            }
        }
    }
    let (lo, hi) = (spot.iter().copied().fold(f64::INFINITY, f64::min), spot.iter().copied().fold(0.0, f64::max));
    let _ = writeln!(
        s,
        "tight places: turns on the spot {} each way (warped: {:.0}°–{:.0}°); side steps {} left, {} right; steps back {}",
        degrees(&spot),
        lo * w.spot_scale.0,
        hi * w.spot_scale.1,
        aside[0].iter().map(|d| format!("{d:.2} m")).collect::<Vec<_>>().join(", "),
        aside[1].iter().map(|d| format!("{d:.2} m")).collect::<Vec<_>>().join(", "),
        back.iter().map(|d| format!("{d:.2} m")).collect::<Vec<_>>().join(", "),
    );
    let _ = writeln!(
        s,
        "  sharpest turn within one stride at walking pace: {:.0}° ({}; warped up to {:.0}°); stops within one step: {}",
        stride_turn.0.to_degrees(),
        stride_turn.1,
        stride_turn.0.to_degrees() * w.turn_scale.1,
        quick_stops.join(", ")
    );
}

/// The import scale of `db build`: `--scale` when given, else the unit the first file's leg
/// length points to, said on stderr with the feet it was measured to.
fn build_scale(a: &BuildArgs, first: &Path, text: &str) -> Result<f64, Failure> {
    let names = a.feet.clone().unwrap_or_default();
    let file = first.display().to_string();
    let skeleton = bvh::parse(text, &file, "clip", &BvhOptions::default())?.skeleton;
    let Some((feet, from)) = rig::locate_feet(&skeleton, &names) else {
        return Err(anyhow!(
            "{file}: cannot find the foot joints (tried {}); name them with --feet LEFT,RIGHT",
            if names.is_empty() {
                "joint names such as LeftFoot or mixamorig:LeftFoot, then the shape of the hierarchy".to_string()
            } else {
                names.join(", ")
            }
        )
        .into());
    };
    let joint = |i: usize| skeleton.joints()[i].name.as_str();
    let how = match from {
        rig::FeetFrom::Given => "as given",
        rig::FeetFrom::Name => "found by name",
        rig::FeetFrom::Topology => "found from the shape of the hierarchy",
    };
    eprintln!("{file}: feet {} / {} ({how})", joint(feet[0]), joint(feet[1]));
    if let Some(s) = a.scale {
        eprintln!("{file}: lengths × {s} (--scale)");
        return Ok(s);
    }
    let Some(g) = rig::guess_unit(&skeleton, feet) else {
        eprintln!("{file}: warning: the legs have no length; taking metres (give --scale to choose)");
        return Ok(1.0);
    };
    if g.human {
        eprintln!(
            "{file}: lengths in {} (scale {}), read from the leg: {:.4} file units from {} to {}, {:.2} m in that unit; --scale overrides",
            g.unit.name,
            g.unit.metres,
            g.leg_length,
            joint(0),
            joint(feet[0]),
            g.leg_length_m()
        );
    } else {
        eprintln!(
            "{file}: warning: no usual unit makes the leg ({:.4} file units from {} to {}) {:.2}–{:.2} m long; taking the nearest, {} (scale {}); give --scale to choose",
            g.leg_length,
            joint(0),
            joint(feet[0]),
            rig::LEG_LENGTH_M / rig::LEG_TOLERANCE,
            rig::LEG_LENGTH_M * rig::LEG_TOLERANCE,
            g.unit.name,
            g.unit.metres
        );
    }
    Ok(g.unit.metres)
}

/// Reads the hand-written interval list: `CLIP START END` per line, `#` comments.
pub fn parse_intervals(text: &str, file: &str) -> Result<Vec<IntervalSpec>, SourceError> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let (fields, end_col) = tokenize(line);
        if fields.is_empty() {
            continue;
        }
        if fields.len() != 3 {
            let col = fields.get(3).map_or(end_col, |f| f.col);
            return Err(SourceError::new(
                file,
                n + 1,
                col,
                format!("expected CLIP START END, found {} fields", fields.len()),
            ));
        }
        let num = |t: Tok| {
            t.text.parse::<usize>().map_err(|_| {
                SourceError::new(file, n + 1, t.col, format!("expected a frame number, found '{}'", t.text))
            })
        };
        let (start, end) = (num(fields[1])?, num(fields[2])?);
        if end <= start {
            return Err(SourceError::new(file, n + 1, fields[2].col, "the last frame must come after the first"));
        }
        out.push(IntervalSpec { clip: fields[0].text.to_string(), start, end });
    }
    Ok(out)
}

/// `strider db …`.
pub fn db(command: DbCommand) -> Outcome {
    match command {
        DbCommand::Build(a) => {
            if let Some(s) = a.scale
                && !(s > 0.0 && s.is_finite())
            {
                return Err(anyhow!("--scale must be a positive number").into());
            }
            if let Some(k) = a.k
                && !(1..=crate::anim::db::MAX_K).contains(&k)
            {
                return Err(anyhow!("--k must be in 1..={}, found {k}", crate::anim::db::MAX_K).into());
            }
            if let Some(f) = &a.feet
                && f.len() != 2
            {
                return Err(anyhow!("--feet takes two joint names, LEFT,RIGHT; found {}", f.len()).into());
            }
            let mut texts = Vec::with_capacity(a.bvh.len());
            for p in &a.bvh {
                texts.push(files::read_text(p)?);
            }
            let manual = match &a.intervals {
                Some(p) => {
                    let text = files::read_text(p)?;
                    Some(parse_intervals(&text, &p.display().to_string())?)
                }
                None => None,
            };
            let scale = build_scale(&a, &a.bvh[0], &texts[0])?;
            let mut skeleton: Option<Skeleton> = None;
            let mut clips: Vec<Clip> = Vec::new();
            for (p, text) in a.bvh.iter().zip(&texts) {
                let (s, c) = parse_bvh(p, text, scale)?;
                match &skeleton {
                    Some(k) if !same_skeleton(k, &s) => {
                        return Err(anyhow!("{}: its skeleton differs from the first file's", p.display()).into());
                    }
                    Some(_) => {}
                    None => skeleton = Some(s),
                }
                if clips.iter().any(|o| o.name == c.name) {
                    return Err(anyhow!("{}: a clip named '{}' is already in the database", p.display(), c.name).into());
                }
                clips.push(c);
            }
            let skeleton = skeleton.ok_or_else(|| anyhow!("no BVH files"))?;
            let feet = a.feet.clone().unwrap_or_default();
            let mut params = DbParams { k: a.k.unwrap_or(DbParams::default().k), ..DbParams::default() };
            params.contacts.feet = feet.clone();
            let built = Database::build(clips.clone(), skeleton.clone(), params.clone(), manual.as_deref());
            let db = match built {
                // Without --k, a small capture still makes a database: K shrinks to fit.
                Err(DbError::TooFewIntervals(n, _)) if a.k.is_none() && n >= 2 => {
                    eprintln!("{n} intervals: K = {} (give more clips for the usual K = {})", n - 1, params.k);
                    params.k = n - 1;
                    Database::build(clips, skeleton, params, manual.as_deref())
                }
                other => other,
            }
            .map_err(|e| anyhow!("{e}"))?;
            write_database(&db, &a.out, &feet)?;
            outln!(
                "{} intervals from {} clips, K = {}, lengths × {scale}, written to {}",
                db.intervals.len(),
                db.clips.len(),
                db.params.k,
                a.out.display()
            )?;
            Ok(())
        }
        DbCommand::Info { dir } => {
            let db = match &dir {
                Some(d) => load_database(d)?,
                None => builtin_database()?,
            };
            files::write_stdout(format_args!("{}", describe(&db, dir.as_deref())))?;
            Ok(())
        }
        DbCommand::Track { dir, policy, transition } => {
            let body = BodyArgs { body: BodyKind::Animated, db: dir, policy, transition, ..BodyArgs::default() };
            let anim = load_animation(&body)?.ok_or_else(|| anyhow!("no animation"))?;
            let f = crate::sim::measure_tracking(&anim.0, 1.35, 0.8);
            let phases = crate::sim::animated::PHASES;
            outln!(
                "90° heading change, walking: left {:.2} s, right {:.2} s (within 10°; mean of {phases} phases, slowest {:.2} / {:.2} s)",
                f.turn_left_90_s,
                f.turn_right_90_s,
                f.worst_s[0],
                f.worst_s[1]
            )?;
            outln!(
                "speed change 0.8 → 1.35 m/s: {:.2} s; 1.35 → 0.8 m/s: {:.2} s (within 10 %; mean of {phases} phases, slowest {:.2} / {:.2} s)",
                f.speed_up_s,
                f.slow_down_s,
                f.worst_s[2],
                f.worst_s[3]
            )?;
            outln!("RMS distance, commanded path to root path (60 s of varied commands): {:.3} m", f.rms_path_m)?;
            outln!(
                "foot skating (heel and toe): {:.3} cm/frame at 60 Hz; plants sliding under 2 cm: {:.1}%",
                f.foot_skating_cm_per_frame,
                100.0 * f.steady_plant_share
            )?;
            outln!(
                "transitions: {:.2} per second; mean transition cost {:.4}",
                f.transitions_per_s,
                f.transition_cost
            )?;
            Ok(())
        }
        DbCommand::Strip(a) => super::db_strip::run(a),
        DbCommand::Export { out } => {
            let db = builtin_database()?;
            write_database(&db, &out, &[])?;
            outln!("{} clips, {} intervals written to {}", db.clips.len(), db.intervals.len(), out.display())?;
            Ok(())
        }
    }
}

/// A description of a database: skeleton, clips, intervals, neighbours.
pub fn describe(db: &Database, dir: Option<&Path>) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let name = dir.map_or("built-in (22-DOF actor, generated clips)".to_string(), |d| d.display().to_string());
    let dof: usize = db.skeleton.joints().iter().map(|j| j.channels.len()).sum();
    let _ = writeln!(s, "database: {name}");
    let _ = writeln!(
        s,
        "skeleton: {} joints, {dof} degrees of freedom; feet {} / {}",
        db.skeleton.len(),
        db.skeleton.joints()[db.feet[0]].name,
        db.skeleton.joints()[db.feet[1]].name
    );
    let total: f64 = db.clips.iter().map(Clip::duration).sum();
    let _ = writeln!(s, "clips: {} ({total:.1} s)", db.clips.len());
    let _ = writeln!(s, "intervals: {}", db.intervals.len());
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for i in &db.intervals {
        lo = lo.min(i.duration);
        hi = hi.max(i.duration);
    }
    let _ = writeln!(s, "interval length: {lo:.2}–{hi:.2} s; speeds up to {:.2} m/s", db.max_speed());
    let _ =
        writeln!(s, "neighbours: K = {}, ε = {:.4}, fingerprint {:016x}", db.params.k, db.epsilon, db.fingerprint());
    let (lo, hi) = db.candidates.iter().fold((usize::MAX, 0), |(lo, hi), c| (lo.min(c.len()), hi.max(c.len())));
    let mirrored = db.mirror.iter().filter(|m| m.is_some()).count();
    let count = |f: &dyn Fn(&crate::anim::db::IntervalKind) -> bool| db.kinds.iter().filter(|k| f(k)).count();
    let _ = writeln!(
        s,
        "candidates per switch: {lo}–{hi}; mirrored intervals: {mirrored} of {}; stopping {}, in place {}, turning on the spot {} left / {} right",
        db.intervals.len(),
        count(&|k| k.stops),
        count(&|k| k.in_place),
        count(&|k| k.spot_turn > 0),
        count(&|k| k.spot_turn < 0)
    );
    let w = crate::anim::warp::WarpLimits::default();
    let _ = writeln!(
        s,
        "sharp turns while moving (40° or more): {} left / {} right; default warping (`strider train`): turns ×{:.2}–{:.2} (on the spot ×{:.2}–{:.2}), bends up to {:.0}°, strides ×{:.2}–{:.2}",
        count(&|k| k.sharp_turn > 0),
        count(&|k| k.sharp_turn < 0),
        w.turn_scale.0,
        w.turn_scale.1,
        w.spot_scale.0,
        w.spot_scale.1,
        w.bend_rad.to_degrees(),
        w.stride.0,
        w.stride.1
    );
    tight_places(&mut s, db, &w);
    let _ = writeln!(s, "{:<22} {:>7} {:>10} {:>9}", "clip", "frames", "intervals", "speed");
    for (c, clip) in db.clips.iter().enumerate() {
        let ivs: Vec<_> = db.intervals.iter().filter(|i| i.clip == c).collect();
        let v = ivs.iter().map(|i| i.speed).sum::<f64>() / ivs.len().max(1) as f64;
        let _ = writeln!(s, "{:<22} {:>7} {:>10} {:>7.2} m/s", clip.name, clip.frames.len(), ivs.len(), v);
    }
    s
}

/// `strider train`.
pub fn train(a: TrainArgs) -> Outcome {
    let max = crate::anim::policy::MAX_EPISODES;
    if !(1..=max).contains(&a.episodes) {
        return Err(anyhow!("--episodes must be in 1..={max}, found {}", a.episodes).into());
    }
    files::check_writable(&a.out)?;
    let db = match &a.db {
        Some(d) => load_database(d)?,
        None => builtin_database()?,
    };
    let mut policy = if a.resume {
        let bytes = files::read_bytes(&a.out)?;
        let p = Policy::from_bytes(&bytes, &db).map_err(|e| anyhow!("{}: {e}", a.out.display()))?;
        if p.episodes >= a.episodes {
            return Err(anyhow!(
                "{}: already trained for {} episodes; give --episodes above that to go on",
                a.out.display(),
                p.episodes
            )
            .into());
        }
        eprintln!("resuming at {} episodes (seed {})", p.episodes, p.seed);
        p
    } else {
        Policy::new(&db, StateGrid::default(), LearnParams::default(), a.seed)
    };
    let target = a.episodes;
    let bar = indicatif::ProgressBar::new(target);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} episodes, {elapsed} elapsed, eta {eta} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_position(policy.episodes);
    let mut stable_since: Option<u64> = None;
    let mut last_changed = f64::NAN;
    let mut write_error = None;
    let started = std::time::Instant::now();
    let out = a.out.clone();
    // Ctrl-C or a termination signal stops training between two rounds, where no temporary
    // file exists: the last checkpoint stays the policy file.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(signal, stop.clone()).context("cannot install the signal handler")?;
    }
    policy.train(
        &db,
        target,
        50,
        &mut |p| {
            if stop.load(std::sync::atomic::Ordering::Relaxed) {
                bar.finish_and_clear();
                eprintln!("interrupted after {} episodes; {} holds the last checkpoint", p.episodes, out.display());
                std::process::exit(130);
            }
            bar.set_position(p.episodes);
            bar.set_message(format!("best action changed in {:.2}% of states", 100.0 * p.changed));
            last_changed = p.changed;
            if p.changed < 0.005 {
                stable_since.get_or_insert(p.episodes);
            } else {
                stable_since = None;
            }
        },
        &mut |p| {
            if let Err(e) = write_atomic(&out, &p.to_bytes()) {
                write_error.get_or_insert(e);
            }
        },
    );
    bar.finish_and_clear();
    if let Some(e) = write_error {
        return Err(anyhow!("cannot write checkpoint {}: {e}", out.display()).into());
    }
    write_atomic(&a.out, &policy.to_bytes()).with_context(|| format!("cannot write {}", a.out.display()))?;
    let secs = started.elapsed().as_secs_f64();
    outln!(
        "trained {} episodes in {secs:.1} s; {} of {} sampled states visited; {}; written to {}",
        policy.episodes,
        policy.visited_states(),
        policy.states(),
        match stable_since {
            Some(e) => format!("best actions stable (under 0.5% changing per round) since episode {e}"),
            None => format!(
                "best actions still changing ({:.2}% of visited states in the last round)",
                100.0 * last_changed
            ),
        },
        a.out.display()
    )?;
    outln!(
        "mirrored states picking the mirrored candidate: {:.1}%; action values never updated: {:.1}%",
        100.0 * policy.mirror_agreement(&db),
        100.0 * policy.untouched_share()
    )?;
    outln!("held-out episodes of the training MDP ({HELD_OUT_EPISODES}, drawn as training draws them):")?;
    outln!("  {:<10} {:>12} {:>13}", "strategy", "mean return", "task success")?;
    for s in Strategy::ALL {
        let e = crate::anim::policy::evaluate(&db, &policy, s, HELD_OUT_EPISODES, a.seed);
        outln!("  {:<10} {:>12.4} {:>12.1}%", s.name(), e.mean_return, 100.0 * e.task_success)?;
    }
    Ok(())
}

/// Held-out episodes `strider train` scores the policy and the baselines on.
const HELD_OUT_EPISODES: u64 = 20_000;
