//! Terrain in maps (seed 002 §3.2): the text and Rhai map formats, the ground profile along a
//! path, and the animated character walking over the shipped terrain scenes.

use glam::DVec2;
use strider::maps::text;
use strider::script::{Limits, ScriptLog, map_api};
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
    ];
    for (src, at, needle) in cases {
        let e = text::parse(src, "w.txt").expect_err(needle);
        assert_eq!((e.line, e.col), at, "{needle}: {e}");
        assert!(e.message.contains(needle), "{needle}: {e}");
    }
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
    let s = map_api::load_scenario(src, "t.rhai", Limits::default(), &ScriptLog::new()).unwrap();
    assert_eq!(s.terrain.features().len(), 8);
    assert_eq!(s.world().terrain.ground(DVec2::new(16.0, 0.0)), Some(0.05));
    let bad = r#"
        let m = world("t");
        m.start(0.0, 0.0, 0.0);
        m.goal(10.0, 0.0, 0.5);
        m.stairs(11.0, 0.0, 3.0, 2.0, 0.0, 0.4, 0.0, 0);
        m
    "#;
    let e = map_api::load_scenario(bad, "t.rhai", Limits::default(), &ScriptLog::new()).unwrap_err();
    assert_eq!(e.line, 5, "{e}");
    assert!(e.message.contains("treads"), "{e}");
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
