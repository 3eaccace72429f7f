//! The animation database, the trained policy and the animated character, end to end
//! (seed 000 §3.2): the built-in database, the shipped policy, database directories, training
//! files, animated navigation and the command line.

mod common;

use common::strider;

use std::path::{Path, PathBuf};

use std::sync::Arc;

use glam::{DVec2, DVec3};
use strider::anim::bvh::{self, BvhOptions};
use strider::anim::player::{Choice, Chooser, Player, PlayerParams, SwitchPoint};
use strider::anim::policy::{Errors, Strategy, evaluate};
use strider::anim::warp::WarpLimits;
use strider::anim::{Database, Ground};
use strider::builtin;
use strider::cli::anim::parse_intervals;
use strider::experiment::run_episode;
use strider::load::{load_database, save_database};
use strider::script::{Limits, ScriptLog, load_scenario};
use strider::sim::{
    AnimatedBody, Animation, AnimationHandle, Body, Command, LayeredController, OpenSpace, StepParameters,
    Surroundings, measure_tracking,
};
use strider::world::{Obstacle, ObstacleShape, Pose, World};

fn temp_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn animation() -> Arc<Animation> {
    Arc::new(builtin::animation().expect("shipped policy matches the built-in database"))
}

#[test]
fn builtin_database_has_the_actor_and_enough_intervals() {
    let db = builtin::database().unwrap();
    let dof: usize = db.skeleton.joints().iter().map(|j| j.channels.len()).sum();
    assert_eq!(dof, 22);
    assert!(db.intervals.len() >= 200, "{} intervals", db.intervals.len());
    for (c, clip) in db.clips.iter().enumerate() {
        assert!(db.intervals.iter().any(|i| i.clip == c), "clip {} has no interval", clip.name);
    }
    for (i, cands) in db.candidates.iter().enumerate() {
        assert!(cands.len() > db.params.k, "the successor and its K neighbours at least");
        assert_eq!(cands[0].interval, db.successor[i]);
        assert!(cands.iter().all(|c| c.interval < db.intervals.len() && c.weight > 0.0));
    }
    // Intervals run from foot plant to foot plant: walking intervals alternate feet.
    let walk: Vec<u8> =
        db.intervals.iter().filter(|i| db.clips[i.clip].name == "walk_straight").map(|i| i.foot).collect();
    assert!(walk.windows(2).skip(1).all(|w| w[0] != w[1]), "{walk:?}");
}

#[test]
fn shipped_policy_belongs_to_the_builtin_database() {
    let a = animation();
    assert!(a.policy.visited_states() > a.policy.states() / 2);
    // Far to the left of the commanded heading, walking: the chosen interval turns left.
    let walk = a.db.intervals.iter().position(|i| a.db.clips[i.clip].name == "walk_straight").unwrap();
    let mut turned = 0.0;
    let mut i = walk;
    let mut e = Errors { speed: 0.0, direction: 1.5 };
    for _ in 0..4 {
        i = a.db.candidates[i][a.policy.choose(i, e)].interval;
        turned += a.db.intervals[i].turn();
        e.direction -= a.db.intervals[i].turn();
    }
    assert!(turned > 0.5, "turned {turned} rad");
}

#[test]
fn database_directories_round_trip() {
    let db = builtin::database().unwrap();
    let dir = temp_dir("db_round_trip");
    save_database(&db, &dir).unwrap();
    let back = load_database(&dir).unwrap();
    assert_eq!(back.clips.len(), db.clips.len());
    let spans = |d: &strider::anim::Database| d.intervals.iter().map(|i| (i.clip, i.start, i.end)).collect::<Vec<_>>();
    assert_eq!(spans(&back), spans(&db));
    // Clips written at 1e-6 precision may swap near-ties (clips that start with the same pose),
    // never for a worse choice: every successor starts as close to its predecessor's end.
    for i in 0..db.intervals.len() {
        let iv = &db.intervals[i];
        let end = db.relative_pose(iv.clip, iv.end as f64);
        let d = |s: usize| db.pose_distance(&end, &db.samples(s)[0]);
        assert!((d(back.successor[i]) - d(db.successor[i])).abs() < 1e-4, "interval {i}");
    }
}

#[test]
fn shipped_clips_are_the_generated_ones() {
    let db = builtin::database().unwrap();
    let shipped = load_database(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/db"))).unwrap();
    let spans = |d: &strider::anim::Database| d.intervals.iter().map(|i| (i.clip, i.start, i.end)).collect::<Vec<_>>();
    assert_eq!(spans(&shipped), spans(&db), "assets/db is stale: run `strider db export --out assets/db`");
    for (a, b) in shipped.clips.iter().zip(&db.clips) {
        assert_eq!(a.name, b.name);
        for (fa, fb) in a.frames.iter().zip(&b.frames) {
            assert!(fa.root.distance(fb.root) < 1e-6);
            for (qa, qb) in fa.rotations.iter().zip(&fb.rotations) {
                assert!(strider::anim::angle_between(*qa, *qb) < 1e-5);
            }
        }
    }
}

#[test]
fn hand_written_interval_lists() {
    let list = parse_intervals("# clip start end\nwalk 0 30\n\nwalk 30 61 # second\n", "i.txt").unwrap();
    assert_eq!(list.len(), 2);
    assert_eq!(list[1].end, 61);
    assert_eq!(
        parse_intervals("walk 0 x\n", "i.txt").unwrap_err().to_string(),
        "i.txt:1:8: expected a frame number, found 'x'"
    );
    assert_eq!(
        parse_intervals("walk 5 5\n", "i.txt").unwrap_err().to_string(),
        "i.txt:1:8: the last frame must come after the first"
    );
    assert!(parse_intervals("walk 1 2 3\n", "i.txt").unwrap_err().to_string().starts_with("i.txt:1:10:"));
}

fn controller() -> LayeredController {
    builtin::controller().expect("built-in rules")
}

#[test]
fn animated_navigation_is_collision_free_and_deterministic() {
    let log = ScriptLog::new();
    let scenario = load_scenario(include_str!("../maps/sparse.rhai"), "sparse.rhai", Limits::default(), &log).unwrap();
    let world = scenario.world();
    let params = StepParameters { animation: Some(AnimationHandle(animation())), ..StepParameters::default() };
    let c = controller();
    let a = run_episode(&scenario, &world, 0, &c, &params, 0, 1);
    let b = run_episode(&scenario, &world, 0, &c, &params, 0, 1);
    assert_eq!(a.record, b.record);
    assert_eq!(a.trail, b.trail);
    assert_eq!(a.record.collisions, 0);
    assert!(a.record.foot_skating_cm_per_frame.is_some() && a.record.tracking_rms_m.is_some());
    assert!(a.record.path_length_m > 1.0);
}

#[test]
fn tracking_commands_on_open_ground() {
    // Warped turns and strides: a walking 90° turn within about two steps, a speed change
    // within one, planted feet held (simulated seconds, the same on every machine).
    let f = measure_tracking(&animation(), 1.35, 0.8);
    assert!(f.turn_left_90_s <= 1.0 && f.turn_right_90_s <= 1.0, "{f:?}");
    assert!(f.speed_up_s <= 1.0 && f.slow_down_s <= 1.0, "{f:?}");
    assert!(f.rms_path_m < 0.5, "{f:?}");
    assert!(f.foot_skating_cm_per_frame <= 0.15 && f.steady_plant_share >= 0.95, "{f:?}");
}

#[test]
fn the_character_passes_one_metre_doors_and_keeps_its_room() {
    // Random grids of 1 m cells: every way is a metre wide, every turn a door's mouth.
    let params = StepParameters { animation: Some(AnimationHandle(animation())), ..StepParameters::default() };
    let c = controller();
    for seed in 0..4 {
        let scenario = strider::maps::kind::generate(strider::maps::kind::WorldKind::Grid, 4100 + seed);
        let world = scenario.world();
        let e = run_episode(&scenario, &world, 0, &c, &params, 0, seed);
        let r = &e.record;
        assert!(r.reached && r.collisions == 0, "grid {seed}: {r:?}");
        assert!(r.min_clearance_m >= strider::sim::animated::KEEP_ROOM_M - 1e-9, "grid {seed}: {r:?}");
    }
}

#[test]
fn command_line_database_and_training() {
    let dir = temp_dir("cli_train");
    let out = strider(&["db", "info"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("22 degrees of freedom") && text.contains("intervals:"), "{text}");
    let policy = dir.join("p.policy");
    let p = policy.to_str().unwrap();
    let out = strider(&["train", "--episodes", "128", "--seed", "3", "--out", p]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let first = std::fs::read(&policy).unwrap();
    let out = strider(&["train", "--episodes", "256", "--seed", "3", "--out", p, "--resume"]);
    assert!(out.status.success());
    let resumed = std::fs::read(&policy).unwrap();
    let out = strider(&["train", "--episodes", "256", "--seed", "3", "--out", dir.join("q.policy").to_str().unwrap()]);
    assert!(out.status.success());
    assert_eq!(std::fs::read(dir.join("q.policy")).unwrap(), resumed, "resuming gives the same policy as one run");
    assert_ne!(first, resumed);
    // A damaged policy is a clear error, not a panic.
    let mut bad = resumed.clone();
    bad[40] ^= 0xff;
    std::fs::write(&policy, &bad).unwrap();
    let out = strider(&["run", "maps/open_field.rhai", "--policy", p]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("corrupt"));
    // A BVH error names file, line and column.
    std::fs::write(dir.join("bad.bvh"), "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 zero\n").unwrap();
    let out = strider(&[
        "db",
        "build",
        "--bvh",
        dir.join("bad.bvh").to_str().unwrap(),
        "--out",
        dir.join("db").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.bvh:4:"), "{err}");
}

/// Picks candidates in a fixed pseudo-random order and remembers the path predicted for each.
struct Scripted {
    k: usize,
    predicted: Vec<Vec<DVec2>>,
}

impl Chooser for Scripted {
    /// A fixed scramble of the candidates, skipping those whose start cannot reach the feet
    /// planted now (as the character's own chooser does).
    fn choose(&mut self, db: &Database, at: &SwitchPoint) -> Choice {
        let n = db.candidates[at.ending].len();
        let first = (self.k * 7 + 3) % n;
        let c = (0..n)
            .map(|j| (first + j) % n)
            .find(|&c| at.reach_gap(db, c) <= strider::sim::animated::LOCK_REACH_M)
            .unwrap_or(first);
        // Warped as the character warps, toward headings and speeds in a fixed scramble.
        let k = self.k as f64;
        let next = &db.intervals[db.candidates[at.ending][c].interval];
        let (direction, speed) = (0.3 * (k % 5.0 - 2.0), next.speed * (0.8 + 0.2 * (k % 3.0)));
        let warp = at.warp_toward(db, c, direction, speed, &WarpLimits::default());
        self.k += 1;
        let choice = Choice { candidate: c, warp };
        let mut path = Vec::new();
        at.path(db, choice, &mut path);
        self.predicted.push(path);
        choice
    }
}

fn walk_interval(db: &Database) -> usize {
    db.intervals.iter().position(|i| db.clips[i.clip].name == "walk_straight").unwrap()
}

#[test]
fn predicted_paths_are_the_played_paths() {
    let a = animation();
    let db = &a.db;
    let mut chooser = Scripted { k: 0, predicted: Vec::new() };
    let mut player = Player::new(db, walk_interval(db), Ground::default(), PlayerParams::default());
    let mut trail = vec![DVec2::ZERO];
    for _ in 0..3000 {
        player.advance_frame(db, &mut chooser);
        let g = player.ground();
        trail.push(DVec2::new(g.x, g.y));
    }
    assert!(chooser.predicted.len() > 50);
    // Every predicted point lies on the played root path (a polyline at 60 Hz).
    let on_trail = |p: DVec2| {
        trail
            .windows(2)
            .map(|w| {
                let (a, b) = (w[0], w[1]);
                let t = ((p - a).dot(b - a) / (b - a).length_squared().max(1e-18)).clamp(0.0, 1.0);
                p.distance(a + (b - a) * t)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut worst = 0.0f64;
    for path in chooser.predicted.iter().take(chooser.predicted.len() - 1) {
        for &p in path {
            worst = worst.max(on_trail(p));
        }
    }
    // Warped pieces follow arcs, exact where the curvature is constant; what is left stays
    // under the 5 mm the look-ahead adds to every clearance it checks.
    assert!(worst < 4e-3, "a predicted point is {worst} m off the played path");
}

#[test]
fn locked_feet_stay_planted_through_transitions() {
    let a = animation();
    let db = &a.db;
    let play = |locking: bool| {
        let mut chooser = Scripted { k: 0, predicted: Vec::new() };
        let params = PlayerParams { foot_locking: locking, ..PlayerParams::default() };
        let mut player = Player::new(db, walk_interval(db), Ground::default(), params);
        for _ in 0..3600 {
            player.advance_frame(db, &mut chooser);
        }
        player.metrics
    };
    let (locked, free) = (play(true), play(false));
    assert!(locked.transitions > 30, "{locked:?}");
    assert!(locked.foot_skating_cm_per_frame() < free.foot_skating_cm_per_frame(), "{locked:?} {free:?}");
    assert!(locked.steady_plant_share() >= 0.95, "{locked:?}");
}

#[test]
fn the_character_looks_before_it_steps() {
    // A wall across the way 4 m ahead: commanded to walk on, the character stops short of it
    // with its clearance margin, without the last-resort guard ever holding its root.
    let a = animation();
    let wall = Obstacle::build(
        ObstacleShape::Box { center: DVec2::new(4.5, 0.0), width: 1.0, height: 6.0, yaw: 0.0 },
        0.0,
        2.0,
    )
    .unwrap();
    let world = World::new(vec![wall]);
    let mut body = AnimatedBody::new(a.clone(), Pose { position: DVec2::ZERO, yaw: 0.0 }, 0.3);
    let mut scratch = Vec::new();
    let (mut blocked, mut held) = (0, 0);
    for _ in 0..300 {
        let mut space = Surroundings { world: &world, others: &[], scratch: &mut scratch };
        let out = body.step(Command { turn_rate: 0.0, speed: 1.35, toward: None }, 0.05, &mut space);
        blocked += u32::from(out.blocked);
        held += u32::from(out.held);
        let gap = world.clearance(body.pose().position, 5.0, &mut scratch) - body.radius();
        // Until it is first held it keeps its margin; held for a while, it may turn on the spot
        // as close as the room every frame keeps.
        let least = if held == 0 { a.clearance_m - 0.01 } else { strider::sim::animated::KEEP_ROOM_M - 1e-9 };
        assert!(gap >= least, "gap {gap} m at {:?}", body.pose());
    }
    assert_eq!(blocked, 0, "the last-resort guard had to hold the root");
    assert!(held > 0, "standing against the command counts as held");
    assert!(body.pose().position.x > 2.5, "stopped early at {:?}", body.pose());
}

#[test]
fn a_character_held_at_a_door_post_turns_away_from_it() {
    // Episode 18 of `strider run random:rooms --seed 4242`: the character comes to stand 4 cm
    // inside its margin at a door post, where every turn on the spot sways the pelvis toward
    // the post. Held still, it turns anyway (keeping the 2 cm every frame keeps) and reaches
    // the goal instead of standing there until the time runs out.
    let params = StepParameters { animation: Some(AnimationHandle(animation())), ..StepParameters::default() };
    let c = controller();
    let seed = strider::experiment::world_seed(4242, 18);
    let scenario = strider::maps::kind::generate(strider::maps::kind::WorldKind::Rooms, seed);
    let world = scenario.world();
    let e = run_episode(&scenario, &world, 0, &c, &params, 18, seed);
    assert!(e.record.reached && e.record.collisions == 0, "{:?}", e.record);
    assert!(e.record.min_clearance_m >= strider::sim::animated::KEEP_ROOM_M - 1e-9, "{:?}", e.record);
}

#[test]
fn the_learnt_policy_earns_its_place() {
    let a = animation();
    let learnt = evaluate(&a.db, &a.policy, Strategy::Learnt, 4000, 5);
    for s in [Strategy::Greedy, Strategy::Random, Strategy::Successor] {
        let other = evaluate(&a.db, &a.policy, s, 4000, 5);
        assert!(learnt.mean_return >= other.mean_return, "learnt {learnt:?} vs {} {other:?}", s.name());
    }
    assert!(a.policy.mirror_agreement(&a.db) >= 0.95, "{}", a.policy.mirror_agreement(&a.db));
}

#[test]
fn every_interval_reaches_a_stop_and_turns_on_the_spot_in_one_switch() {
    let db = builtin::database().unwrap();
    for (i, cands) in db.candidates.iter().enumerate() {
        let kinds: Vec<_> = cands.iter().map(|c| db.kinds[c.interval]).collect();
        assert!(kinds.iter().any(|k| k.stops || k.in_place), "interval {i} cannot stop");
        assert!(kinds.iter().any(|k| k.spot_turn > 0), "interval {i} cannot turn left on the spot");
        assert!(kinds.iter().any(|k| k.spot_turn < 0), "interval {i} cannot turn right on the spot");
        // The policy's actions share Eq. 3's weight; side steps and steps back come after them.
        let ranked = db.policy_actions[i];
        let sum: f64 = cands[..ranked].iter().map(|c| c.weight).sum();
        assert!((sum - 1.0).abs() < 1e-9);
        // (Within a side step, its own next interval is the successor.)
        assert!(db.kinds[i].shuffle != 0 || kinds[..ranked].iter().all(|k| k.shuffle == 0));
        assert!(kinds[ranked..].iter().all(|k| k.shuffle != 0));
        assert_eq!(ranked < cands.len(), db.kinds[i].ends_at_rest, "interval {i}");
    }
    // Every interval has its mirror, and mirrored intervals have mirrored candidates in order.
    for i in 0..db.intervals.len() {
        let m = db.mirror[i].unwrap_or_else(|| panic!("{} has no mirror", db.clips[db.intervals[i].clip].name));
        assert_eq!(db.mirror[m], Some(i));
        if m != i {
            let mirrored: Vec<Option<usize>> = db.candidates[i].iter().map(|c| db.mirror[c.interval]).collect();
            let there: Vec<Option<usize>> = db.candidates[m].iter().map(|c| Some(c.interval)).collect();
            assert_eq!(mirrored, there, "candidates of {i} and its mirror {m}");
        }
    }
}

#[test]
fn turning_ability_comes_from_the_database() {
    let a = animation();
    let body = AnimatedBody::new(a.clone(), Pose { position: DVec2::ZERO, yaw: 0.0 }, 0.3);
    // Turning on the spot reaches 90° a second, walking 60°, and no speed up to a jog is left
    // without an ability.
    assert!(body.turn_limit(0.0) >= 90f64.to_radians(), "{}", body.turn_limit(0.0));
    assert!(body.turn_limit(1.35) >= 60f64.to_radians(), "{}", body.turn_limit(1.35));
    assert!((0..=25).all(|k| body.turn_limit(0.1 * k as f64) > 0.5), "a speed without turning");
    // From standing, walking off at 1 m/s covers a metre within 2.5 s.
    let mut b = body.clone();
    for _ in 0..50 {
        b.step(Command { turn_rate: 0.0, speed: 1.0, toward: None }, 0.05, &mut OpenSpace);
    }
    assert!(b.pose().position.x > 1.0, "{:?}", b.pose());
}

#[test]
fn side_steps_and_steps_back_keep_the_feet_planted() {
    // From standing, each side step and step back in turn, warped as the look-ahead would warp
    // them toward a heading and speed they cannot meet: the body goes where the clip goes,
    // facing the same way, and no plant slides.
    let a = animation();
    let db = &a.db;
    // Escape `k` at the first standing switch point, then the natural successors.
    struct Escape(usize, bool);
    impl Chooser for Escape {
        fn choose(&mut self, db: &Database, at: &SwitchPoint) -> Choice {
            let (n, ranked) = (db.candidates[at.ending].len(), db.policy_actions[at.ending]);
            if self.1 || n == ranked {
                return Choice::from(0);
            }
            self.1 = true;
            let c = ranked + self.0.min(n - ranked - 1);
            let speed = 1.3 * db.intervals[db.candidates[at.ending][c].interval].speed;
            Choice { candidate: c, warp: at.warp_toward(db, c, 0.3, speed, &WarpLimits::default()) }
        }
    }
    let idle = (0..db.intervals.len()).find(|&i| db.clips[db.intervals[i].clip].name == "idle").unwrap();
    let escapes = db.candidates[idle].len() - db.policy_actions[idle];
    assert_eq!(escapes, 4, "side steps each way and steps back on each foot after standing");
    let mut shuffles = Vec::new();
    for k in 0..escapes {
        let mut player = Player::new(db, idle, Ground::default(), PlayerParams::default());
        let mut chooser = Escape(k, false);
        let start = player.ground();
        for _ in 0..150 {
            player.advance_frame(db, &mut chooser);
        }
        assert_eq!(player.metrics.sliding_plants, 0, "escape {k}: {:?}", player.metrics);
        let moved = start.to_local(player.ground());
        assert!(moved.yaw.abs() < 0.05 && (moved.x.hypot(moved.y) - 0.3).abs() < 0.1, "escape {k}: {moved:?}");
        shuffles.push(db.kinds[db.candidates[idle][db.policy_actions[idle] + k].interval].shuffle);
    }
    shuffles.sort();
    assert_eq!(shuffles, [-1, 1, 2, 2]);
}

#[test]
fn a_written_bvh_shows_the_motion_played() {
    // An episode in a building (turns, doors, stops, turns on the spot) recorded and written as
    // BVH, read back: every joint of every frame where it was played, legs solved by IK
    // included (the actor's hips cannot twist, so the IK must not twist them either).
    let params = StepParameters {
        animation: Some(AnimationHandle(animation())),
        record_motion: true,
        ..StepParameters::default()
    };
    let seed = strider::experiment::world_seed(31337, 2);
    let scenario = strider::maps::kind::generate(strider::maps::kind::WorldKind::Rooms, seed);
    let world = scenario.world();
    let e = run_episode(&scenario, &world, 0, &controller(), &params, 2, seed);
    assert!(e.motion.len() > 600, "{} frames", e.motion.len());
    let db = &animation().db;
    let mut joints = db.skeleton.joints().to_vec();
    joints[0].offset = DVec3::ZERO;
    let skeleton = strider::anim::Skeleton::new(joints).unwrap();
    let clip = strider::anim::Clip { name: "e".into(), frame_time: 1.0 / 60.0, frames: e.motion.clone() };
    let text = bvh::write(&skeleton, &clip, &BvhOptions::default());
    let read = bvh::parse(&text, "e.bvh", "e", &BvhOptions::default()).unwrap();
    let (mut played, mut shown) = (Vec::new(), Vec::new());
    let mut worst = (0.0f64, 0, String::new());
    for (k, (a, b)) in e.motion.iter().zip(&read.clip.frames).enumerate() {
        skeleton.globals(a, &mut played);
        read.skeleton.globals(b, &mut shown);
        for (j, joint) in skeleton.joints().iter().enumerate() {
            let d =
                played[j].0.distance(shown[j].0).max(skeleton.tip(&played, j).distance(read.skeleton.tip(&shown, j)));
            if d > worst.0 {
                worst = (d, k, joint.name.clone());
            }
        }
    }
    assert!(worst.0 < 1e-3, "{} m off at frame {} ({})", worst.0, worst.1, worst.2);
}
