//! Property tests for the geometry core.

use std::cmp::Ordering;
use std::f64::consts::TAU;

use glam::DVec2;
use proptest::prelude::*;
use strider::geom::{Aabb, ConvexPolygon, GeomError, Shape, SpatialIndex, decompose, floor_i64, orientation};

fn point(range: f64) -> impl Strategy<Value = DVec2> {
    (-range..range, -range..range).prop_map(|(x, y)| DVec2::new(x, y))
}

/// Point clouds: continuous coordinates, or small integers to provoke duplicates and collinearity.
fn cloud() -> impl Strategy<Value = Vec<DVec2>> {
    prop_oneof![
        prop::collection::vec(point(100.0), 0..40),
        prop::collection::vec((-4i32..4, -4i32..4).prop_map(|(x, y)| DVec2::new(x.into(), y.into())), 0..12),
    ]
}

/// A polygon from the hull of a random cloud with at least three well-spread points.
fn polygon() -> impl Strategy<Value = ConvexPolygon> {
    (prop::collection::vec(point(50.0), 3..20), point(40.0)).prop_filter_map("degenerate hull", |(pts, shift)| {
        ConvexPolygon::hull(&pts.iter().map(|&p| p + shift).collect::<Vec<_>>()).ok()
    })
}

/// Length scale of a polygon (and an extra point) for tolerances.
fn scale(poly: &ConvexPolygon, extra: DVec2) -> f64 {
    poly.vertices().iter().chain([&extra]).fold(1.0f64, |m, p| m.max(p.abs().max_element()))
}

fn lerp(a: DVec2, b: DVec2, t: f64) -> DVec2 {
    a + (b - a) * t
}

fn shoelace(pts: &[DVec2]) -> f64 {
    let n = pts.len();
    (0..n).map(|i| pts[i].perp_dot(pts[(i + 1) % n])).sum::<f64>().abs() * 0.5
}

fn is_strictly_convex_ccw(poly: &ConvexPolygon) -> bool {
    let v = poly.vertices();
    let n = v.len();
    n >= 3 && (0..n).all(|i| orientation(v[i], v[(i + 1) % n], v[(i + 2) % n]) == Ordering::Greater)
}

/// Star-shaped outline around the origin: simple by construction.
fn star_outline() -> impl Strategy<Value = Vec<DVec2>> {
    prop::collection::vec((0.0..1.0f64, 0.2..10.0f64), 4..24).prop_filter_map(
        "angles too close or too far apart",
        |mut spokes| {
            spokes.sort_by(|a, b| a.0.total_cmp(&b.0));
            // Distinct angles, each gap below half a turn: the origin then sees every edge, so the
            // outline is simple.
            let wrap = spokes[0].0 + 1.0 - spokes[spokes.len() - 1].0;
            let gaps = spokes.windows(2).map(|w| w[1].0 - w[0].0).chain([wrap]);
            if gaps.into_iter().any(|g| !(1e-3..0.45).contains(&g)) {
                return None;
            }
            Some(spokes.iter().map(|&(a, r)| DVec2::from_angle(a * TAU) * r).collect())
        },
    )
}

/// Histogram outline: columns of integer heights, with collinear vertices along flat tops.
fn histogram_outline() -> impl Strategy<Value = Vec<DVec2>> {
    (prop::collection::vec(1u8..6, 1..10), any::<bool>()).prop_map(|(heights, flip)| {
        let k = heights.len();
        let mut pts = vec![DVec2::new(0.0, 0.0), DVec2::new(k as f64, 0.0)];
        for i in (0..k).rev() {
            let h = f64::from(heights[i]);
            pts.push(DVec2::new(i as f64 + 1.0, h));
            pts.push(DVec2::new(i as f64, h));
        }
        pts.dedup();
        if pts.first() == pts.last() {
            pts.pop();
        }
        if flip {
            pts.reverse();
        }
        pts
    })
}

fn boxes() -> impl Strategy<Value = Vec<Aabb>> {
    prop::collection::vec((point(50.0), 0.0..5.0f64, 0.0..5.0f64), 0..120).prop_map(|items| {
        items.into_iter().map(|(c, w, h)| Aabb::new(c - DVec2::new(w, h), c + DVec2::new(w, h))).collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn hull_contains_inputs_and_is_convex_ccw(pts in cloud()) {
        match ConvexPolygon::hull(&pts) {
            Ok(h) => {
                prop_assert!(is_strictly_convex_ccw(&h));
                for &p in &pts {
                    prop_assert!(h.contains(p), "{p} not in {h:?}");
                    prop_assert_eq!(h.distance(p), 0.0);
                }
                for v in h.vertices() {
                    prop_assert!(pts.contains(v));
                }
            }
            Err(GeomError::TooFewPoints { found }) => {
                let mut distinct = pts.clone();
                distinct.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
                distinct.dedup();
                prop_assert_eq!(found, distinct.len());
                prop_assert!(found < 3);
            }
            Err(GeomError::Collinear) => {
                let a = pts[0];
                let b = pts.iter().copied().find(|&p| p != a).unwrap_or(a);
                prop_assert!(pts.iter().all(|&p| orientation(a, b, p) == Ordering::Equal));
            }
            Err(e) => prop_assert!(false, "unexpected error {e}"),
        }
    }

    #[test]
    fn distance_is_consistent_with_containment(poly in polygon(), q in point(120.0), t in 0.0..1.0f64, edge in 0usize..64) {
        let v = poly.vertices();
        let on_edge = lerp(v[edge % v.len()], v[(edge + 1) % v.len()], t);
        for p in [q, on_edge, v[edge % v.len()], poly.centroid()] {
            let d = poly.distance(p);
            prop_assert!(d >= 0.0);
            prop_assert_eq!(d == 0.0, poly.contains(p), "{} at distance {}", p, d);
            let sd = poly.signed_distance(p);
            let consistent = if poly.contains(p) { sd <= 0.0 } else { sd > 0.0 && (sd - d).abs() <= 1e-12 * scale(&poly, p) };
            prop_assert!(consistent, "signed distance {} vs distance {}", sd, d);
            prop_assert!((poly.closest_point(p).distance(p) - d).abs() <= 1e-9 * scale(&poly, p));
        }
        prop_assert!(poly.contains(poly.centroid()));
        prop_assert!(poly.aabb().expanded(1e-12 * scale(&poly, on_edge)).contains_point(on_edge));
    }

    #[test]
    fn ray_hits_lie_on_the_boundary(poly in polygon(), origin in point(120.0), angle in 0.0..TAU, max_dist in 0.0..400.0f64) {
        let dir = DVec2::from_angle(angle);
        let tol = 1e-9 * scale(&poly, origin);
        match poly.ray_cast(origin, dir, max_dist) {
            Some(0.0) => prop_assert!(poly.contains(origin)),
            Some(t) => {
                prop_assert!(!poly.contains(origin));
                prop_assert!(t <= max_dist);
                let hit = origin + dir * t;
                prop_assert!(poly.signed_distance(hit).abs() < tol, "hit {} sd {}", hit, poly.signed_distance(hit));
                for k in 0..32 {
                    let s = (t - tol).max(0.0) * k as f64 / 31.0;
                    prop_assert!(!poly.contains(origin + dir * s), "inside at {} before hit at {}", s, t);
                }
            }
            None => {
                for k in 0..32 {
                    let s = max_dist * k as f64 / 31.0;
                    prop_assert!(poly.signed_distance(origin + dir * s) > -tol, "missed inside point at {}", s);
                }
            }
        }
    }

    #[test]
    fn circle_queries_agree(center in point(50.0), radius in 0.0..10.0f64, origin in point(80.0), angle in 0.0..TAU) {
        let circle = Shape::circle(center, radius).unwrap();
        let dir = DVec2::from_angle(angle);
        prop_assert_eq!(circle.distance(origin) == 0.0, circle.contains(origin));
        prop_assert!(circle.distance(origin) >= 0.0);
        match circle.ray_cast(origin, dir, 200.0) {
            Some(0.0) => prop_assert!(circle.contains(origin)),
            Some(t) => {
                prop_assert!(circle.signed_distance(origin + dir * t).abs() < 1e-9 * 100.0);
                prop_assert!(!circle.contains(origin + dir * (t - 1e-7).max(0.0)));
            }
            None => prop_assert!(circle.signed_distance(origin + dir * (origin - center).dot(-dir).clamp(0.0, 200.0)) > -1e-9),
        }
    }

    #[test]
    fn floor_to_integer_agrees_with_the_float_floor(x in prop::num::f64::ANY, small in -1e6..1e6f64) {
        for v in [x, small, small.round(), -small.fract()] {
            prop_assert_eq!(floor_i64(v), v.floor() as i64, "{}", v);
        }
    }

    #[test]
    fn grown_polygon_contains_the_rounded_shape(
        poly in polygon(),
        r in 0.01..5.0f64,
        segments in 4usize..40,
        samples in prop::collection::vec((0usize..64, 0.0..1.0f64, 0.0..TAU, 0.0..=1.0f64), 16),
    ) {
        let g = poly.grown(r, segments).unwrap();
        prop_assert!(is_strictly_convex_ccw(&g));
        // The same polygon as the hull of its points, up to where the loop starts.
        let hull = ConvexPolygon::hull(g.vertices()).unwrap();
        let (a, b) = (g.vertices(), hull.vertices());
        prop_assert_eq!(a.len(), b.len());
        let start = b.iter().position(|&p| p == a[0]);
        prop_assert!(start.is_some_and(|s| (0..a.len()).all(|k| a[k] == b[(s + k) % b.len()])));
        prop_assert!(g.area() >= poly.area());
        let v = poly.vertices();
        for (edge, t, angle, s) in samples {
            let base = lerp(v[edge % v.len()], v[(edge + 1) % v.len()], t);
            for q in [base, v[edge % v.len()]] {
                let p = q + DVec2::from_angle(angle) * (r * s);
                prop_assert!(g.contains(p), "{} (dist {}) outside grown polygon", p, poly.distance(p));
            }
        }
    }

    #[test]
    fn decomposition_tiles_star_outlines(outline in star_outline()) {
        check_decomposition(&outline)?;
    }

    #[test]
    fn decomposition_tiles_histogram_outlines(outline in histogram_outline()) {
        check_decomposition(&outline)?;
    }

    #[test]
    fn circle_query_matches_brute_force(items in boxes(), center in point(70.0), radius in 0.0..20.0f64) {
        let index = SpatialIndex::build(&items);
        let mut got = Vec::with_capacity(items.len().max(1));
        let buffer = got.as_ptr();
        index.query_circle(center, radius, &mut got);
        prop_assert_eq!(got.as_ptr(), buffer, "query reallocated");
        let want: Vec<usize> = (0..items.len()).filter(|&i| items[i].distance(center) <= radius).collect();
        prop_assert_eq!(got, want);
    }

    #[test]
    fn ray_query_matches_brute_force(items in boxes(), origin in point(70.0), dir in point(2.0), max_dist in 0.0..100.0f64) {
        let index = SpatialIndex::build(&items);
        let mut got = Vec::new();
        index.query_ray(origin, dir, max_dist, &mut got);
        let want: Vec<usize> = (0..items.len()).filter(|&i| items[i].intersects_segment(origin, dir, max_dist)).collect();
        prop_assert_eq!(got, want);
    }

    #[test]
    fn segment_distance_matches_dense_sampling(poly in polygon(), a in point(120.0), b in point(120.0), r in 0.1..20.0f64, c in point(60.0)) {
        // The exact distance is never more than the distance of sampled points and never less
        // than the smallest sample minus half the sample spacing.
        for shape in [Shape::from(poly), Shape::circle(c, r).unwrap()] {
            let d = shape.segment_distance(a, b);
            let n = 4000;
            let samples = (0..=n).map(|k| shape.distance(lerp(a, b, k as f64 / n as f64))).fold(f64::INFINITY, f64::min);
            let spacing = a.distance(b) / n as f64;
            prop_assert!(d <= samples + 1e-9, "exact {d} above sampled {samples}");
            prop_assert!(d >= samples - spacing - 1e-9, "exact {d} below sampled {samples} by more than {spacing}");
            prop_assert!(d >= 0.0);
        }
    }

    #[test]
    fn capsule_query_finds_everything_within_reach(items in boxes(), a in point(70.0), b in point(70.0), radius in 0.0..10.0f64) {
        let index = SpatialIndex::build(&items);
        let mut got = Vec::new();
        index.query_capsule(a, b, radius, &mut got);
        for (i, bx) in items.iter().enumerate() {
            // Distance from the box to the segment, by sampling the segment densely.
            let n = 400;
            let d = (0..=n).map(|k| bx.distance(lerp(a, b, k as f64 / n as f64))).fold(f64::INFINITY, f64::min);
            if d + a.distance(b) / n as f64 <= radius {
                prop_assert!(got.contains(&i), "box {i} at {d} m missed");
            }
        }
    }
}

fn check_decomposition(outline: &[DVec2]) -> Result<(), TestCaseError> {
    let pieces = decompose(outline).map_err(|e| TestCaseError::fail(format!("{e}")))?;
    let area = shoelace(outline);
    let total: f64 = pieces.iter().map(ConvexPolygon::area).sum();
    prop_assert!((total - area).abs() <= 1e-9 * area.max(1.0), "pieces sum to {} but outline has {}", total, area);
    prop_assert!(pieces.len() <= outline.len() - 2);
    for (i, piece) in pieces.iter().enumerate() {
        prop_assert!(is_strictly_convex_ccw(piece));
        for v in piece.vertices() {
            prop_assert!(outline.contains(v));
        }
        let c = piece.centroid();
        for (j, other) in pieces.iter().enumerate() {
            if i != j {
                prop_assert!(other.signed_distance(c) >= 0.0, "pieces {} and {} overlap", i, j);
            }
        }
    }
    Ok(())
}

/// A point in three dimensions.
fn point3(range: f64) -> impl Strategy<Value = glam::DVec3> {
    (-range..range, -range..range, -range..range).prop_map(|(x, y, z)| glam::DVec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// The prism's signed distance agrees with containment, is 1-Lipschitz, and equals the
    /// distance to the prism's surface sampled independently (the outline's boundary and the
    /// caps) from outside.
    #[test]
    fn prism_distance_is_the_distance_to_the_solid(
        poly in polygon(), circle in (point(30.0), 0.5..20.0f64), use_circle in any::<bool>(),
        z in (-5.0..5.0f64, 0.1..10.0f64), p in point3(60.0), q in point3(60.0)
    ) {
        use strider::geom::Prism;
        let base = if use_circle { Shape::circle(circle.0, circle.1).unwrap() } else { Shape::Polygon(poly) };
        let prism = Prism { base: &base, z_min: z.0, z_max: z.0 + z.1 };
        let d = prism.signed_distance(p);
        let inside = base.contains(p.truncate()) && (prism.z_min..=prism.z_max).contains(&p.z);
        prop_assert_eq!(d <= 0.0, inside, "{} at {}", d, p);
        prop_assert!((d - prism.signed_distance(q)).abs() <= p.distance(q) + 1e-9);
        if !inside {
            // The nearest point of the solid: the outline's closest point, at the height
            // clamped into the interval.
            let flat = base.closest_point(p.truncate());
            let nearest = flat.extend(p.z.clamp(prism.z_min, prism.z_max));
            prop_assert!((d - p.distance(nearest)).abs() < 1e-9, "{} vs {}", d, p.distance(nearest));
        }
    }

    /// The segment's distance is the least of the distances of its points: never above any
    /// sample, and below the densest samples by no more than their spacing allows.
    #[test]
    fn segment_distance_is_the_least_over_the_segment(
        poly in polygon(), z in (-5.0..5.0f64, 0.1..10.0f64), a in point3(60.0), b in point3(60.0), r in 0.0..2.0f64
    ) {
        use strider::geom::{Capsule, Prism};
        let base = Shape::Polygon(poly);
        let prism = Prism { base: &base, z_min: z.0, z_max: z.0 + z.1 };
        let (d, t) = prism.segment_distance(a, b);
        prop_assert!((0.0..=1.0).contains(&t));
        prop_assert!((d - prism.signed_distance(a.lerp(b, t))).abs() < 1e-9);
        const N: usize = 2000;
        let sampled = (0..=N).map(|i| prism.signed_distance(a.lerp(b, i as f64 / N as f64))).fold(f64::INFINITY, f64::min);
        prop_assert!(d <= sampled + 1e-9, "{} above a sample {}", d, sampled);
        prop_assert!(d >= sampled - a.distance(b) / (2 * N) as f64 - 1e-9, "{} far below the samples {}", d, sampled);
        let c = Capsule { a, b, radius: r };
        prop_assert!((prism.capsule_clearance(&c) - (d - r)).abs() < 1e-12);
    }
}

#[test]
fn floor_to_integer_agrees_at_the_edges() {
    let edges = [
        0.0,
        -0.0,
        -0.5,
        0.5,
        -1.0,
        f64::MIN_POSITIVE,
        -f64::MIN_POSITIVE,
        i64::MAX as f64,
        i64::MIN as f64,
        4_503_599_627_370_495.5,
        -4_503_599_627_370_495.5,
        -9.3e18,
        1e300,
        -1e300,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];
    for v in edges {
        assert_eq!(floor_i64(v), v.floor() as i64, "{v}");
    }
}
