//! Reference shortest paths: analytic cases, failure cases, clearance of every returned path,
//! determinism whatever searches came before, and property tests over random worlds, against
//! a dense search written here from the definition.

use std::f64::consts::{PI, TAU};

use glam::DVec2;
use proptest::prelude::*;
use strider::plan::{Path, Planner, shortest_path};
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

/// Asserts that every point sampled along the path (arcs followed) keeps `r` (less 1 µm) from
/// every part, that the path runs from `start` to `goal`, that its pieces join up (each bend's
/// ends on its rim) and that its length is that of its legs and arcs.
fn assert_clear(world: &World, path: &Path, start: DVec2, goal: DVec2, r: f64) {
    assert_eq!(path.points.first(), Some(&start));
    assert_eq!(path.points.last(), Some(&goal));
    assert_eq!(path.points.len(), 2 * path.bends.len() + 2);
    let mut length = 0.0;
    for (i, w) in path.points.chunks(2).enumerate() {
        length += w[0].distance(w[1]);
        if let Some(b) = path.bends.get(i) {
            length += b.radius * b.sweep.abs();
            let (a, z) = (path.points[2 * i + 1], path.points[2 * i + 2]);
            assert!((a.distance(b.center) - b.radius).abs() < 1e-9 && (z.distance(b.center) - b.radius).abs() < 1e-9);
            let turned = (z - b.center).angle_to(a - b.center);
            assert!(((turned + b.sweep) / TAU).fract().abs() < 1e-9 || b.radius == 0.0, "{b:?}");
        }
    }
    assert!((path.length - length).abs() <= 1e-9 * length.max(1.0), "{} vs {length}", path.length);
    for p in path.sampled(0.005) {
        for part in world.parts() {
            let d = part.shape.distance(p);
            assert!(d >= r - 1e-6, "point {p} is {d} m from {:?}; path {:?}", part.shape, path.points);
        }
    }
}

/// Asserts `length` is `exact` within 1e-9 relative.
fn assert_exact(length: f64, exact: f64) {
    assert!((length - exact).abs() <= 1e-9 * exact.max(1.0), "{length} vs the exact {exact}");
}

#[test]
fn empty_world_gives_the_straight_line() {
    let world = World::new(Vec::new());
    let (a, b) = (v(-3.0, 1.0), v(4.0, 2.5));
    let p = shortest_path(&world, a, b, 0.3).unwrap();
    assert_eq!(p.points, vec![a, b]);
    assert!(p.bends.is_empty());
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
    assert_exact(p.length, exact);
    assert_eq!(p.bends.len(), 2);
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
    assert_exact(p.length, 2.0 * tangent + arc);
    assert_eq!(p.bends.len(), 1);
    assert!((p.bends[0].sweep.abs() * big - arc).abs() < 1e-9);
    assert_clear(&world, &p, start, goal, r);

    // Off-centre end points: the same formula with the angle between them.
    let (start, goal) = (v(-4.0, 1.0), v(3.0, -2.5));
    let p = shortest_path(&world, start, goal, r).unwrap();
    let (da, db) = (start.length(), goal.length());
    let theta = start.angle_to(goal).abs();
    let arc = big * (theta - (big / da).acos() - (big / db).acos());
    let exact = (da * da - big * big).sqrt() + (db * db - big * big).sqrt() + arc;
    assert!(arc > 0.0);
    assert_exact(p.length, exact);
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
fn a_planner_answers_alike_whatever_it_was_asked_before() {
    // What one search finds of the graph, later ones use: the answers must not depend on it.
    for (world, side) in [(scattered(40, 20.0, 3), 20.0), (grid_world(32, 150, 3), 32.0)] {
        let mut rng = Lcg(11);
        let mut queries = Vec::new();
        while queries.len() < 12 {
            let a = v(rng.next() * side, rng.next() * side);
            let b = v(rng.next() * side, rng.next() * side);
            let fresh = Planner::new(&world, 0.3).unwrap();
            if fresh.is_free(a) && fresh.is_free(b) {
                queries.push((a, b, fresh.shortest_path(a, b)));
            }
        }
        let forward = Planner::new(&world, 0.3).unwrap();
        let backward = Planner::new(&world, 0.3).unwrap();
        let ahead: Vec<Option<Path>> = queries.iter().map(|&(a, b, _)| forward.shortest_path(a, b)).collect();
        let behind: Vec<Option<Path>> = queries.iter().rev().map(|&(a, b, _)| backward.shortest_path(a, b)).collect();
        let reached = queries.iter().filter(|q| q.2.is_some()).count();
        assert!(reached >= 8, "{reached}");
        for (k, (a, b, fresh)) in queries.iter().enumerate() {
            assert_eq!(&ahead[k], fresh);
            assert_eq!(&behind[queries.len() - 1 - k], fresh);
            if let Some(p) = fresh {
                assert_clear(&world, p, *a, *b, 0.3);
            }
        }
    }
}

#[test]
fn grid_map_paths_are_clear_and_the_corners_are_joined() {
    let world = grid_world(32, 150, 3);
    let (a, b) = (v(0.5, 0.5), v(31.5, 31.5));
    let planner = Planner::new(&world, 0.3).unwrap();
    let p = planner.shortest_path(a, b).expect("the corners are connected for this seed");
    assert!(p.length >= a.distance(b));
    assert_clear(&world, &p, a, b, 0.3);
    let q = planner.shortest_path(v(31.5, 0.5), v(0.5, 31.5)).expect("connected");
    assert_clear(&world, &q, v(31.5, 0.5), v(0.5, 31.5), 0.3);
}

/// The shortest path from the definition, searched densely: every circle a grown part is
/// bounded by (a polygon corner's circle of radius `r`, a disc's grown circle), every
/// straight leg tangent to two of them (or from the start, or to the goal) whose ends lie on
/// the grown boundary and which keeps `r` from every part, and every arc between two such
/// ends along a circle (both ways round) whose points, sampled every milliradian, all keep
/// `r`; Dijkstra over them. Written from the world's own distance functions, apart from the
/// planner's code.
fn dense_reference(world: &World, r: f64, start: DVec2, goal: DVec2) -> Option<f64> {
    let tol = 1e-9 * 20.0;
    let free = |p: DVec2| world.parts().iter().all(|q| q.shape.distance(p) >= r - tol);
    let clear = |a: DVec2, b: DVec2| world.parts().iter().all(|q| q.shape.segment_distance(a, b) >= r - tol);
    let mut circles: Vec<(DVec2, f64)> = Vec::new();
    for part in world.parts() {
        match &part.shape {
            strider::geom::Shape::Polygon(poly) => circles.extend(poly.vertices().iter().map(|&c| (c, r))),
            strider::geom::Shape::Circle { center, radius } => circles.push((*center, radius + r)),
        }
    }
    // Nodes: the start (0), the goal (1), then points on circles: (circle, turn, angle).
    let mut at: Vec<DVec2> = vec![start, goal];
    let mut on: Vec<Option<(usize, i32, f64)>> = vec![None, None];
    let mut edges: Vec<Vec<(usize, f64)>> = vec![Vec::new(), Vec::new()];
    let node = |at: &mut Vec<DVec2>,
                on: &mut Vec<Option<(usize, i32, f64)>>,
                e: &mut Vec<Vec<(usize, f64)>>,
                c: usize,
                s: i32,
                angle: f64| {
        let angle = angle.rem_euclid(TAU);
        if let Some(k) =
            on.iter().position(|o| o.is_some_and(|(c2, s2, a2)| c2 == c && s2 == s && (a2 - angle).abs() < 1e-12))
        {
            return k;
        }
        at.push(circles[c].0 + DVec2::from_angle(angle) * circles[c].1);
        on.push(Some((c, s, angle)));
        e.push(Vec::new());
        at.len() - 1
    };
    // The leg leaving circle (c1, ρ1) turning s1 (+1 left: centre on the left) for circle
    // (c2, ρ2) turning s2: its right-hand normal w satisfies w·(c2 − c1) = s1·ρ1 − s2·ρ2.
    let leg = |(c1, r1): (DVec2, f64), s1: i32, (c2, r2): (DVec2, f64), s2: i32| -> Option<(DVec2, DVec2, f64)> {
        let d = c2 - c1;
        let k = f64::from(s1) * r1 - f64::from(s2) * r2;
        if d.length() <= k.abs() {
            return None;
        }
        let phi = d.y.atan2(d.x) - (k / d.length()).acos();
        let w = DVec2::from_angle(phi);
        Some((c1 + w * (f64::from(s1) * r1), c2 + w * (f64::from(s2) * r2), phi))
    };
    let normal = |s: i32, phi: f64| if s > 0 { phi } else { phi + PI };
    if clear(start, goal) {
        edges[0].push((1, start.distance(goal)));
    }
    for c in 0..circles.len() {
        for s in [1, -1] {
            if let Some((p, q, phi)) = leg((start, 0.0), 1, circles[c], s)
                && free(q)
                && clear(p, q)
            {
                let n = node(&mut at, &mut on, &mut edges, c, s, normal(s, phi));
                edges[0].push((n, p.distance(q)));
            }
            if let Some((p, q, phi)) = leg(circles[c], s, (goal, 0.0), 1)
                && free(p)
                && clear(p, q)
            {
                let n = node(&mut at, &mut on, &mut edges, c, s, normal(s, phi));
                edges[n].push((1, p.distance(q)));
            }
            for c2 in 0..circles.len() {
                for s2 in [1, -1] {
                    if c2 == c {
                        continue;
                    }
                    if let Some((p, q, phi)) = leg(circles[c], s, circles[c2], s2)
                        && free(p)
                        && free(q)
                        && clear(p, q)
                    {
                        let a = node(&mut at, &mut on, &mut edges, c, s, normal(s, phi));
                        let b = node(&mut at, &mut on, &mut edges, c2, s2, normal(s2, phi));
                        edges[a].push((b, p.distance(q)));
                    }
                }
            }
        }
    }
    // Arcs: each node on to the next one round its circle the way it turns.
    for a in 2..at.len() {
        let Some((c, s, angle)) = on[a] else { continue };
        let next = (2..at.len())
            .filter(|&b| b != a && on[b].is_some_and(|(c2, s2, _)| c2 == c && s2 == s))
            .map(|b| (b, (f64::from(s) * (on[b].unwrap().2 - angle)).rem_euclid(TAU)))
            .min_by(|x, y| x.1.total_cmp(&y.1));
        if let Some((b, sweep)) = next {
            let (center, radius) = circles[c];
            let steps = (sweep / 1e-3).ceil().max(1.0) as usize;
            let along = (0..=steps).all(|i| {
                free(center + DVec2::from_angle(angle + f64::from(s) * sweep * i as f64 / steps as f64) * radius)
            });
            if along {
                edges[a].push((b, radius * sweep));
            }
        }
    }
    let mut dist = vec![f64::INFINITY; at.len()];
    let mut done = vec![false; at.len()];
    dist[0] = 0.0;
    loop {
        let u =
            (0..at.len()).filter(|&i| !done[i] && dist[i].is_finite()).min_by(|&a, &b| dist[a].total_cmp(&dist[b]))?;
        if u == 1 {
            return Some(dist[1]);
        }
        done[u] = true;
        for &(w, len) in &edges[u] {
            dist[w] = dist[w].min(dist[u] + len);
        }
    }
}

#[test]
fn the_dense_reference_knows_the_analytic_cases() {
    // A cylinder between start and goal: tangent, arc, tangent.
    let world = World::new(vec![cylinder(0.0, 0.0, 1.0)]);
    let big: f64 = 1.3;
    let exact = 2.0 * (25.0 - big * big).sqrt() + big * (PI - 2.0 * (big / 5.0).acos());
    assert_exact(dense_reference(&world, 0.3, v(-5.0, 0.0), v(5.0, 0.0)).unwrap(), exact);
    // Nothing in the way, and a goal walled in.
    assert_exact(dense_reference(&world, 0.3, v(-5.0, 2.0), v(5.0, 2.0)).unwrap(), 10.0);
    let ring = World::new(vec![
        boxed(0.0, 3.0, 6.4, 0.4, 0.0),
        boxed(0.0, -3.0, 6.4, 0.4, 0.0),
        boxed(3.0, 0.0, 0.4, 6.4, 0.0),
        boxed(-3.0, 0.0, 0.4, 6.4, 0.0),
    ]);
    assert!(dense_reference(&ring, 0.3, v(10.0, 1.0), v(0.0, 0.0)).is_none());
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
    fn lengths_are_the_dense_references_within_1e_9(
        obstacles in prop::collection::vec(random_obstacle(), 1..=5),
        start in (-10.0..10.0f64, -10.0..10.0f64),
        goal in (-10.0..10.0f64, -10.0..10.0f64),
        r in 0.05..0.6f64,
    ) {
        let world = World::new(obstacles);
        let (start, goal) = (v(start.0, start.1), v(goal.0, goal.1));
        let free = |p: DVec2| world.parts().iter().all(|part| part.shape.distance(p) >= r);
        prop_assume!(free(start) && free(goal));
        let found = shortest_path(&world, start, goal, r);
        let reference = dense_reference(&world, r, start, goal);
        match (&found, reference) {
            (Some(p), Some(exact)) => {
                prop_assert!((p.length - exact).abs() <= 1e-9 * exact.max(1.0), "{} vs the dense {exact}", p.length);
                assert_clear(&world, p, start, goal, r);
            }
            (None, None) => {}
            other => prop_assert!(false, "{other:?}"),
        }
    }

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
