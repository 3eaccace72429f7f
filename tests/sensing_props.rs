//! The fast all-around sensing gives exactly what the plain one gives: the fan of rays cast
//! against the obstacles gathered once (`World::ray_fan`), and any bundle of rays from one
//! point (`World::ray_casts`), hit where each ray cast on its own (`World::ray_cast`) hits, and
//! the windowed swept free distances (`swept_free`, `swept_free_ahead`) equal the per-ray
//! definition (`swept_free_along`) on every ray, bit for bit.

use glam::DVec2;
use proptest::prelude::*;
use strider::maps::kind::{self, WorldKind};
use strider::sim::sense::{Fan, swept_free, swept_free_ahead, swept_free_along};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn the_ray_fan_hits_where_each_ray_hits(
        kind in prop::sample::select(vec![WorldKind::Cluttered, WorldKind::Rooms, WorldKind::Maze, WorldKind::Grid]),
        seed in 0u64..1000,
        at in (0.0..1.0f64, 0.0..1.0f64),
        n in 1usize..200,
        max in 0.1..12.0f64,
    ) {
        let world = kind::generate(kind, seed).world();
        let bounds = world.bounds().expect("obstacles");
        let origin = bounds.min - DVec2::splat(2.0) + (bounds.max - bounds.min + DVec2::splat(4.0)) * DVec2::new(at.0, at.1);
        let fan = Fan::of(n);
        let (mut scratch, mut out) = (Vec::new(), Vec::new());
        world.ray_fan(origin, &fan.rays, max, &mut scratch, &mut out);
        prop_assert_eq!(out.len(), n);
        for (k, &dir) in fan.rays.iter().enumerate() {
            let one = world.ray_cast(origin, dir, max, &mut scratch).unwrap_or(f64::INFINITY);
            prop_assert_eq!(out[k].to_bits(), one.to_bits(), "ray {} of {} from {}", k, n, origin);
        }
    }

    #[test]
    fn a_bundle_of_rays_hits_where_each_ray_hits(
        kind in prop::sample::select(vec![WorldKind::Cluttered, WorldKind::Rooms, WorldKind::Maze, WorldKind::Grid]),
        seed in 0u64..1000,
        at in (0.0..1.0f64, 0.0..1.0f64),
        angles in prop::collection::vec(-4.0..4.0f64, 1..40),
        max in 0.1..12.0f64,
    ) {
        let world = kind::generate(kind, seed).world();
        let bounds = world.bounds().expect("obstacles");
        let origin = bounds.min - DVec2::splat(2.0) + (bounds.max - bounds.min + DVec2::splat(4.0)) * DVec2::new(at.0, at.1);
        let dirs: Vec<DVec2> = angles.iter().map(|&a| DVec2::from_angle(a)).collect();
        let (mut scratch, mut out) = (Vec::new(), vec![0.0; dirs.len()]);
        world.ray_casts(origin, &dirs, max, &mut scratch, &mut out);
        for (k, &dir) in dirs.iter().enumerate() {
            let one = world.ray_cast(origin, dir, max, &mut scratch).unwrap_or(f64::INFINITY);
            prop_assert_eq!(out[k].to_bits(), one.to_bits(), "ray {} from {}", k, origin);
        }
    }

    #[test]
    fn windowed_swept_free_is_the_per_ray_definition(
        scan in prop::collection::vec(prop_oneof![3 => 0.0..6.0f64, 1 => Just(5.0f64)], 1..150),
        radius in 0.0..1.5f64,
    ) {
        let range = 5.0;
        let n = scan.len();
        let fan = Fan::of(n);
        let fast = swept_free(&scan, radius, range);
        for (i, f) in fast.iter().enumerate() {
            let slow = swept_free_along(&scan, i, radius, radius, range, |d| fan.turns[d]);
            prop_assert_eq!(f.to_bits(), slow.to_bits(), "ray {} of {}", i, n);
        }
    }

    #[test]
    fn the_swept_free_distance_ahead_is_the_per_ray_definition(
        scan in prop::collection::vec(prop_oneof![3 => 0.0..6.0f64, 1 => Just(5.0f64)], 1..150),
        radius in 0.0..1.5f64,
        clearance in 0.0..0.5f64,
    ) {
        let range = 5.0;
        let n = scan.len();
        let fan = Fan::of(n);
        for i in 0..n {
            let fast = swept_free_ahead(&scan, i, radius, radius + clearance, range, &fan.turns);
            let slow = swept_free_along(&scan, i, radius, radius + clearance, range, |d| fan.turns[d]);
            prop_assert_eq!(fast.to_bits(), slow.to_bits(), "ray {} of {}", i, n);
        }
    }
}
