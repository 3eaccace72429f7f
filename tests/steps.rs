//! The footstep planner (seed 002 §4.1–4.2) against an exhaustive search over the same step
//! set, on generated profiles of every kind and on the shipped ones; every foothold, swing and
//! leg pose checked from the ground pieces directly; `strider steps` end to end.

mod common;

use common::strider;

use std::collections::{HashSet, VecDeque};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use proptest::prelude::*;
use strider::footstep::legs::SWING_SAMPLES;
use strider::footstep::{
    Course, Foot, Foothold, FootstepParams, FootstepPlanner, GroundPiece, GroundProfile, PlanError, PlannerMode,
    StepSet, StopReason, Walk, WalkOutcome, check_step, position_m, walk,
};
use strider::ground::parse;
use strider::rng::{stream, uniform};

// ---------------------------------------------------------------------------------------------
// The oracle and the independent checks.

/// Exhaustive breadth-first search over every sequence of valid steps from the start: whether
/// one reaches the goal, and the furthest foothold (micrometres from the start) any reaches.
fn oracle(course: &Course, params: &FootstepParams) -> (bool, i64) {
    let steps = StepSet::new(params);
    let x = |o: i64| position_m(course.start_m, o);
    let mut seen = HashSet::new();
    let mut queue = VecDeque::from([(0i64, 0i64)]);
    let mut best = 0;
    while let Some((a, b)) = queue.pop_front() {
        if x(b) >= course.goal_m {
            return (true, b);
        }
        best = best.max(b);
        for &s in steps.lengths_um() {
            let n = b + s;
            if !seen.contains(&(b, n)) && check_step(&course.ground, params, x(a), x(b), x(n)).is_ok() {
                seen.insert((b, n));
                queue.push_back((b, n));
            }
        }
    }
    (false, best)
}

/// Heights of every piece covering `x`.
fn heights(pieces: &[GroundPiece], x: f64) -> Vec<f64> {
    pieces
        .iter()
        .filter(|p| p.x0_m <= x && x <= p.x1_m)
        .map(|p| p.z0_m + (x - p.x0_m) * (p.z1_m - p.z0_m) / (p.x1_m - p.x0_m))
        .collect()
}

/// One height where the ground is continuous at `x`.
fn height(pieces: &[GroundPiece], x: f64) -> f64 {
    let h = heights(pieces, x);
    assert!(!h.is_empty(), "no ground at {x}");
    h[0]
}

/// Checks a foothold from the pieces: the whole sole on ground, no gap or vertical step under
/// it, no piece under it steeper than the limit, resting on the ground at both ends with no
/// bump above it; the height change from the previous foothold within the limits.
fn check_foothold(pieces: &[GroundPiece], params: &FootstepParams, f: &Foothold, prev: Option<&Foothold>, what: &str) {
    let l = params.leg.foot_length_m();
    let (x0, x1) = (f.sole.x_m - l / 2.0, f.sole.x_m + l / 2.0);
    for k in 0..=480 {
        let x = x0 + (x1 - x0) * k as f64 / 480.0;
        assert!(!heights(pieces, x).is_empty(), "{what}: a gap under the sole at {x}");
    }
    for p in pieces {
        for e in [p.x0_m, p.x1_m] {
            if x0 < e && e < x1 {
                let h = heights(pieces, e);
                let spread = h.iter().cloned().fold(f64::MIN, f64::max) - h.iter().cloned().fold(f64::MAX, f64::min);
                assert!(spread <= 1e-6, "{what}: a vertical step under the sole at {e}");
            }
        }
        if p.x1_m > x0 && p.x0_m < x1 {
            let slope = ((p.z1_m - p.z0_m) / (p.x1_m - p.x0_m)).atan().to_degrees().abs();
            assert!(slope <= params.max_slope_deg + 1e-9, "{what}: standing on a {slope}° slope");
        }
    }
    let (z0, z1) = (height(pieces, x0), height(pieces, x1));
    assert!((f.sole.z_m - 0.5 * (z0 + z1)).abs() < 1e-9, "{what}: the sole does not rest on the ground");
    for k in 0..=48 {
        let x = x0 + (x1 - x0) * k as f64 / 48.0;
        let line = z0 + (z1 - z0) * k as f64 / 48.0;
        assert!(height(pieces, x) <= line + 1e-6, "{what}: the sole straddles a bump at {x}");
    }
    if let Some(p) = prev {
        let rise = f.sole.z_m - p.sole.z_m;
        assert!(rise <= params.max_step_up_m + 1e-9, "{what}: a step up of {rise}");
        assert!(-rise <= params.max_step_down_m + 1e-9, "{what}: a step down of {}", -rise);
    }
}

/// Checks a whole walk from the pieces: footholds, the swings at eight times the planner's
/// samples (no point of the sole below the ground), and the legs (bones keep their lengths, so
/// every ankle is within reach; knees bend forward; the hip moves continuously).
fn check_walk(course: &Course, params: &FootstepParams, w: &Walk, what: &str) {
    let pieces = course.ground.pieces();
    let steps = StepSet::new(params);
    let lengths: Vec<f64> = (0..steps.len()).map(|j| steps.length_m(j)).collect();
    assert_eq!(w.footholds.len(), w.steps.len() + 2, "{what}");
    assert_eq!((w.footholds[0].foot, w.footholds[1].foot), (Foot::Left, Foot::Right));
    assert_eq!((w.footholds[0].sole.x_m, w.footholds[1].sole.x_m), (course.start_m, course.start_m));
    for (i, f) in w.footholds.iter().enumerate() {
        let prev = i.checked_sub(1).map(|j| &w.footholds[j]);
        check_foothold(pieces, params, f, prev, &format!("{what}: foothold {i}"));
    }
    let l = params.leg.foot_length_m();
    let mut last_hip = None;
    for (i, s) in w.steps.iter().enumerate() {
        let what = format!("{what}: step {}", i + 1);
        let sw = &s.swing;
        assert_eq!(s.foot, w.footholds[i + 2].foot);
        assert_eq!(w.footholds[i + 2].foot, w.footholds[i].foot, "{what}: feet alternate");
        assert_eq!(
            (sw.lift_off, sw.stance, sw.touch_down),
            (w.footholds[i].sole, w.footholds[i + 1].sole, w.footholds[i + 2].sole)
        );
        assert!(
            lengths.iter().any(|len| (len - sw.length_m()).abs() < 2e-6),
            "{what}: {} is not in the step set",
            sw.length_m()
        );
        assert_eq!(sw.sole_at(0.0), sw.lift_off);
        assert_eq!(sw.sole_at(1.0), sw.touch_down);
        let fine = 8 * SWING_SAMPLES;
        for k in 1..fine {
            let t = k as f64 / fine as f64;
            let sole = sw.sole_at(t);
            let (heel, toe) = (sole.heel(l), sole.toe(l));
            let under = |x: f64| heel.y + (toe.y - heel.y) * (x - heel.x) / (toe.x - heel.x);
            let mut xs: Vec<f64> = (0..=48).map(|j| heel.x + (toe.x - heel.x) * j as f64 / 48.0).collect();
            xs.extend(pieces.iter().flat_map(|p| [p.x0_m, p.x1_m]).filter(|&e| heel.x <= e && e <= toe.x));
            for x in xs {
                for g in heights(pieces, x) {
                    assert!(
                        g <= under(x) + 1e-9,
                        "{what}: the swinging sole is {} m into the ground at x = {x}, t = {t}",
                        g - under(x)
                    );
                }
            }
        }
        for pose in sw.poses(48) {
            for leg in [pose.swing, pose.stance] {
                assert!((leg.knee.distance(leg.hip) - params.leg.thigh_m).abs() < 1e-9, "{what}: thigh");
                assert!(
                    (leg.knee.distance(leg.ankle) - params.leg.shin_m).abs() < 1e-9,
                    "{what}: out of reach at {}",
                    pose.phase
                );
                assert!((leg.ankle - leg.hip).perp_dot(leg.knee - leg.hip) >= -1e-9, "{what}: knee bent backward");
            }
            assert_eq!(pose.swing.hip, pose.stance.hip);
        }
        let hip = sw.pose_at(0.0).swing.hip;
        if let Some(last) = last_hip {
            assert!(hip.distance(last) < 1e-9, "{what}: the hip jumps between steps");
        }
        last_hip = Some(sw.pose_at(1.0).swing.hip);
    }
}

/// The planner's walk agrees with the oracle: crosses when it can; otherwise stops, with a
/// reason, at the furthest foothold any sequence of steps reaches.
fn agree(course: &Course, params: &FootstepParams, what: &str) -> bool {
    let (can, best) = oracle(course, params);
    let w = walk(course, *params, PlannerMode::Window).unwrap();
    check_walk(course, params, &w, what);
    if can {
        assert!(w.reached(), "{what}: the oracle crosses, the planner stopped: {:?}", w.outcome);
    } else {
        let WalkOutcome::Stopped(StopReason::NoFurtherStep { at_m, .. }) = &w.outcome else {
            panic!("{what}: the oracle cannot cross, the planner says {:?}", w.outcome)
        };
        assert_eq!(*at_m, position_m(course.start_m, best), "{what}: stopped short of the furthest reachable foothold");
        assert!(!w.outcome_text().is_empty());
    }
    let nominal = walk(course, *params, PlannerMode::Nominal).unwrap();
    check_walk(course, params, &nominal, &format!("{what} (planner off)"));
    if can {
        // Without planning the walker may be trapped, but never goes where the planner could not.
        assert!(nominal.footholds.len() >= 2);
    }
    can
}

trait OutcomeText {
    fn outcome_text(&self) -> String;
}

impl OutcomeText for Walk {
    fn outcome_text(&self) -> String {
        match &self.outcome {
            WalkOutcome::Reached => "reached".into(),
            WalkOutcome::Stopped(r) => r.to_string(),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Generated profiles.

/// Builds a profile left to right.
struct Builder {
    pieces: Vec<GroundPiece>,
    x: f64,
    z: f64,
}

impl Builder {
    fn new() -> Builder {
        let mut b = Builder { pieces: Vec::new(), x: -0.5, z: 0.0 };
        b.run(1.5);
        b
    }
    fn run(&mut self, length: f64) {
        self.slope(length, 0.0);
    }
    fn slope(&mut self, length: f64, rise: f64) {
        self.pieces.push(GroundPiece { x0_m: self.x, z0_m: self.z, x1_m: self.x + length, z1_m: self.z + rise });
        self.x += length;
        self.z += rise;
    }
    fn step(&mut self, dz: f64) {
        self.z += dz;
    }
    fn gap(&mut self, width: f64) {
        self.x += width;
    }
    fn finish(mut self) -> Course {
        let goal = self.x + 0.8;
        self.run(1.8);
        Course::new(GroundProfile::new(self.pieces).unwrap(), 0.0, goal).unwrap()
    }
}

const KINDS: [&str; 6] = ["stairs", "slope", "gap", "stones", "step", "blocks"];

fn generate(kind: &str, seed: u64) -> Course {
    let mut r = stream(seed, 0, 11);
    let mut b = Builder::new();
    match kind {
        "stairs" => {
            let (rise, tread) = (uniform(&mut r, 0.08, 0.5), uniform(&mut r, 0.2, 0.45));
            let n = 2 + (uniform(&mut r, 0.0, 4.0) as usize);
            let down = if uniform(&mut r, 0.0, 1.0) < 0.5 { -1.0 } else { 1.0 };
            for _ in 0..n {
                b.step(down * rise);
                b.run(tread);
            }
            b.run(uniform(&mut r, 0.3, 1.2));
            for _ in 0..n {
                b.step(-down * rise);
                b.run(tread);
            }
        }
        "slope" => {
            let deg: f64 = uniform(&mut r, 5.0, 40.0);
            let length = uniform(&mut r, 0.4, 2.5);
            let sign = if uniform(&mut r, 0.0, 1.0) < 0.5 { -1.0 } else { 1.0 };
            b.slope(length, sign * length * deg.to_radians().tan());
            b.run(uniform(&mut r, 0.2, 1.0));
            let deg2: f64 = uniform(&mut r, 5.0, 35.0);
            let length2 = uniform(&mut r, 0.4, 2.0);
            b.slope(length2, -sign * length2 * deg2.to_radians().tan());
        }
        "gap" => {
            b.gap(uniform(&mut r, 0.1, 1.3));
            b.step(uniform(&mut r, -0.4, 0.4));
            b.run(uniform(&mut r, 0.3, 1.0));
            b.gap(uniform(&mut r, 0.1, 0.8));
        }
        "stones" => {
            for _ in 0..(2 + uniform(&mut r, 0.0, 5.0) as usize) {
                b.gap(uniform(&mut r, 0.1, 0.7));
                b.step(uniform(&mut r, -0.12, 0.12));
                b.run(uniform(&mut r, 0.2, 0.55));
            }
            b.gap(uniform(&mut r, 0.1, 0.6));
        }
        "step" => {
            b.step(uniform(&mut r, -0.8, 0.8));
            b.run(uniform(&mut r, 0.2, 1.5));
            b.step(uniform(&mut r, -0.6, 0.6));
        }
        "blocks" => {
            for _ in 0..(1 + uniform(&mut r, 0.0, 3.0) as usize) {
                let h = uniform(&mut r, 0.05, 0.75);
                b.step(h);
                b.run(uniform(&mut r, 0.08, 1.2));
                b.step(-h);
                b.run(uniform(&mut r, 0.2, 1.5));
            }
        }
        _ => unreachable!(),
    }
    b.finish()
}

#[test]
fn generated_profiles_of_every_kind_agree_with_the_exhaustive_search() {
    let params = FootstepParams::default();
    for kind in KINDS {
        let (mut crossed, mut stopped) = (0, 0);
        for seed in 0..48 {
            let course = generate(kind, seed);
            if agree(&course, &params, &format!("{kind} #{seed}")) {
                crossed += 1;
            } else {
                stopped += 1;
            }
        }
        eprintln!("{kind}: {crossed} crossed, {stopped} stopped");
        // The generators make both kinds of profile.
        assert!(crossed >= 10 && stopped >= 10, "{kind}: {crossed} crossed, {stopped} stopped");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Arbitrary pieces — each a run of ground after a gap (possibly none) and a jump in height,
    /// flat or sloping — are walked safely and in agreement with the exhaustive search.
    #[test]
    fn arbitrary_profiles_agree_with_the_exhaustive_search(
        pieces in prop::collection::vec((0.0f64..0.9, -0.6f64..0.6, 0.05f64..1.6, -0.8f64..0.8), 1..7)
    ) {
        let mut b = Builder::new();
        for (gap, jump, length, slope) in pieces {
            if gap > 0.3 {
                b.gap(gap - 0.3);
            }
            b.step(jump);
            b.slope(length, slope * length);
        }
        agree(&b.finish(), &FootstepParams::default(), "arbitrary");
    }

    /// Any text is read or refused with a located error; never a panic.
    #[test]
    fn any_text_is_read_or_refused(text in "(start|goal|ground|[a-z]{1,3}|-?[0-9]{1,2}(\\.[0-9])?|nan|inf|#|\n| |\t){0,60}") {
        if let Ok(course) = parse(&text, "any.profile") {
            // A parsed course can be handed to the planner: it plans or refuses the start.
            let _ = walk(&course, FootstepParams::default(), PlannerMode::Window);
        }
    }
}

#[test]
fn other_windows_and_resolutions_agree_too() {
    for (n, m) in [(1, 13), (2, 6), (4, 9), (3, 26)] {
        let params = FootstepParams { window_steps: n, intervals: m, ..FootstepParams::default() };
        for (i, kind) in KINDS.iter().enumerate() {
            for seed in 100..104 {
                agree(&generate(kind, seed + 10 * i as u64), &params, &format!("n={n} m={m} {kind} #{seed}"));
            }
        }
    }
}

#[test]
fn walks_are_deterministic() {
    let course = generate("stones", 3);
    let a = walk(&course, FootstepParams::default(), PlannerMode::Window).unwrap();
    let b = walk(&course, FootstepParams::default(), PlannerMode::Window).unwrap();
    assert_eq!(a, b);
}

// ---------------------------------------------------------------------------------------------
// Shipped profiles and the command line.

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn shipped(name: &str) -> Course {
    let path = root().join("maps/profiles").join(format!("{name}.profile"));
    parse(&std::fs::read_to_string(&path).unwrap(), &path.display().to_string()).unwrap()
}

#[test]
fn shipped_profiles_are_crossed_or_stop_at_the_edge() {
    let params = FootstepParams::default();
    for name in ["stairs", "slope", "stepping_stones", "fig8_trap", "low_blocks"] {
        assert!(agree(&shipped(name), &params, name), "{name} must be crossable");
    }
    for (name, hazard) in [("gap_too_wide", "a gap from x = 3.00 m to 4.20 m"), ("cliff", "a drop of 1.50 m")] {
        assert!(!agree(&shipped(name), &params, name), "{name} must not be crossable");
        let w = walk(&shipped(name), params, PlannerMode::Window).unwrap();
        assert!(w.outcome_text().contains(hazard), "{name}: {}", w.outcome_text());
    }
    let dir = std::fs::read_dir(root().join("maps/profiles")).unwrap();
    assert_eq!(dir.count(), 7, "every shipped profile is tested here");
}

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&o.stdout)))
}

fn temp(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("steps");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn the_fig8_trap_both_ways_through_the_command_line() {
    let off = strider(&["steps", "maps/profiles/fig8_trap.profile", "--planner", "off"]);
    assert_eq!(off.status.code(), Some(1), "{}", String::from_utf8_lossy(&off.stderr));
    let v = json(&off);
    assert_eq!(v["reached"], false);
    let footholds = v["footholds"].as_array().unwrap();
    let last = footholds.last().unwrap()["x_m"].as_f64().unwrap();
    assert!(last < 3.0, "stuck before the gap: {last}");
    assert!(footholds.iter().all(|f| f["x_m"].as_f64().unwrap() + 0.12 <= 3.0), "never over the gap");
    let reason = v["stopped_reason"].as_str().unwrap();
    assert!(reason.contains("no ground under the sole"), "{reason}");

    let on = strider(&["steps", "maps/profiles/fig8_trap.profile"]);
    assert!(on.status.success(), "{}", String::from_utf8_lossy(&on.stderr));
    let v = json(&on);
    assert_eq!(v["reached"], true);
    assert!(v.get("stopped_reason").is_none());
    let footholds = v["footholds"].as_array().unwrap();
    let n = footholds.len();
    assert_eq!((footholds[0]["foot"].as_str(), footholds[1]["foot"].as_str()), (Some("left"), Some("right")));
    assert_eq!((footholds[0]["x_m"].as_f64(), footholds[1]["x_m"].as_f64()), (Some(0.0), Some(0.0)));
    assert!(footholds[n - 1]["x_m"].as_f64().unwrap() >= 6.0);
    for f in footholds {
        let x = f["x_m"].as_f64().unwrap();
        assert!(x + 0.12 <= 3.0 || x - 0.12 >= 3.6, "a foothold over the gap: {x}");
    }
    assert_eq!(v["swings"].as_array().unwrap().len(), n - 2);
    assert_eq!(v["planning_ms"].as_array().unwrap().len(), n - 2);
    for swing in v["swings"].as_array().unwrap() {
        let points = swing.as_array().unwrap();
        assert_eq!(points.len(), SWING_SAMPLES + 1);
        for p in &points[1..SWING_SAMPLES] {
            assert!(p[1].as_f64().unwrap() > 0.0, "the sole's lowest point is above the ground mid-swing");
        }
    }
    let p = &v["params"];
    let expected = [
        ("foot_length_m", 0.24),
        ("step_min_m", 0.25),
        ("step_max_m", 0.9),
        ("window_steps", 3.0),
        ("intervals", 13.0),
        ("max_step_up_m", 0.45),
        ("max_step_down_m", 0.5),
        ("max_slope_deg", 30.0),
        ("leg_length_m", 0.88),
    ];
    for (key, value) in expected {
        assert!((p[key].as_f64().unwrap() - value).abs() < 1e-12, "{key}: {}", p[key]);
    }
    assert_eq!(p.as_object().unwrap().len(), expected.len());
}

#[test]
fn the_text_summary_and_the_options() {
    let o =
        strider(&["steps", "maps/profiles/stairs.profile", "--format", "text", "--window", "2", "--intervals", "26"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("planner on: 2 steps ahead") && text.contains("26 intervals"), "{text}");
    assert!(text.contains("reached the goal") && text.contains("uphill") && text.contains("downhill"), "{text}");
    assert!(text.contains("planning per step: median"), "{text}");
    let o = strider(&["steps", "maps/profiles/cliff.profile", "--format", "text"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stdout).contains("a drop of 1.50 m at x = 4.00 m"));
    assert!(String::from_utf8_lossy(&o.stderr).contains("the goal was not reached"));
}

#[test]
fn bad_input_is_a_clear_error() {
    let cases: Vec<(PathBuf, Vec<&str>, &str)> = vec![
        (
            temp("malformed.profile", b"start 0\ngoal 2\nground 0 0 two 0\n"),
            vec![],
            "malformed.profile:3:12: expected a number, found `two`",
        ),
        (
            temp("order.profile", b"start 0\ngoal 2\nground 0 0 3 0\nground 2 0 4 0\n"),
            vec![],
            "order.profile:4:8: the piece starts at X0 = 2 before the previous piece ends",
        ),
        (
            temp("nan.profile", b"start 0\ngoal 2\nground 0 0 3 nan\n"),
            vec![],
            "nan.profile:3:14: `nan` is not a finite number",
        ),
        (temp("utf8.profile", b"start 0\ngoal 2\nground 0 0 \xff 0\n"), vec![], "utf8.profile:3:12: not UTF-8 text"),
        (
            temp("start.profile", b"start 0.5\ngoal 2\nground 0.55 0 3 0\n"),
            vec![],
            "start.profile:1: the feet cannot stand at the start",
        ),
        (temp("ok.profile", b"start 0\ngoal 2\nground -1 0 3 0\n"), vec!["--intervals", "0"], "intervals = 0"),
        (temp("ok.profile", b"start 0\ngoal 2\nground -1 0 3 0\n"), vec!["--window", "0"], "window_steps = 0"),
        (temp("ok.profile", b"start 0\ngoal 2\nground -1 0 3 0\n"), vec!["--window", "9"], "window_steps = 9"),
        (PathBuf::from("maps/profiles/missing.profile"), vec![], "cannot open maps/profiles/missing.profile"),
    ];
    for (path, extra, needle) in cases {
        let mut args = vec!["steps", path.to_str().unwrap()];
        args.extend(extra);
        let o = strider(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: '{err}' should contain '{needle}'");
        assert!(!err.contains("panicked"));
    }
    // A byte-order mark is fine.
    let bom = temp("bom.profile", b"\xef\xbb\xbfstart 0\ngoal 2\nground -1 0 3 0\n");
    assert!(strider(&["steps", bom.to_str().unwrap()]).status.success());
}

#[test]
fn inverted_limits_and_empty_step_sets_are_refused() {
    let g = GroundProfile::flat(-1.0, 5.0).unwrap();
    let ok = FootstepParams::default();
    for (params, needle) in [
        (FootstepParams { step_min_m: 0.8, step_max_m: 0.3, step_init_m: 0.5, ..ok }, "inverted step limits"),
        (FootstepParams { intervals: 0, ..ok }, "intervals = 0"),
        (FootstepParams { window_steps: 0, ..ok }, "window_steps = 0"),
        (FootstepParams { max_slope_deg: f64::NAN, ..ok }, "max_slope_deg = NaN"),
    ] {
        let e = FootstepPlanner::new(&g, 0.0, 3.0, params, PlannerMode::Window).err().unwrap();
        assert!(matches!(e, PlanError::Params(_)) && e.to_string().contains(needle), "{e}");
    }
}

#[test]
fn a_closed_pipe_is_not_an_error() {
    // A long walk prints far more than a pipe holds.
    let path = temp("long.profile", b"start 0\ngoal 300\nground -1 0 302 0\n");
    let mut child = Command::new(env!("CARGO_BIN_EXE_strider"))
        .args(["steps", path.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut out = child.stdout.take().unwrap();
    let mut first = [0u8; 16];
    out.read_exact(&mut first).unwrap();
    drop(out);
    let status = child.wait().unwrap();
    let mut err = String::new();
    child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
    assert!(status.success(), "{status}: {err}");
    assert!(err.is_empty(), "{err}");
}

#[test]
fn side_views_and_motion_files_from_the_command_line() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("side_views");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("trap_off.png");
    let off =
        strider(&["steps", "maps/profiles/fig8_trap.profile", "--planner", "off", "--png", png.to_str().unwrap()]);
    assert_eq!(off.status.code(), Some(1), "{}", String::from_utf8_lossy(&off.stderr));
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");

    let out = dir.join("render");
    let r =
        strider(&["render", "maps/terrain_fig8_trap.rhai", "--out", out.to_str().unwrap(), "--every", "0", "--side"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(&std::fs::read(out.join("side.png")).unwrap()[1..4], b"PNG");
    assert!(out.join("final.png").exists());

    // Refused before any work: with the disc body, and on a flat map.
    let refused = dir.join("refused");
    for args in [
        vec!["render", "maps/terrain_fig8_trap.rhai", "--out", refused.to_str().unwrap(), "--side", "--body", "disc"],
        vec!["render", "maps/sparse.rhai", "--out", refused.to_str().unwrap(), "--side"],
        vec!["run", "maps/terrain_fig8_trap.rhai", "--bvh-out", refused.to_str().unwrap(), "--body", "disc"],
    ] {
        let o = strider(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let flag = if args[0] == "run" { "--bvh-out" } else { "--side" };
        assert!(String::from_utf8_lossy(&o.stderr).contains(flag), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(!refused.exists(), "{args:?} wrote nothing");
    }
}
