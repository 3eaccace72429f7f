//! The upper body among obstacles (seed 002 §5): generated scenes of every kind the upper body
//! meets — overhead bars to duck under, chest-height shelves narrower than the shoulders, bars
//! too low to duck (walked round), lamps at arm height over a table beside the way, kerbs to
//! step over — walked by the character through
//! `strider run --bvh-out`, and every bone of the exported motion checked against the map's
//! obstacles by forward kinematics over the BVH file and geometry of this test's own.

mod common;

use common::strider;

use std::path::{Path, PathBuf};

use glam::{DVec2, DVec3};
use rand_chacha::ChaCha8Rng;
use rand_core::{RngCore, SeedableRng};
use strider::anim::bvh::{self, BvhOptions};

/// An obstacle of a generated scene: a box (centre, size, no rotation) or a cylinder, with its
/// vertical extent.
#[derive(Debug, Clone, Copy)]
enum Solid {
    Box { c: DVec2, w: f64, h: f64, z: (f64, f64) },
    Cylinder { c: DVec2, r: f64, z: (f64, f64) },
}

impl Solid {
    /// More than a millimetre inside (a sole resting on a kerb's top touches it), by this
    /// test's own arithmetic.
    fn contains(&self, p: DVec3) -> bool {
        const E: f64 = 1e-3;
        let within = |(lo, hi): (f64, f64)| p.z > lo + E && p.z < hi - E;
        match *self {
            Solid::Box { c, w, h, z } => {
                (p.x - c.x).abs() < w / 2.0 - E && (p.y - c.y).abs() < h / 2.0 - E && within(z)
            }
            Solid::Cylinder { c, r, z } => p.truncate().distance(c) < r - E && within(z),
        }
    }

    fn line(&self) -> String {
        match *self {
            Solid::Box { c, w, h, z } => format!("z_extent {} {}\nbox {} {} {} {}\n", z.0, z.1, c.x, c.y, w, h),
            Solid::Cylinder { c, r, z } => format!("z_extent {} {}\ncyl {} {} {}\n", z.0, z.1, c.x, c.y, r),
        }
    }
}

/// A generated scene: its obstacles, ponds (holes in the ground: centre, radius), start and
/// goal.
struct Scene {
    name: String,
    solids: Vec<Solid>,
    ponds: Vec<(DVec2, f64)>,
    goal: DVec2,
}

impl Scene {
    fn new(name: impl Into<String>, solids: Vec<Solid>, goal: DVec2) -> Scene {
        Scene { name: name.into(), solids, ponds: Vec::new(), goal }
    }

    fn text(&self) -> String {
        let mut t = format!("# {}\nstart -1 0 0\ngoal {} {}\n", self.name, self.goal.x, self.goal.y);
        for s in &self.solids {
            t += &s.line();
        }
        for (c, r) in &self.ponds {
            t += &format!("hole cyl {} {} {}\n", c.x, c.y, r);
        }
        t
    }

    /// A point of a bone is wrong where it is inside an obstacle, or in a pond below the ground.
    fn wrong(&self, p: DVec3) -> bool {
        self.solids.iter().any(|s| s.contains(p))
            || self.ponds.iter().any(|(c, r)| p.z < -1e-3 && p.truncate().distance(*c) < r - 1e-3)
    }
}

/// A corridor of full-height walls from x = 1 to x = 1 + `length`, `width` wide inside.
fn corridor(length: f64, width: f64) -> Vec<Solid> {
    let y = width / 2.0 + 0.1;
    let c = 1.0 + length / 2.0;
    [y, -y].map(|y| Solid::Box { c: DVec2::new(c, y), w: length, h: 0.2, z: (0.0, 2.0) }).to_vec()
}

/// The same corridor as the only way through a closed room (x from -1.5 to `length` + 3.5, y
/// from -3 to 3): walls across the room at both of its ends.
fn building(length: f64, width: f64) -> Vec<Solid> {
    let wall = |c: DVec2, w: f64, h: f64| Solid::Box { c, w, h, z: (0.0, 2.0) };
    let (x0, x1) = (-1.5, length + 3.5);
    let mut s = corridor(length, width);
    s.push(wall(DVec2::new((x0 + x1) / 2.0, 3.1), x1 - x0, 0.2));
    s.push(wall(DVec2::new((x0 + x1) / 2.0, -3.1), x1 - x0, 0.2));
    s.push(wall(DVec2::new(x0 - 0.1, 0.0), 0.2, 6.4));
    s.push(wall(DVec2::new(x1 + 0.1, 0.0), 0.2, 6.4));
    let inner = width / 2.0;
    let span = 3.0 - inner;
    for x in [1.1, 0.9 + length] {
        for side in [1.0, -1.0] {
            s.push(wall(DVec2::new(x, side * (inner + span / 2.0)), 0.2, span));
        }
    }
    s
}

/// Chest-height shelves from both walls of a 0.84 m corridor at `x` (their undersides 1.0–1.2 m
/// up, 0.6–1.4 m long), leaving 0.30–0.34 m between them.
fn shelves(rng: &mut ChaCha8Rng, x: f64) -> Vec<Solid> {
    let gap = uniform(rng, 0.30, 0.34);
    let length = uniform(rng, 0.6, 1.4);
    let depth = 0.42 - gap / 2.0;
    let z = (uniform(rng, 1.0, 1.2), 1.8);
    [1.0, -1.0]
        .map(|side| Solid::Box { c: DVec2::new(x, side * (gap / 2.0 + depth / 2.0)), w: length, h: depth, z })
        .to_vec()
}

/// A number drawn evenly from `[lo, hi]`.
fn uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

/// Scene `k` of each kind, drawn from a fixed stream.
fn generate(kind: &str, k: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0000 + k);
    let name = format!("{kind}_{k}");
    match kind {
        // An overhead bar across a corridor, its underside 1.45–1.65 m up.
        "bar" => {
            let mut solids = building(6.0, 1.2);
            let z = uniform(&mut rng, 1.45, 1.65);
            let x = uniform(&mut rng, 3.0, 5.0);
            solids.push(Solid::Box {
                c: DVec2::new(x, 0.0),
                w: uniform(&mut rng, 0.05, 0.15),
                h: 1.2,
                z: (z, z + 0.1),
            });
            Scene::new(name, solids, DVec2::new(8.0, 0.0))
        }
        // Shelves at chest height from both walls of a corridor, their undersides 1.0–1.2 m up,
        // leaving 0.30–0.34 m between.
        "shelves" => {
            let mut solids = building(6.0, 0.84);
            let x = uniform(&mut rng, 3.0, 5.0);
            solids.extend(shelves(&mut rng, x));
            Scene::new(name, solids, DVec2::new(8.0, 0.0))
        }
        // The same shelves standing free in the open (below the duck height: walked round).
        "open_shelves" => {
            let x = uniform(&mut rng, 3.0, 5.0);
            let y = uniform(&mut rng, -0.5, 0.5);
            let solids = shelves(&mut rng, x)
                .into_iter()
                .map(|s| match s {
                    Solid::Box { c, w, h, z } => Solid::Box { c: c + DVec2::new(0.0, y), w, h, z },
                    other => other,
                })
                .collect();
            Scene::new(name, solids, DVec2::new(8.0, 0.0))
        }
        // A corridor with an overhead bar to duck under and shelves to twist between, in either
        // order.
        "mixed" => {
            let mut solids = building(6.0, 0.84);
            let (first, second) = (uniform(&mut rng, 2.2, 3.0), uniform(&mut rng, 4.6, 5.4));
            let (bar_x, shelves_x) = if rng.next_u64() % 2 == 0 { (first, second + 0.4) } else { (second, first) };
            let z = uniform(&mut rng, 1.45, 1.65);
            solids.push(Solid::Box {
                c: DVec2::new(bar_x, 0.0),
                w: uniform(&mut rng, 0.05, 0.15),
                h: 0.84,
                z: (z, z + 0.1),
            });
            solids.extend(shelves(&mut rng, shelves_x));
            Scene::new(name, solids, DVec2::new(8.0, 0.0))
        }
        // A pond wider than the longest step (radius 1.0–1.6 m) on the straight way in the
        // open: walked round, no foot in it.
        "pond" => {
            let r = uniform(&mut rng, 1.0, 1.6);
            let c = DVec2::new(uniform(&mut rng, 3.5, 4.5), uniform(&mut rng, -0.4, 0.4));
            Scene { ponds: vec![(c, r)], ..Scene::new(name, Vec::new(), DVec2::new(8.0, 0.0)) }
        }
        // A bar 0.8–1.0 m up, too low to duck: it blocks the straight way, to be walked round.
        "low_bar" => {
            let z = uniform(&mut rng, 0.8, 1.0);
            let x = uniform(&mut rng, 3.0, 5.0);
            let y = uniform(&mut rng, -1.0, 0.0);
            let solids = vec![Solid::Box { c: DVec2::new(x, y), w: 0.1, h: 4.0, z: (z, z + 0.1) }];
            Scene::new(name, solids, DVec2::new(8.0, 0.0))
        }
        // A bar 1.05–1.25 m up in the open: too high to step over, too low to duck under (the
        // actor ducks to about 1.31 m), so it is walked round.
        "mid_bar" => {
            let z = uniform(&mut rng, 1.05, 1.25);
            let x = uniform(&mut rng, 3.0, 5.0);
            let y = uniform(&mut rng, -1.0, 0.0);
            let solids = vec![Solid::Box { c: DVec2::new(x, y), w: 0.1, h: 4.0, z: (z, z + 0.1) }];
            Scene::new(name, solids, DVec2::new(8.0, 0.0))
        }
        // A table beside the way with lamps hanging over its edge at arm height.
        "table" => {
            let edge = uniform(&mut rng, 0.5, 0.6);
            let mut solids = vec![Solid::Box { c: DVec2::new(4.0, edge + 0.4), w: 3.0, h: 0.8, z: (0.0, 0.75) }];
            for x in [3.0, 5.0] {
                let r = uniform(&mut rng, 0.12, 0.18);
                let z = uniform(&mut rng, 1.0, 1.1);
                solids.push(Solid::Cylinder { c: DVec2::new(x, edge), r, z: (z, z + 0.3) });
            }
            Scene::new(name, solids, DVec2::new(8.0, 0.0))
        }
        // Kerbs across the way, 0.08–0.2 m high, to step over or onto.
        "kerbs" => {
            let mut solids = Vec::new();
            let mut x = 1.5;
            for _ in 0..3 {
                x += uniform(&mut rng, 1.0, 2.0);
                let w = uniform(&mut rng, 0.15, 0.4);
                solids.push(Solid::Box { c: DVec2::new(x, 0.0), w, h: 3.0, z: (0.0, uniform(&mut rng, 0.08, 0.2)) });
            }
            Scene::new(name, solids, DVec2::new(x + 2.0, 0.0))
        }
        _ => unreachable!(),
    }
}

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every bone of every frame of `file`, as points 1 cm apart from joint to child joint (and to
/// the end sites: the top of the head, the hands, the toes).
fn bone_points(file: &bvh::Bvh, mut each: impl FnMut(usize, &str, DVec3)) {
    let sk = &file.skeleton;
    let mut g = Vec::new();
    for (k, pose) in file.clip.frames.iter().enumerate() {
        sk.globals(pose, &mut g);
        bones_of(sk, &g, |name, p| each(k, name, p));
    }
}

/// The bones of one frame (`g`, the skeleton's global joints), as [`bone_points`] gives them.
fn bones_of(sk: &strider::anim::Skeleton, g: &[(DVec3, glam::DQuat)], mut each: impl FnMut(&str, DVec3)) {
    for (i, j) in sk.joints().iter().enumerate() {
        let mut ends = Vec::new();
        if let Some(p) = j.parent {
            ends.push((g[p].0, g[i].0));
        }
        if j.end_site.is_some() {
            ends.push((g[i].0, sk.tip(g, i)));
        }
        for (a, b) in ends {
            let n = ((a.distance(b) / 0.01).ceil() as usize).max(1);
            for s in 0..=n {
                each(&j.name, a.lerp(b, s as f64 / n as f64));
            }
        }
    }
}

/// The bar of issue 12: on generated scenes of every kind the character reaches the goal and
/// no bone of the exported motion is ever inside an obstacle.
#[test]
fn no_bone_of_the_exported_motion_enters_an_obstacle() {
    let out = dir("upper_body_scenes");
    let mut bent = 0.0f64;
    let mut twisted = 0.0f64;
    // Scenes 0, 1, 2 of each kind, or `STRIDER_UPPER_SCENES` of them from `STRIDER_UPPER_FIRST`
    // for a longer run on other scenes.
    let env = |name: &str, default: u64| std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default);
    let (first, per_kind) = (env("STRIDER_UPPER_FIRST", 0), env("STRIDER_UPPER_SCENES", 3));
    let mut failed = Vec::new();
    for kind in ["bar", "shelves", "open_shelves", "mixed", "low_bar", "mid_bar", "table", "kerbs", "pond"] {
        for k in first..first + per_kind {
            let scene = generate(kind, k);
            let map = out.join(format!("{}.txt", scene.name));
            std::fs::write(&map, scene.text()).unwrap();
            let bvh_dir = out.join(&scene.name);
            let run =
                strider(&["run", map.to_str().unwrap(), "--format", "json", "--bvh-out", bvh_dir.to_str().unwrap()]);
            let text = String::from_utf8_lossy(&run.stdout);
            let json: serde_json::Value = serde_json::from_str(&text)
                .unwrap_or_else(|e| panic!("{}: {e}\n{}", scene.name, String::from_utf8_lossy(&run.stderr)));
            let record = &json["episodes"][0];
            let time = record["time_s"].as_f64().unwrap_or(f64::NAN);
            eprintln!(
                "{}: {} in {time:.1} s, collisions {}, bend {:.0}°, twist {:.0}°, least clearance {}, refused {}",
                scene.name,
                if record["reached"] == true { "reached" } else { "NOT reached" },
                record["collisions"],
                record["max_waist_bend_deg"].as_f64().unwrap_or(0.0),
                record["max_waist_twist_deg"].as_f64().unwrap_or(0.0),
                record["upper_body_min_clearance_m"],
                record["upper_body_refused_steps"]
            );
            if record["reached"] != true || record["collisions"] != 0 || !run.status.success() {
                failed.push(format!(
                    "{}: reached {}, collisions {}",
                    scene.name, record["reached"], record["collisions"]
                ));
            }
            bent = bent.max(record["max_waist_bend_deg"].as_f64().unwrap_or(0.0));
            twisted = twisted.max(record["max_waist_twist_deg"].as_f64().unwrap_or(0.0));
            let path = bvh_dir.join("episode_0.bvh");
            let bvh_text = std::fs::read_to_string(&path).unwrap();
            let file = bvh::parse(&bvh_text, "episode_0.bvh", "episode_0", &BvhOptions::default()).unwrap();
            assert!(file.clip.frames.len() > 100, "{}", scene.name);
            let mut inside = None;
            bone_points(&file, |frame, joint, p| {
                if inside.is_none() && scene.wrong(p) {
                    inside = Some((frame, joint.to_string(), p));
                }
            });
            if let Some(at) = inside {
                failed.push(format!("{}: a bone inside an obstacle or a pond at {at:?}", scene.name));
            }
        }
    }
    assert!(failed.is_empty(), "{} failed:\n{}", failed.len(), failed.join("\n"));
    // The scenes asked for both a deep bend (the bars) and a twist (the shelves).
    assert!(bent > 45.0, "deepest bend {bent}°");
    assert!(twisted > 45.0, "largest twist {twisted}°");
}

/// The check above is not blind: the database's motion, with no upper-body planning, walked
/// under a bar at 1.5 m puts the head inside it.
#[test]
fn the_check_sees_a_head_through_a_bar() {
    let scene = Scene::new("open_corridor", corridor(6.0, 1.2), DVec2::new(8.0, 0.0));
    let out = dir("upper_body_blind");
    let map = out.join("open.txt");
    std::fs::write(&map, scene.text()).unwrap();
    let run = strider(&["run", map.to_str().unwrap(), "--bvh-out", out.join("bvh").to_str().unwrap()]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let text = std::fs::read_to_string(out.join("bvh/episode_0.bvh")).unwrap();
    let file = bvh::parse(&text, "episode_0.bvh", "episode_0", &BvhOptions::default()).unwrap();
    let bar = Solid::Box { c: DVec2::new(4.0, 0.0), w: 0.1, h: 1.2, z: (1.5, 1.6) };
    let mut hits = 0;
    bone_points(&file, |_, _, p| hits += usize::from(bar.contains(p)));
    assert!(hits > 0);
}

/// Without anything the upper body can touch the motion is the database's, bit for bit: a bar
/// high above the head changes nothing.
#[test]
fn a_bar_out_of_reach_changes_nothing() {
    let out = dir("upper_body_unchanged");
    let mut motions = Vec::new();
    for (name, extra) in [("plain", ""), ("high_bar", "z_extent 2.4 2.5\nbox 4 0 0.1 1.2\n")] {
        let scene = Scene::new(name, corridor(6.0, 1.2), DVec2::new(8.0, 0.0));
        let map = out.join(format!("{name}.txt"));
        std::fs::write(&map, scene.text() + extra).unwrap();
        let run = strider(&["run", map.to_str().unwrap(), "--bvh-out", out.join(name).to_str().unwrap()]);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        motions.push(std::fs::read_to_string(out.join(name).join("episode_0.bvh")).unwrap());
    }
    assert_eq!(motions[0], motions[1]);
}

/// `render --side --front` writes strips of the moments the upper body moved for obstacles
/// (what they show is checked in `render::sim_view`); both are refused before any work where
/// there is nothing to show or with the disc.
#[test]
fn the_strips_show_the_bend_and_the_twist() {
    let out = dir("upper_body_strips");
    let frames = out.join("frames");
    let r = strider(&[
        "render",
        "maps/upper_all.rhai",
        "--out",
        frames.to_str().unwrap(),
        "--every",
        "0",
        "--side",
        "--front",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    for file in ["upper_side.png", "upper_front.png", "final.png"] {
        assert_eq!(&std::fs::read(frames.join(file)).unwrap()[1..4], b"PNG", "{file}");
    }
    let refused = out.join("refused");
    for args in [
        vec!["render", "maps/sparse.rhai", "--out", refused.to_str().unwrap(), "--front"],
        vec!["render", "maps/upper_all.rhai", "--out", refused.to_str().unwrap(), "--front", "--body", "disc"],
        vec!["render", "maps/sparse.rhai", "--out", refused.to_str().unwrap(), "--side"],
    ] {
        let o = strider(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let flag = args.iter().find(|a| a.starts_with("--") && *a != &"--out" && *a != &"--body").unwrap();
        assert!(String::from_utf8_lossy(&o.stderr).contains(flag), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(!refused.exists(), "{args:?} wrote nothing");
    }
}

/// One body for planning and for what is shown: on motions exported with `--bvh-out` (a bar to
/// duck under, shelves to twist between), the capsules posed from each frame of the file hang
/// on that frame's joints — each capsule's ends are joints or end sites of the file (the head's
/// top end aside: it is the end site less the head's radius) — and every bone of the file lies
/// inside one of them.
#[test]
fn the_capsules_are_the_bones_of_the_exported_motion() {
    use strider::anim::body::{Part, UpperBody};
    let out = dir("upper_body_capsules");
    for kind in ["bar", "shelves"] {
        let scene = generate(kind, 0);
        let map = out.join(format!("{}.txt", scene.name));
        std::fs::write(&map, scene.text()).unwrap();
        let bvh_dir = out.join(&scene.name);
        let run = strider(&["run", map.to_str().unwrap(), "--bvh-out", bvh_dir.to_str().unwrap()]);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let text = std::fs::read_to_string(bvh_dir.join("episode_0.bvh")).unwrap();
        let file = bvh::parse(&text, "episode_0.bvh", "episode_0", &BvhOptions::default()).unwrap();
        let sk = &file.skeleton;
        let body = UpperBody::of(sk).expect("the exported skeleton is the actor's");
        let (mut g, mut caps) = (Vec::new(), Vec::new());
        let mut moved = false;
        let mut bones = Vec::new();
        for (k, pose) in file.clip.frames.iter().enumerate() {
            sk.globals(pose, &mut g);
            body.capsules(pose, &mut caps);
            assert_eq!(caps.len(), 16);
            let joints: Vec<DVec3> = (0..g.len()).flat_map(|i| [g[i].0, sk.tip(&g, i)]).collect();
            let on_a_joint = |p: DVec3| joints.iter().any(|j| j.distance(p) < 1e-6);
            for &(part, c) in &caps {
                assert!(on_a_joint(c.a), "{}: frame {k}: {part:?} starts off the joints", scene.name);
                assert!(
                    part == Part::Head || on_a_joint(c.b),
                    "{}: frame {k}: {part:?} ends off the joints",
                    scene.name
                );
            }
            bones.clear();
            bones_of(sk, &g, |name, p| bones.push((name.to_string(), p)));
            for (name, p) in &bones {
                let inside = caps.iter().any(|(_, c)| {
                    let (ab, ap) = (c.b - c.a, *p - c.a);
                    let t = if ab.length_squared() > 0.0 {
                        (ap.dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    p.distance(c.a + ab * t) <= c.radius + 1e-9
                });
                assert!(inside, "{}: frame {k}: a point of {name}'s bone at {p} is in no capsule", scene.name);
            }
            moved |= g[0].0.x > 3.0;
        }
        assert!(moved, "{}: the character walked", scene.name);
    }
}

/// A bar across a corridor lower than the character ducks under and higher than it steps over:
/// walked round where there is a way round (the corridor's outside), and where there is none
/// (the corridor is the only way through a closed room) the episode ends at once with the
/// reason, naming the bar.
#[test]
fn a_bar_with_no_way_round_ends_the_episode_with_the_reason() {
    let out = dir("upper_body_no_way");
    let bar = Solid::Box { c: DVec2::new(4.0, 0.0), w: 0.1, h: 1.2, z: (1.1, 1.2) };
    for (name, mut solids, way_round) in [("open", corridor(6.0, 1.0), true), ("closed", building(6.0, 1.0), false)] {
        solids.push(bar);
        let scene = Scene::new(name, solids, DVec2::new(8.0, 0.0));
        let map = out.join(format!("{name}.txt"));
        std::fs::write(&map, scene.text()).unwrap();
        let run =
            strider(&["run", map.to_str().unwrap(), "--format", "json", "--bvh-out", out.join(name).to_str().unwrap()]);
        let json: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
        let record = &json["episodes"][0];
        assert_eq!(record["reached"], way_round, "{name}: {record}");
        assert_eq!(record["collisions"], 0, "{name}: {record}");
        if way_round {
            assert!(record["refusal"].is_null(), "{name}: {record}");
            let text = std::fs::read_to_string(out.join(name).join("episode_0.bvh")).unwrap();
            let file = bvh::parse(&text, "episode_0.bvh", "episode_0", &BvhOptions::default()).unwrap();
            let mut hits = 0;
            bone_points(&file, |_, _, p| hits += usize::from(bar.contains(p)));
            assert_eq!(hits, 0, "{name}: a bone in the bar");
        } else {
            let why = record["refusal"].as_str().unwrap_or_else(|| panic!("{name}: no reason: {record}"));
            assert!(why.contains("(4.00, 0.00)") && why.contains("underside 1.10 m"), "{why}");
            assert_eq!(record["steps"], 0, "{name}: {record}");
            assert!(!run.status.success(), "a run whose episode is refused is not clean");
            assert!(
                String::from_utf8_lossy(&run.stderr).contains("no way round"),
                "{}",
                String::from_utf8_lossy(&run.stderr)
            );
        }
    }
}

/// The shipped upper-body scenes: the goal reached and no bone of the upper body ever inside an
/// obstacle (the simulation's own count, over the capsules' axes, `upper_body_collisions`).
#[test]
fn the_shipped_upper_body_scenes_keep_every_bone_clear() {
    let mut failed = Vec::new();
    for name in ["upper_all", "upper_low_bar", "upper_overhead_bar", "upper_shelves", "upper_table"] {
        let map = format!("maps/{name}.rhai");
        let run = strider(&["run", &map, "--format", "json"]);
        let json: serde_json::Value = serde_json::from_slice(&run.stdout)
            .unwrap_or_else(|e| panic!("{name}: {e}\n{}", String::from_utf8_lossy(&run.stderr)));
        let record = &json["episodes"][0];
        if record["reached"] != true || record["collisions"] != 0 || record["upper_body_collisions"] != 0 {
            failed.push(format!(
                "{name}: reached {}, collisions {}, upper body {}",
                record["reached"], record["collisions"], record["upper_body_collisions"]
            ));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
