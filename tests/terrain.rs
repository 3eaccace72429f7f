//! Terrain in maps (seed 002 §3.2): the text and Rhai map formats, the ground profile along a
//! path, and the animated character walking over the shipped terrain scenes.

use glam::DVec2;
use strider::maps::text;
use strider::script::{Limits, ScriptLog, load_scenario};
use strider::world::terrain::FeatureKind;

const TERRAIN_TEXT: &str = "\
start 0 0
goal 20 0
platform 0.3 box 3 0 1 2
hole cyl 6 0 0.5
slope 0 0.4 9 0 2 2 0.1
stairs 0.4 0 3 12 0 3 2
platform 0.1 poly 14 -1 15 -1 15 1 14 1
z_extent 0 0.2
box 17 0 0.5 2
";

#[test]
fn text_worlds_carry_terrain_and_write_it_back() {
    let s = text::parse(TERRAIN_TEXT, "t.txt").unwrap();
    let kinds: Vec<FeatureKind> = s.terrain.features().iter().map(|f| f.kind).collect();
    assert_eq!(kinds.len(), 5);
    assert_eq!(kinds[0], FeatureKind::Platform { z_m: 0.3 });
    assert_eq!(kinds[1], FeatureKind::Hole);
    assert_eq!(kinds[3], FeatureKind::Stairs { z0_m: 0.4, z1_m: 0.0, treads: 3 });
    let back = text::parse(&text::write(&s), "t.txt").unwrap();
    assert_eq!(back.terrain, s.terrain);
    assert_eq!(back.obstacles, s.obstacles);
    // The low box is ground in the world, not a wall.
    let w = s.world();
    assert!(w.obstacles().is_empty());
    assert_eq!(w.terrain.ground(DVec2::new(17.0, 0.0)), Some(0.2));
    assert_eq!(w.terrain.ground(DVec2::new(6.0, 0.0)), None);
    assert!((w.terrain.height(DVec2::new(9.0, 0.0)) - 0.2).abs() < 1e-12);
}

#[test]
fn bad_terrain_lines_are_located() {
    let cases = [
        ("start 0 0\ngoal 5 0\nplatform 0.2\n", (3, 13), "needs a shape"),
        ("start 0 0\ngoal 5 0\nplatform x box 1 1 1 1\n", (3, 10), "expected a number"),
        ("start 0 0\ngoal 5 0\nhole tri 1 1 1\n", (3, 6), "expected a shape"),
        ("start 0 0\ngoal 5 0\nstairs 0 1 2.5 3 0 1 1\n", (3, 12), "whole number of treads"),
        ("start 0 0\ngoal 5 0\nstairs 0 1 0 3 0 1 1\n", (3, 12), "whole number of treads"),
        ("start 0 0\ngoal 5 0\nslope 0 1 3 0 -1 1\n", (3, 15), "box width must be positive"),
        ("start 0 0\ngoal 5 0\nslope 0 1 3 0 1\n", (3, 16), "needs at least 6"),
        ("start 0 0\ngoal 5 0\nhole box 1 1 0 1\n", (3, 14), "box width"),
        ("start 0 0\ngoal 5 0\nfootsteps step_max_m\n", (3, 11), "pairs of a parameter"),
        ("start 0 0\ngoal 5 0\nfootsteps step_max_m 0.8 stride 1\n", (3, 26), "unknown parameter `stride`"),
        ("start 0 0\ngoal 5 0\nfootsteps intervals 2.5\n", (3, 11), "whole number"),
        ("start 0 0\ngoal 5 0\nfootsteps step_min_m 2\n", (3, 1), "footsteps:"),
    ];
    for (src, at, needle) in cases {
        let e = text::parse(src, "w.txt").expect_err(needle);
        assert_eq!((e.line, e.col), at, "{needle}: {e}");
        assert!(e.message.contains(needle), "{needle}: {e}");
    }
}

#[test]
fn text_worlds_carry_footstep_parameters_and_write_them_back() {
    let s = text::parse("start 0 0\ngoal 5 0\nfootsteps step_max_m 0.8 window_steps 2\n", "w.txt").unwrap();
    assert_eq!((s.footsteps.step_max_m, s.footsteps.window_steps), (0.8, 2));
    let back = text::parse(&text::write(&s), "back.txt").unwrap();
    assert_eq!((back.footsteps.step_max_m, back.footsteps.window_steps), (0.8, 2));
    assert_eq!(text::parse("start 0 0\ngoal 5 0\n", "d.txt").unwrap().footsteps, Default::default());
}

#[test]
fn rhai_maps_carry_terrain() {
    let src = r#"
        let m = world("t");
        m.start(0.0, 0.0, 0.0);
        m.goal(10.0, 0.0, 0.5);
        m.platform_box(3.0, 0.0, 1.0, 2.0, 0.0, 0.3);
        m.hole_cylinder(6.0, 0.0, 0.5);
        m.slope(8.0, 0.0, 2.0, 2.0, 0.0, 0.0, 0.4);
        m.stairs(11.0, 0.0, 3.0, 2.0, 0.0, 0.4, 0.0, 3);
        m.platform(0.1, [[14, -1], [15, -1], [15, 1]]);
        m.hole_box(16.0, 0.0, 1.0, 1.0, 0.0);
        m.platform_cylinder(16.0, 0.0, 0.2, 0.05);
        m.hole([[18, -1], [19, -1], [19, 1]]);
        m
    "#;
    let s = load_scenario(src, "t.rhai", Limits::default(), &ScriptLog::new()).unwrap();
    assert_eq!(s.terrain.features().len(), 8);
    assert_eq!(s.world().terrain.ground(DVec2::new(16.0, 0.0)), Some(0.05));
    let bad = r#"
        let m = world("t");
        m.start(0.0, 0.0, 0.0);
        m.goal(10.0, 0.0, 0.5);
        m.stairs(11.0, 0.0, 3.0, 2.0, 0.0, 0.4, 0.0, 0);
        m
    "#;
    let e = load_scenario(bad, "t.rhai", Limits::default(), &ScriptLog::new()).unwrap_err();
    assert_eq!(e.line, 5, "{e}");
    assert!(e.message.contains("treads"), "{e}");
}

#[test]
fn footstep_parameters_come_from_the_map_script() {
    let base = "let m = world(\"t\");\nm.start(0.0, 0.0, 0.0);\nm.goal(10.0, 0.0, 0.5);\n";
    let ok = format!("{base}m.footsteps(#{{ window_steps: 2, intervals: 8, step_max_m: 0.8 }});\nm\n");
    let s = load_scenario(&ok, "t.rhai", Limits::default(), &ScriptLog::new()).unwrap();
    assert_eq!((s.footsteps.window_steps, s.footsteps.intervals, s.footsteps.step_max_m), (2, 8, 0.8));
    assert_eq!(s.world().footsteps, s.footsteps);
    for (bad, needle) in [
        ("#{ intervals: 0 }", "intervals = 0"),
        ("#{ window_steps: 0 }", "window_steps = 0"),
        ("#{ step_min_m: 0.9, step_max_m: 0.3, step_init_m: 0.5 }", "inverted step limits"),
        ("#{ stride: 1.0 }", "unknown parameter `stride`"),
    ] {
        let src = format!("{base}m.footsteps({bad});\nm\n");
        let e = load_scenario(&src, "t.rhai", Limits::default(), &ScriptLog::new()).unwrap_err();
        assert_eq!(e.line, 4, "{e}");
        assert!(e.message.contains(needle), "{needle}: {e}");
    }
}

#[test]
fn the_profile_along_a_path_is_the_terrain_under_it() {
    let s = text::parse(TERRAIN_TEXT, "t.txt").unwrap();
    let w = s.world();
    let p = w.terrain.profile(DVec2::ZERO, DVec2::X, -1.0, 20.0).unwrap();
    // Every piece's height is the terrain's at its points, and gaps are holes.
    for x in (0..2100).map(|i| -1.0 + i as f64 * 0.01) {
        let here = w.terrain.ground(DVec2::new(x, 0.0));
        let on = p.height_at(x);
        let same = match (here, on) {
            (Some(a), Some(b)) => (a - b).abs() < 1e-9,
            (a, b) => a == b,
        };
        // At an edge (a vertical step, the rim of a hole) the two may take either side.
        let edge = p.pieces().iter().any(|q| (q.x0_m - x).abs() < 1e-6 || (q.x1_m - x).abs() < 1e-6);
        assert!(same || edge, "x = {x}: terrain {here:?}, profile {on:?}");
    }
}

mod character {
    use std::sync::Arc;

    use strider::experiment::run_episode;
    use strider::scenario::Scenario;
    use strider::script::{Limits, ScriptLog, load_scenario};
    use strider::sim::{AnimationHandle, LayeredController, Simulation, StepParameters};

    fn params() -> StepParameters {
        StepParameters {
            animation: Some(AnimationHandle(Arc::new(strider::builtin::animation().unwrap()))),
            ..StepParameters::default()
        }
    }

    fn controller() -> LayeredController {
        strider::builtin::controller().expect("built-in rules")
    }

    fn map(src: &str, name: &str) -> Scenario {
        load_scenario(src, name, Limits::default(), &ScriptLog::new()).unwrap()
    }

    const SCENES: [(&str, &str, f64); 4] = [
        ("terrain_stairs.rhai", include_str!("../maps/terrain_stairs.rhai"), 8.4),
        ("terrain_slope.rhai", include_str!("../maps/terrain_slope.rhai"), 11.0),
        ("terrain_stepping_stones.rhai", include_str!("../maps/terrain_stepping_stones.rhai"), 6.0),
        ("terrain_fig8_trap.rhai", include_str!("../maps/terrain_fig8_trap.rhai"), 3.6),
    ];

    /// The bar of issue 11: the character crosses every shipped terrain scene with zero
    /// collisions and zero invalid footholds, deterministically.
    #[test]
    fn the_character_crosses_every_shipped_terrain_scene() {
        let (p, c) = (params(), controller());
        for (name, src, beyond_m) in SCENES {
            let s = map(src, name);
            let w = s.world();
            assert!(!w.terrain.is_flat(), "{name}");
            let e = run_episode(&s, &w, 0, &c, &p, 0, 1);
            let r = &e.record;
            assert!(r.reached, "{name}: {r:?}");
            assert_eq!(r.collisions, 0, "{name}");
            assert_eq!(r.invalid_footholds, Some(0), "{name}");
            assert!(r.footsteps_planned.unwrap() >= 8, "{name}: {r:?}");
            assert!(e.trail.iter().any(|q| q.x > beyond_m), "{name}: crossed the terrain");
            assert_eq!(run_episode(&s, &w, 0, &c, &p, 0, 1).trail, e.trail, "{name}: deterministic");
        }
    }

    /// The highest ground under the segment `a`–`b` (plan view), sampled every 5 mm.
    fn ground_under(terrain: &strider::world::Terrain, a: glam::DVec3, b: glam::DVec3) -> (f64, glam::DVec3) {
        let n = ((a.truncate().distance(b.truncate()) / 0.005).ceil() as usize).max(1);
        (0..=n)
            .map(|k| a.lerp(b, k as f64 / n as f64))
            .map(|p| (p.z - terrain.height(p.truncate()), p))
            .fold((f64::INFINITY, a), |m, x| if x.0 < m.0 { x } else { m })
    }

    /// The played soles keep above the ground on maps: in every frame of the recorded motion,
    /// every point of each sole from heel to toe is above the terrain under it (kerb and stair
    /// edges included), within a millimetre — shipped terrain scenes and kerbs 0.10–0.20 m.
    #[test]
    fn played_soles_stay_above_every_edge_they_pass() {
        use strider::anim::actor::{HEEL_POINT, LEFT_FOOT, RIGHT_FOOT, TOE_POINT};
        let (mut p, c) = (params(), controller());
        p.record_motion = true;
        let kerbs: Vec<(String, String)> = [0.1, 0.15, 0.2]
            .iter()
            .map(|h| {
                let src = format!(
                    r#"let m = world("kerb");
                    m.start(0.0, 0.0, 0.0);
                    m.goal(7.0, 0.0, 0.5);
                    m.heights(0.0, {h});
                    m.box(3.0, 0.0, 0.3, 3.0, 0.0);
                    m"#
                );
                (format!("kerb_{h}"), src)
            })
            .collect();
        let scenes = SCENES.iter().map(|(n, s, _)| (n.to_string(), s.to_string())).chain(kerbs);
        for (name, src) in scenes {
            let s = map(&src, &name);
            let w = s.world();
            let e = run_episode(&s, &w, 0, &c, &p, 0, 1);
            assert!(e.record.reached, "{name}");
            let sk = &p.animation.as_ref().unwrap().0.db.skeleton;
            let feet = [LEFT_FOOT, RIGHT_FOOT].map(|f| sk.find(f).unwrap());
            let mut g = Vec::new();
            let mut worst = (f64::INFINITY, 0, glam::DVec3::ZERO);
            for (k, pose) in e.motion.iter().enumerate() {
                sk.globals(pose, &mut g);
                for &f in &feet {
                    let (ankle, q) = g[f];
                    let (d, at) = ground_under(&w.terrain, ankle + q * HEEL_POINT, ankle + q * TOE_POINT);
                    if d < worst.0 {
                        worst = (d, k, at);
                    }
                }
            }
            assert!(
                worst.0 > -1e-3,
                "{name}: a sole {:.4} m into the ground at frame {} ({:?})",
                -worst.0,
                worst.1,
                worst.2
            );
        }
    }

    #[test]
    fn footholds_land_on_the_stones_and_the_pelvis_follows_the_stairs() {
        let (p, c) = (params(), controller());
        for (name, src, _) in [SCENES[0], SCENES[2]] {
            let s = map(src, name);
            let mut sim = Simulation::new(s.world(), p.clone());
            sim.add_agent(s.tasks[0], &c);
            let mut highest: f64 = 0.0;
            while !sim.all_done() {
                sim.step();
                let f = sim.agents[0].body.animated().unwrap().footing().unwrap();
                highest = highest.max(f.ground_height_m(0.5));
            }
            let f = sim.agents[0].body.animated().unwrap().footing().unwrap();
            for h in f.footholds() {
                let z = sim.world.terrain.ground(h.position);
                assert!(z.is_some_and(|z| (z - h.z_m).abs() < 1e-6), "{name}: {h:?} over {z:?}");
            }
            if name.contains("stairs") {
                assert!((highest - 0.6).abs() < 0.05, "the pelvis climbs to the landing: {highest}");
            }
        }
    }

    #[test]
    fn the_side_view_unrolls_every_step_along_the_path() {
        use strider::render::side_view::render_side_view;
        use strider::render::sim_view::SideRecorder;
        let (p, c) = (params(), controller());
        let (name, src, _) = SCENES[0];
        let s = map(src, name);
        let mut sim = Simulation::new(s.world(), p);
        sim.add_agent(s.tasks[0], &c);
        let mut side = SideRecorder::default();
        while !sim.all_done() {
            sim.step();
            side.observe(sim.agents[0].body.animated().unwrap().footing().unwrap());
        }
        let f = sim.agents[0].body.animated().unwrap().footing().unwrap();
        let view = side.view(0.24, 4);
        // Every foothold taken, in order, at the heights the terrain has there, spaced as walked.
        assert_eq!(side.len() + 2, f.footholds().len(), "{name}");
        assert_eq!(view.footholds.len(), f.footholds().len());
        for (k, (drawn, taken)) in view.footholds.iter().zip(f.footholds()).enumerate() {
            assert_eq!(drawn.foot, taken.foot);
            assert!((drawn.sole.z_m - taken.z_m).abs() < 1e-9, "foothold {k}");
        }
        for w in view.footholds[1..].windows(2) {
            assert!(w[1].sole.x_m > w[0].sole.x_m);
        }
        // The ground pieces follow each other and hold every foothold.
        for w in view.ground.windows(2) {
            assert!(w[1].x0_m >= w[0].x1_m - 1e-9);
        }
        for h in &view.footholds {
            assert!(view.ground.iter().any(|g| g.x0_m <= h.sole.x_m && h.sole.x_m <= g.x1_m));
        }
        assert_eq!(view.legs.len(), 4 * side.len() + 1);
        let (pm, _) = render_side_view(&view);
        assert!(pm.width() > pm.height());
    }

    /// `strider run --bvh-out`: the file read back with the project's BVH parser holds one
    /// frame at the start and one per 1/60 s played, the root at the world position of the
    /// episode's trail, the pelvis on the landing of the stairs.
    #[test]
    fn the_exported_motion_follows_the_episode() {
        use strider::anim::bvh::{self, BvhOptions};
        let (name, src, _) = SCENES[0];
        let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("bvh_out");
        let _ = std::fs::remove_dir_all(&dir);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_strider"))
            .args(["run", &format!("maps/{name}"), "--bvh-out", dir.to_str().unwrap()])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = std::fs::read_to_string(dir.join("episode_0.bvh")).unwrap();
        assert!(text.contains("ROOT Hips\n{\n\tOFFSET 0 0 0\n"), "root offset 0 0 0");
        let file = bvh::parse(&text, "episode_0.bvh", "episode_0", &BvhOptions::default()).unwrap();
        let clip = &file.clip;
        assert!((clip.frame_time - 1.0 / 60.0).abs() < 1e-12, "{}", clip.frame_time);
        // The same episode through the library (deterministic): its trail, step by step.
        let s = map(src, name);
        let mut p = params();
        p.limits.radius = s.agent_radius;
        let e = run_episode(&s, &s.world(), 0, &controller(), &p, 0, 1);
        let steps = e.record.steps as usize;
        let per_step = (p.dt_s * 60.0 + 1e-9).floor() as usize;
        assert_eq!(clip.frames.len(), 1 + per_step * steps);
        assert_eq!(e.trail.len(), steps + 1);
        let mut highest: f64 = 0.0;
        for (k, at) in e.trail.iter().enumerate() {
            let root = clip.frames[per_step * k].root;
            assert!(glam::DVec2::new(root.x, root.y).distance(*at) < 1e-6, "step {k}: root {root} vs trail {at}");
            highest = highest.max(root.z);
        }
        // The pelvis climbs with the stairs to the 0.6 m landing (about 0.95 m above it).
        assert!((highest - 1.55).abs() < 0.1, "highest pelvis {highest}");
        assert!((clip.frames[0].root.z - 0.95).abs() < 0.05);
    }

    /// The legs of the exported motion, checked by forward kinematics over the BVH file alone:
    /// no heel or toe ever below the ground, every foothold the planner took (but a last one
    /// the episode ends before reaching) held by its foot's sole, knees bending forward, and
    /// no foot jumping between frames.
    #[test]
    fn the_exported_legs_stand_on_the_footholds() {
        use glam::DVec3;
        use strider::anim::actor::{HEEL_POINT, LEFT_FOOT, LEFT_LEG, RIGHT_FOOT, RIGHT_LEG, TOE_POINT};
        use strider::anim::bvh::{self, BvhOptions};
        let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("bvh_legs");
        for (name, src, _) in SCENES {
            let _ = std::fs::remove_dir_all(&dir);
            let out = std::process::Command::new(env!("CARGO_BIN_EXE_strider"))
                .args(["run", &format!("maps/{name}"), "--bvh-out", dir.to_str().unwrap()])
                .current_dir(env!("CARGO_MANIFEST_DIR"))
                .output()
                .unwrap();
            assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
            let text = std::fs::read_to_string(dir.join("episode_0.bvh")).unwrap();
            let file = bvh::parse(&text, "episode_0.bvh", "episode_0", &BvhOptions::default()).unwrap();
            let sk = &file.skeleton;
            let feet = [sk.find(LEFT_FOOT).unwrap(), sk.find(RIGHT_FOOT).unwrap()];
            let knees = [sk.find(LEFT_LEG).unwrap(), sk.find(RIGHT_LEG).unwrap()];
            let s = map(src, name);
            let w = s.world();
            let mut soles = Vec::new();
            let mut g = Vec::new();
            let mut lowest = f64::INFINITY;
            for (k, pose) in file.clip.frames.iter().enumerate() {
                sk.globals(pose, &mut g);
                let mut both = [DVec3::ZERO; 2];
                for i in 0..2 {
                    let (ankle, q) = g[feet[i]];
                    let (heel, toe) = (ankle + q * HEEL_POINT, ankle + q * TOE_POINT);
                    for p in [heel, toe] {
                        if let Some(z) = w.terrain.ground(p.truncate()) {
                            lowest = lowest.min(p.z - z);
                        }
                    }
                    both[i] = 0.5 * (heel + toe);
                    let bend = pose.rotations[knees[i]].to_euler(glam::EulerRot::YXZ).0;
                    assert!(bend >= -1e-9, "{name}: frame {k}: a knee bends backward ({bend})");
                }
                soles.push(both);
            }
            assert!(lowest > -1e-3, "{name}: a foot {lowest} m into the ground");
            // At most 8 m/s between frames (the swing's peak is about 5).
            let dt = file.clip.frame_time;
            for (k, f) in soles.windows(2).enumerate() {
                for (a, b) in f[0].iter().zip(&f[1]) {
                    let v = a.distance(*b) / dt;
                    assert!(v < 8.0, "{name}: frame {k}: a foot jumps at {v} m/s");
                }
            }
            // The footholds, from the same (deterministic) episode through the library.
            let mut sim = Simulation::new(w.clone(), params());
            sim.add_agent(s.tasks[0], &controller());
            while !sim.all_done() {
                sim.step();
            }
            let f = sim.agents[0].body.animated().unwrap().footing().unwrap();
            let taken = f.footholds();
            assert!(taken.len() >= 10, "{name}");
            for h in &taken[..taken.len() - 1] {
                let at = h.sole_centre().extend(h.z_m);
                let i = h.foot.index();
                let nearest = soles.iter().map(|s| s[i].distance(at)).fold(f64::INFINITY, f64::min);
                assert!(nearest < 0.015, "{name}: {h:?} held only within {nearest} m");
            }
        }
    }

    #[test]
    fn the_character_walks_round_a_pond_it_cannot_step_across() {
        // Ponds of 1–1.6 m radius on the straight way in an open field: a wall of the navigation,
        // walked round; no foot ever lands in the water.
        for (k, r) in [1.0, 1.3, 1.6].into_iter().enumerate() {
            let y = [0.0, 0.3, -0.4][k];
            let src = format!(
                r#"
                let m = world("pond");
                m.start(0.0, 0.0, 0.0);
                m.goal(10.0, 0.0, 0.5);
                m.hole_cylinder(5.0, {y}, {r});
                m
            "#
            );
            let s = map(&src, "pond.rhai");
            let mut sim = Simulation::new(s.world(), params());
            sim.add_agent(s.tasks[0], &controller());
            while !sim.all_done() {
                sim.step();
            }
            assert_eq!(sim.agents[0].outcome, Some(strider::sim::Outcome::Reached), "pond of radius {r}");
            let f = sim.agents[0].body.animated().unwrap().footing().unwrap();
            let centre = glam::DVec2::new(5.0, y);
            for h in f.footholds() {
                assert!(h.sole_centre().distance(centre) > r, "pond of radius {r}: {h:?}");
            }
        }
    }

    #[test]
    fn a_gap_too_wide_stops_the_character_with_a_reason() {
        // 0.8 m: narrower than the longest step (0.9 m, so not a wall of the navigation) but too
        // wide for a sole to clear.
        let src = r#"
            let m = world("wide_gap");
            m.start(0.0, 0.0, 0.0);
            m.goal(8.0, 0.0, 0.5);
            m.time_limit(15.0);
            m.hole_box(4.0, 0.0, 0.8, 40.0, 0.0);
            m
        "#;
        let s = map(src, "wide_gap.rhai");
        let mut p = params();
        p.record_motion = true;
        let mut sim = Simulation::new(s.world(), p);
        sim.add_agent(s.tasks[0], &controller());
        while !sim.all_done() {
            sim.step();
        }
        let body = sim.agents[0].body.animated().unwrap();
        let f = body.footing().unwrap();
        assert_eq!(f.invalid_footholds(), 0);
        assert!(f.footholds().iter().all(|h| h.position.x < 3.6 || h.position.x > 4.4), "{:?}", f.footholds());
        let reason = f.stopped().expect("stopped");
        assert!(reason.contains("no sequence of steps"), "{reason}");
        assert!(sim.agents[0].outcome != Some(strider::sim::Outcome::Reached));
        // Standing at the edge, both soles rest on the last two footholds.
        use strider::anim::actor::{HEEL_POINT, LEFT_FOOT, RIGHT_FOOT, TOE_POINT};
        let sk = &body.animation().db.skeleton;
        let mut g = Vec::new();
        sk.globals(body.motion().unwrap().last().unwrap(), &mut g);
        let taken = f.footholds();
        for h in &taken[taken.len() - 2..] {
            let (ankle, q) = g[sk.find([LEFT_FOOT, RIGHT_FOOT][h.foot.index()]).unwrap()];
            let sole = 0.5 * (ankle + q * HEEL_POINT + ankle + q * TOE_POINT);
            assert!(sole.distance(h.sole_centre().extend(h.z_m)) < 0.01, "{h:?}: sole at {sole}");
        }
    }

    #[test]
    fn flat_worlds_have_no_footing() {
        let s = map(include_str!("../maps/open_field.rhai"), "open_field.rhai");
        let e = run_episode(&s, &s.world(), 0, &controller(), &params(), 0, 1);
        assert_eq!(e.record.invalid_footholds, None);
        assert_eq!(e.record.footstep_planning_ms_p99, None);
    }
}

#[test]
fn run_takes_the_footstep_planner_off_as_steps_does() {
    // Seed 002 Fig. 8 on a map: with the planner the character crosses the ditch; with the
    // nominal step alone it stops before a step that would land in it, never on it.
    let run = |planner: &str| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_strider"))
            .args(["run", "maps/terrain_fig8_trap.rhai", "--planner", planner, "--format", "json"])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap();
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        json["episodes"][0].clone()
    };
    let (on, off) = (run("on"), run("off"));
    assert_eq!(on["reached"], true, "{on}");
    assert_eq!(off["reached"], false, "{off}");
    assert_eq!(off["invalid_footholds"], 0, "{off}");
    assert_eq!(off["collisions"], 0, "{off}");
}
