//! Reference shortest paths: analytic cases, failure cases, clearance of every returned path,
//! determinism, timing on larger worlds and a property test over random worlds.

use std::f64::consts::PI;
use std::time::Instant;

use glam::DVec2;
use proptest::prelude::*;
use strider::plan::{LENGTH_ERROR_BOUND, Path, Planner, path_length, shortest_path};
use strider::world::{Obstacle, ObstacleShape, World};

fn v(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

fn boxed(cx: f64, cy: f64, w: f64, h: f64, yaw: f64) -> Obstacle {
    Obstacle::build(ObstacleShape::Box { center: v(cx, cy), width: w, height: h, yaw }, 0.0, 2.0).unwrap()
}

fn cylinder(cx: f64, cy: f64, radius: f64) -> Obstacle {
    Obstacle::build(ObstacleShape::Cylinder { center: v(cx, cy), radius }, 0.0, 2.0).unwrap()
}

/// Asserts that every point sampled along the path keeps `r` (less 1 µm) from every part, and
/// that the path runs from `start` to `goal` with a consistent length.
fn assert_clear(world: &World, path: &Path, start: DVec2, goal: DVec2, r: f64) {
    assert_eq!(path.points.first(), Some(&start));
    assert_eq!(path.points.last(), Some(&goal));
    assert!((path.length - path_length(&path.points)).abs() <= 1e-12 * path.length.max(1.0));
    for w in path.points.windows(2) {
        let steps = (w[0].distance(w[1]) / 0.005).ceil().max(1.0) as usize;
        for i in 0..=steps {
            let p = w[0].lerp(w[1], i as f64 / steps as f64);
            for part in world.parts() {
                let d = part.shape.distance(p);
                assert!(d >= r - 1e-6, "point {p} is {d} m from {:?}; path {:?}", part.shape, path.points);
            }
        }
    }
}

/// Asserts `exact <= length <= exact · (1 + LENGTH_ERROR_BOUND)` up to rounding.
fn assert_within_bound(length: f64, exact: f64) {
    assert!(length >= exact - 1e-9, "{length} below the true optimum {exact}");
    assert!(length <= exact * (1.0 + LENGTH_ERROR_BOUND) + 1e-9, "{length} exceeds {exact} by more than the bound");
}

#[test]
fn empty_world_gives_the_straight_line() {
    let world = World::new(Vec::new());
    let (a, b) = (v(-3.0, 1.0), v(4.0, 2.5));
    let p = shortest_path(&world, a, b, 0.3).unwrap();
    assert_eq!(p.points, vec![a, b]);
    assert_eq!(p.length, a.distance(b));
    let same = shortest_path(&world, a, a, 0.3).unwrap();
    assert_eq!(same.length, 0.0);
}

#[test]
fn box_between_start_and_goal() {
    // Box [-1, 1]², agent radius 0.5: the path rounds the corners (-1, 1) and (1, 1) on arcs of
    // radius 0.5 and runs along the grown top side y = 1.5 in between.
    let world = World::new(vec![boxed(0.0, 0.0, 2.0, 2.0, 0.0)]);
    let r = 0.5;
    let (start, goal) = (v(-3.0, 0.0), v(3.0, 0.0));
    let p = shortest_path(&world, start, goal, r).unwrap();
    let corner = v(-1.0, 1.0);
    let d = start.distance(corner);
    let tangent = (d * d - r * r).sqrt();
    let to_start = (start - corner).to_angle().rem_euclid(2.0 * PI);
    let touch = to_start - (r / d).acos();
    let arc = r * (touch - PI / 2.0);
    let exact = 2.0 * (tangent + arc) + 2.0;
    assert!((exact - 7.0480).abs() < 1e-3, "{exact}");
    assert_within_bound(p.length, exact);
    let above = p.points.iter().all(|q| q.y >= 0.0);
    let below = p.points.iter().all(|q| q.y <= 0.0);
    assert!(above || below, "{:?}", p.points);
    assert_clear(&world, &p, start, goal, r);
}

#[test]
fn cylinder_matches_tangent_arc_tangent() {
    let world = World::new(vec![cylinder(0.0, 0.0, 1.0)]);
    let r = 0.3;
    let big = 1.0 + r;
    let (start, goal) = (v(-5.0, 0.0), v(5.0, 0.0));
    let p = shortest_path(&world, start, goal, r).unwrap();
    let tangent = (25.0 - big * big).sqrt();
    let arc = big * (PI - 2.0 * (big / 5.0).acos());
    assert_within_bound(p.length, 2.0 * tangent + arc);
    assert_clear(&world, &p, start, goal, r);

    // Off-centre end points: the same formula with the angle between them.
    let (start, goal) = (v(-4.0, 1.0), v(3.0, -2.5));
    let p = shortest_path(&world, start, goal, r).unwrap();
    let (da, db) = (start.length(), goal.length());
    let theta = start.angle_to(goal).abs();
    let arc = big * (theta - (big / da).acos() - (big / db).acos());
    let exact = (da * da - big * big).sqrt() + (db * db - big * big).sqrt() + arc;
    assert!(arc > 0.0);
    assert_within_bound(p.length, exact);
    assert_clear(&world, &p, start, goal, r);
}

fn u_trap() -> World {
    // Bottom at x ∈ [0.8, 1.2], arms along y = ±2 reaching to x = -2, open towards -x.
    World::new(vec![boxed(1.0, 0.0, 0.4, 4.4, 0.0), boxed(-0.4, 2.0, 3.2, 0.4, 0.0), boxed(-0.4, -2.0, 3.2, 0.4, 0.0)])
}

#[test]
fn u_trap_is_left_and_walked_around() {
    let world = u_trap();
    let r = 0.3;
    // From inside the U: out through the opening, then around an arm.
    let (start, goal) = (v(-0.5, 0.0), v(5.0, 0.0));
    let p = shortest_path(&world, start, goal, r).unwrap();
    assert!(p.length > start.distance(goal) + 2.0, "{p:?}");
    assert!(p.points.iter().any(|q| q.x < -2.0), "{p:?}");
    assert_clear(&world, &p, start, goal, r);
    // From in front of the opening: around the outside of an arm.
    let start = v(-5.0, 0.0);
    let p = shortest_path(&world, start, goal, r).unwrap();
    assert!(p.length > start.distance(goal), "{p:?}");
    assert!(p.points.iter().any(|q| q.y.abs() >= 2.2 + r - 1e-9), "{p:?}");
    assert_clear(&world, &p, start, goal, r);
}

#[test]
fn blocked_start_or_goal_gives_none() {
    let world = World::new(vec![boxed(0.0, 0.0, 2.0, 2.0, 0.3)]);
    assert!(shortest_path(&world, v(0.0, 0.0), v(5.0, 0.0), 0.3).is_none());
    assert!(shortest_path(&world, v(5.0, 0.0), v(0.2, 0.1), 0.3).is_none());
    // Outside the box but within the agent radius of it.
    let near = v(0.0, 0.0) + DVec2::from_angle(0.3 + PI / 2.0) * 1.2;
    assert!(shortest_path(&world, near, v(5.0, 0.0), 0.3).is_none());
    assert!(shortest_path(&world, near, v(5.0, 0.0), 0.1).is_some());
}

#[test]
fn walled_off_goal_gives_none() {
    // A closed square ring of four walls around the goal.
    let world = World::new(vec![
        boxed(0.0, 3.0, 6.4, 0.4, 0.0),
        boxed(0.0, -3.0, 6.4, 0.4, 0.0),
        boxed(3.0, 0.0, 0.4, 6.4, 0.0),
        boxed(-3.0, 0.0, 0.4, 6.4, 0.0),
    ]);
    assert!(shortest_path(&world, v(10.0, 1.0), v(0.0, 0.0), 0.3).is_none());
    assert!(shortest_path(&world, v(0.0, 0.0), v(-10.0, 1.0), 0.3).is_none());
    // Inside the ring both ends are reachable.
    let p = shortest_path(&world, v(-1.0, -1.0), v(1.0, 1.5), 0.3).unwrap();
    assert_eq!(p.points.len(), 2);
    // A gap narrower than the agent closes the ring; a wider one opens it.
    let gap = |width: f64| {
        let side = (6.4 - width) / 2.0;
        World::new(vec![
            boxed(0.0, -3.0, 6.4, 0.4, 0.0),
            boxed(3.0, 0.0, 0.4, 6.4, 0.0),
            boxed(-3.0, 0.0, 0.4, 6.4, 0.0),
            boxed(-3.2 + side / 2.0, 3.0, side, 0.4, 0.0),
            boxed(3.2 - side / 2.0, 3.0, side, 0.4, 0.0),
        ])
    };
    assert!(shortest_path(&gap(0.59), v(0.0, 0.0), v(0.0, 10.0), 0.3).is_none());
    let p = shortest_path(&gap(0.61), v(0.0, 0.0), v(0.0, 10.0), 0.3).unwrap();
    assert!((p.length - 10.0).abs() < 1e-9, "{p:?}");
}

/// A small deterministic generator for test worlds.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Boxes and cylinders scattered over a `side`-metre square, avoiding two corner pockets.
fn scattered(count: usize, side: f64, seed: u64) -> World {
    let mut rng = Lcg(seed);
    let mut obstacles = Vec::new();
    while obstacles.len() < count {
        let c = v(rng.next() * side, rng.next() * side);
        if c.length() < 2.5 || c.distance(DVec2::splat(side)) < 2.5 {
            continue;
        }
        if rng.next() < 0.3 {
            obstacles.push(cylinder(c.x, c.y, 0.2 + rng.next() * 0.6));
        } else {
            obstacles.push(boxed(c.x, c.y, 0.3 + rng.next() * 1.5, 0.3 + rng.next() * 1.5, rng.next() * PI));
        }
    }
    World::new(obstacles)
}

/// A MovingAI-like map: a `side`×`side` grid of 1 m cells with `blocked` unit boxes at
/// pseudo-random free cells (corner cells stay free) and walls around the map.
fn grid_world(side: usize, blocked: usize, seed: u64) -> World {
    let mut rng = Lcg(seed);
    let mut taken = vec![false; side * side];
    taken[0] = true;
    taken[side * side - 1] = true;
    let mut obstacles = Vec::new();
    while obstacles.len() < blocked {
        let cell = ((rng.next() * (side * side) as f64) as usize).min(side * side - 1);
        if taken[cell] {
            continue;
        }
        taken[cell] = true;
        let (x, y) = ((cell % side) as f64, (cell / side) as f64);
        obstacles.push(boxed(x + 0.5, y + 0.5, 1.0, 1.0, 0.0));
    }
    let s = side as f64;
    obstacles.push(boxed(s / 2.0, -0.5, s + 2.0, 1.0, 0.0));
    obstacles.push(boxed(s / 2.0, s + 0.5, s + 2.0, 1.0, 0.0));
    obstacles.push(boxed(-0.5, s / 2.0, 1.0, s, 0.0));
    obstacles.push(boxed(s + 0.5, s / 2.0, 1.0, s, 0.0));
    World::new(obstacles)
}

#[test]
fn results_are_deterministic() {
    let world = scattered(40, 20.0, 7);
    let (a, b) = (v(0.5, 0.5), v(19.5, 19.5));
    let first = shortest_path(&world, a, b, 0.3).unwrap();
    let second = shortest_path(&world, a, b, 0.3).unwrap();
    assert_eq!(first, second);
    assert!(first.length > a.distance(b));
    assert_clear(&world, &first, a, b, 0.3);
}

#[test]
fn forty_obstacles_take_milliseconds() {
    for seed in 1..4 {
        let world = scattered(40, 20.0, seed);
        let (a, b) = (v(0.5, 0.5), v(19.5, 19.5));
        let t = Instant::now();
        let p = shortest_path(&world, a, b, 0.3);
        let elapsed = t.elapsed();
        println!("20 m world, 40 obstacles, seed {seed}: {elapsed:?}, {:?}", p.as_ref().map(|p| p.length));
        if let Some(p) = &p {
            assert_clear(&world, p, a, b, 0.3);
        }
        if !cfg!(debug_assertions) {
            assert!(elapsed.as_millis() < 100, "{elapsed:?}");
        }
    }
}

#[test]
fn grid_map_with_150_boxes_is_fast() {
    let world = grid_world(32, 150, 3);
    let (a, b) = (v(0.5, 0.5), v(31.5, 31.5));
    let t = Instant::now();
    let planner = Planner::new(&world, 0.3).unwrap();
    let built = t.elapsed();
    let p = planner.shortest_path(a, b).expect("the corners are connected for this seed");
    let total = t.elapsed();
    println!(
        "32×32 grid, 150 boxes: graph {built:?} ({} nodes), total {total:?}, length {:.3}",
        planner.node_count(),
        p.length
    );
    assert!(p.length >= a.distance(b));
    assert_clear(&world, &p, a, b, 0.3);
    if !cfg!(debug_assertions) {
        assert!(total.as_millis() < 500, "{total:?}");
    }
    // Reusing the planner: one more query costs only the end-point connections and the search.
    let t = Instant::now();
    let q = planner.shortest_path(v(31.5, 0.5), v(0.5, 31.5));
    println!("  second query {:?}: {:?}", t.elapsed(), q.as_ref().map(|q| q.length));
    if let Some(q) = &q {
        assert_clear(&world, q, v(31.5, 0.5), v(0.5, 31.5), 0.3);
    }
}

fn random_obstacle() -> impl Strategy<Value = Obstacle> {
    let center = (-8.0..8.0f64, -8.0..8.0f64);
    prop_oneof![
        (center.clone(), 0.2..3.0f64, 0.2..3.0f64, 0.0..PI).prop_map(|((x, y), w, h, yaw)| boxed(x, y, w, h, yaw)),
        (center, 0.1..1.5f64).prop_map(|((x, y), r)| cylinder(x, y, r)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn returned_paths_are_clear_and_no_shorter_than_the_straight_line(
        obstacles in prop::collection::vec(random_obstacle(), 0..=10),
        start in (-10.0..10.0f64, -10.0..10.0f64),
        goal in (-10.0..10.0f64, -10.0..10.0f64),
        r in 0.05..0.6f64,
    ) {
        let world = World::new(obstacles);
        let (start, goal) = (v(start.0, start.1), v(goal.0, goal.1));
        let free = |p: DVec2| world.parts().iter().all(|part| part.shape.distance(p) >= r);
        prop_assume!(free(start) && free(goal));
        if let Some(p) = shortest_path(&world, start, goal, r) {
            prop_assert!(p.length >= start.distance(goal) - 1e-12);
            assert_clear(&world, &p, start, goal, r);
        }
    }
}
