//! Terrain height over the XY plane (seed 002 §3.2, §4; DESIGN.md §1, §4): flat ground at
//! height 0 with features laid over it — raised platforms (steps, stepping stones, the tops of
//! low obstacles), slopes, stairs, and holes where there is no foothold at all.
//!
//! Features are painted in order: where several cover a point, the last one given decides the
//! ground there (a hole then stones on it make stepping stones over a gap). Slopes and stairs
//! are boxes whose height runs along the box's own x axis: a slope rises linearly from `z0`
//! at the box's −x side to `z1` at its +x side; stairs of `n` treads split the box into `n`
//! equal treads along that axis, tread `k` (from the −x side) at `z0 + (z1 − z0)·(k + 1)/(n + 1)`,
//! so ground at `z0` before them and at `z1` after them is reached by `n + 1` equal risers.
//!
//! Obstacles whose top is at most [`STEP_ONTO_MAX_Z_M`](super::obstacle::STEP_ONTO_MAX_Z_M)
//! above the ground (and whose bottom is on it) are no walls ([`Obstacle::is_low`]):
//! [`Terrain::with_low_obstacles`] turns them into platforms at their `z_max`, to be stepped
//! onto or over.
//!
//! [`Terrain::profile`] cuts the terrain with a vertical plane — the character's sagittal
//! plane along its path — into the 1-D [`GroundProfile`] of the footstep planner: the exact
//! intersection, with gaps where there is a hole and vertical steps at platform and tread
//! edges.
//!
//! Invariants: a [`Terrain`] only holds validated features (finite numbers within range, slopes
//! and stairs on boxes, 1 ≤ n ≤ [`MAX_STAIR_TREADS`]); queries are pure and never panic;
//! `profile` is deterministic and returns pieces in increasing X.

use std::fmt;

use glam::DVec2;

use crate::geom::Shape;
use crate::ground::{GroundPiece, GroundProfile};
use crate::world::obstacle::{Obstacle, ObstacleShape};

/// Largest number of treads of one flight of stairs.
pub const MAX_STAIR_TREADS: usize = 1000;
/// Largest terrain height magnitude accepted, metres.
pub const MAX_HEIGHT_M: f64 = 1000.0;
/// Intersections closer than this along a profile are one, metres.
const PROFILE_EPS_M: f64 = 1e-9;

/// How a feature shapes the ground inside its outline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FeatureKind {
    /// Flat ground at height `z_m`.
    Platform {
        /// Height, metres.
        z_m: f64,
    },
    /// Ground rising linearly along the box's x axis (box outlines only).
    Slope {
        /// Height at the box's −x side, metres.
        z0_m: f64,
        /// Height at the box's +x side, metres.
        z1_m: f64,
    },
    /// `treads` flat treads along the box's x axis (box outlines only), see the
    /// [module docs](self).
    Stairs {
        /// Ground height before the first tread, metres.
        z0_m: f64,
        /// Ground height after the last tread, metres.
        z1_m: f64,
        /// Number of treads.
        treads: usize,
    },
    /// No ground: no foothold anywhere inside.
    Hole,
}

/// One terrain feature: an outline and what the ground is like inside it.
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainFeature {
    /// The outline (same descriptions as obstacles).
    pub shape: ObstacleShape,
    /// What the ground is inside.
    pub kind: FeatureKind,
    parts: Vec<Shape>,
}

/// Why a terrain feature cannot be built.
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainError(pub String);

impl fmt::Display for TerrainError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for TerrainError {}

impl TerrainFeature {
    /// Builds and checks a feature: a valid outline, finite heights within ±[`MAX_HEIGHT_M`],
    /// slopes and stairs on boxes, 1–[`MAX_STAIR_TREADS`] treads.
    pub fn new(shape: ObstacleShape, kind: FeatureKind) -> Result<TerrainFeature, TerrainError> {
        let height = |what: &str, z: f64| {
            if z.is_finite() && z.abs() <= MAX_HEIGHT_M {
                Ok(())
            } else {
                Err(TerrainError(format!("{what} must be a finite height within ±{MAX_HEIGHT_M} m, found {z}")))
            }
        };
        match kind {
            FeatureKind::Platform { z_m } => height("platform height", z_m)?,
            FeatureKind::Slope { z0_m, z1_m } | FeatureKind::Stairs { z0_m, z1_m, .. } => {
                height("z0", z0_m)?;
                height("z1", z1_m)?;
                if !matches!(shape, ObstacleShape::Box { .. }) {
                    return Err(TerrainError("slopes and stairs must be boxes".into()));
                }
            }
            FeatureKind::Hole => {}
        }
        if let FeatureKind::Stairs { treads, .. } = kind
            && !(1..=MAX_STAIR_TREADS).contains(&treads)
        {
            return Err(TerrainError(format!("stairs need 1 to {MAX_STAIR_TREADS} treads, found {treads}")));
        }
        let parts = Obstacle::build(shape.clone(), 0.0, 1.0).map_err(|e| TerrainError(e.to_string()))?.parts;
        Ok(TerrainFeature { shape, kind, parts })
    }

    /// Whether `p` lies inside the outline (boundary included).
    pub fn contains(&self, p: DVec2) -> bool {
        self.parts.iter().any(|s| s.contains(p))
    }

    /// The convex parts of the outline.
    pub fn parts(&self) -> &[Shape] {
        &self.parts
    }

    /// The box's centre, x axis and half width, for slopes and stairs.
    fn axis(&self) -> Option<(DVec2, DVec2, f64)> {
        match self.shape {
            ObstacleShape::Box { center, width, yaw, .. } => Some((center, DVec2::from_angle(yaw), width / 2.0)),
            _ => None,
        }
    }

    /// Where `p` lies along the box's x axis, 0 at the −x side and 1 at the +x side.
    fn along(&self, p: DVec2) -> f64 {
        match self.axis() {
            Some((c, a, h)) => ((p - c).dot(a) + h) / (2.0 * h),
            None => 0.0,
        }
    }

    /// The ground height this feature gives at `p` (extended beyond the outline; `None` for a
    /// hole). Stairs take the tread `tread` when given, else the one under `p`.
    fn height_at(&self, p: DVec2, tread: Option<usize>) -> Option<f64> {
        match self.kind {
            FeatureKind::Platform { z_m } => Some(z_m),
            FeatureKind::Slope { z0_m, z1_m } => Some(z0_m + (z1_m - z0_m) * self.along(p)),
            FeatureKind::Stairs { z0_m, z1_m, treads } => {
                let k = tread.unwrap_or_else(|| tread_of(self.along(p), treads));
                Some(z0_m + (z1_m - z0_m) * (k + 1) as f64 / (treads + 1) as f64)
            }
            FeatureKind::Hole => None,
        }
    }
}

fn tread_of(u: f64, treads: usize) -> usize {
    let k = (u * treads as f64).floor();
    if k.is_nan() { 0 } else { k.clamp(0.0, (treads - 1) as f64) as usize }
}

/// Ground height as a function of position.
#[derive(Debug, Clone, Default, PartialEq)]
pub enum Terrain {
    /// Height 0 everywhere.
    #[default]
    Flat,
    /// Height 0 with features laid over it, in order (the last one covering a point decides).
    Uneven(Vec<TerrainFeature>),
}

impl Terrain {
    /// Terrain of `features` (flat when there are none).
    pub fn from_features(features: Vec<TerrainFeature>) -> Terrain {
        if features.is_empty() { Terrain::Flat } else { Terrain::Uneven(features) }
    }

    /// The features, in order.
    pub fn features(&self) -> &[TerrainFeature] {
        match self {
            Terrain::Flat => &[],
            Terrain::Uneven(f) => f,
        }
    }

    /// True for flat ground everywhere.
    pub fn is_flat(&self) -> bool {
        self.features().is_empty()
    }

    /// This terrain with the low obstacles among `obstacles` ([`Obstacle::is_low`]) laid over it
    /// as platforms at their tops.
    pub fn with_low_obstacles(&self, obstacles: &[Obstacle]) -> Terrain {
        let mut features = self.features().to_vec();
        for o in obstacles.iter().filter(|o| o.is_low()) {
            features.push(TerrainFeature {
                shape: o.shape.clone(),
                kind: FeatureKind::Platform { z_m: o.z_max },
                parts: o.parts.clone(),
            });
        }
        Terrain::from_features(features)
    }

    /// The feature deciding the ground at `p`, if any.
    fn top_at(&self, p: DVec2) -> Option<&TerrainFeature> {
        self.features().iter().rev().find(|f| f.contains(p))
    }

    /// Ground height at `p`, metres; `None` over a hole.
    pub fn ground(&self, p: DVec2) -> Option<f64> {
        match self.top_at(p) {
            None => Some(0.0),
            Some(f) => f.height_at(p, None),
        }
    }

    /// Ground height at `p`, metres (0 over a hole).
    pub fn height(&self, p: DVec2) -> f64 {
        self.ground(p).unwrap_or(0.0)
    }

    /// The ground cut by the vertical plane through `origin` along the unit direction `dir`,
    /// from `x0_m` to `x1_m` along it (X = distance from `origin`): straight pieces with gaps
    /// over holes. `None` when there is no ground at all in that range.
    pub fn profile(&self, origin: DVec2, dir: DVec2, x0_m: f64, x1_m: f64) -> Option<GroundProfile> {
        self.strip_profile(origin, dir, x0_m, x1_m, &[0.0], 0.0)
    }

    /// The ground under a strip along the path: the profiles of the lines at `offsets` metres
    /// to the left of the vertical plane through `origin` along `dir` (see
    /// [`Terrain::profile`]), taken together. There is ground at X only where every line has
    /// some and their heights there differ by at most `tolerance_m`, at the highest of them; a
    /// hole or an edge under any line is a gap. `None` when no ground is left.
    ///
    /// One pass cuts every line: each feature's outline (and a flight's tread edges) is
    /// clipped against all the lines, the cuts of all of them sorted together, and between two
    /// neighbouring cuts every line's ground is one straight piece, read off the feature on
    /// top there.
    pub fn strip_profile(
        &self,
        origin: DVec2,
        dir: DVec2,
        x0_m: f64,
        x1_m: f64,
        offsets: &[f64],
        tolerance_m: f64,
    ) -> Option<GroundProfile> {
        let dir = dir.normalize_or_zero();
        if dir == DVec2::ZERO || !(x1_m > x0_m) || !origin.is_finite() || offsets.is_empty() {
            return None;
        }
        let side = dir.perp();
        let lines: Vec<DVec2> = offsets.iter().map(|&o| origin + side * o).collect();
        if !lines.iter().all(|l| l.is_finite()) {
            return None;
        }
        let mut cuts = vec![x0_m, x1_m];
        for f in self.features() {
            for &o in &lines {
                for part in &f.parts {
                    if let Some((a, b)) = clip(part, o, dir, x0_m, x1_m) {
                        cuts.push(a);
                        cuts.push(b);
                    }
                }
                if let (FeatureKind::Stairs { treads, .. }, Some((c, a, h))) = (f.kind, f.axis()) {
                    let rate = dir.dot(a);
                    if rate.abs() > 1e-12 {
                        for k in 1..treads {
                            let s = -h + 2.0 * h * k as f64 / treads as f64;
                            let t = (s - (o - c).dot(a)) / rate;
                            if t > x0_m && t < x1_m {
                                cuts.push(t);
                            }
                        }
                    }
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|b, a| (*b - *a).abs() <= PROFILE_EPS_M);
        let mut pieces: Vec<GroundPiece> = Vec::new();
        'span: for w in cuts.windows(2) {
            let (a, b) = (w[0], w[1]);
            if b - a <= PROFILE_EPS_M {
                continue;
            }
            let (mut za, mut zb) = ([f64::INFINITY, f64::NEG_INFINITY], [f64::INFINITY, f64::NEG_INFINITY]);
            for &o in &lines {
                let Some((ha, hb)) = self.span_heights(o, dir, a, b) else { continue 'span };
                za = [za[0].min(ha), za[1].max(ha)];
                zb = [zb[0].min(hb), zb[1].max(hb)];
            }
            if za[1] - za[0] > tolerance_m || zb[1] - zb[0] > tolerance_m {
                continue;
            }
            push_piece(&mut pieces, GroundPiece { x0_m: a, z0_m: za[1], x1_m: b, z1_m: zb[1] });
        }
        GroundProfile::new(pieces).ok()
    }

    /// The ground's heights at X = `a` and `b` on the line through `origin` along `dir`, where
    /// no cut lies between them (one feature on top all along): `None` over a hole.
    fn span_heights(&self, origin: DVec2, dir: DVec2, a: f64, b: f64) -> Option<(f64, f64)> {
        let at = |t: f64| origin + dir * t;
        let mid = at(0.5 * (a + b));
        match self.top_at(mid) {
            None => Some((0.0, 0.0)),
            Some(f) => {
                let tread = match f.kind {
                    FeatureKind::Stairs { treads, .. } => Some(tread_of(f.along(mid), treads)),
                    _ => None,
                };
                Some((f.height_at(at(a), tread)?, f.height_at(at(b), tread)?))
            }
        }
    }
}

/// Appends `piece`, continuing the last one when it is the same straight line.
fn push_piece(pieces: &mut Vec<GroundPiece>, piece: GroundPiece) {
    if let Some(last) = pieces.last_mut()
        && last.x1_m == piece.x0_m
        && last.z1_m == piece.z0_m
        && (piece.rise_per_m() - last.rise_per_m()).abs() < 1e-12
    {
        last.x1_m = piece.x1_m;
        last.z1_m = piece.z1_m;
        return;
    }
    pieces.push(piece);
}

/// The parameter range `[a, b]` within `[t0, t1]` over which `origin + t·dir` lies in `shape`.
fn clip(shape: &Shape, origin: DVec2, dir: DVec2, t0: f64, t1: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (t0, t1);
    match shape {
        Shape::Circle { center, radius } => {
            let d = origin - *center;
            let b = d.dot(dir);
            let disc = b * b - (d.length_squared() - radius * radius);
            if disc <= 0.0 {
                return None;
            }
            let r = disc.sqrt();
            lo = lo.max(-b - r);
            hi = hi.min(-b + r);
        }
        Shape::Polygon(poly) => {
            // Cyrus–Beck against each edge of the counter-clockwise polygon.
            for (p, q) in poly.edges() {
                let e = q - p;
                let normal = DVec2::new(e.y, -e.x);
                let num = (origin - p).dot(normal);
                let den = dir.dot(normal);
                if den.abs() < 1e-15 {
                    if num > 0.0 {
                        return None;
                    }
                    continue;
                }
                let t = -num / den;
                if den < 0.0 {
                    lo = lo.max(t);
                } else {
                    hi = hi.min(t);
                }
            }
        }
    }
    (hi - lo > PROFILE_EPS_M).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_2;

    use super::*;

    fn boxed(cx: f64, cy: f64, w: f64, h: f64) -> ObstacleShape {
        ObstacleShape::Box { center: DVec2::new(cx, cy), width: w, height: h, yaw: 0.0 }
    }

    #[test]
    fn heights_of_each_kind() {
        let t = Terrain::from_features(vec![
            TerrainFeature::new(boxed(2.0, 0.0, 2.0, 2.0), FeatureKind::Platform { z_m: 0.2 }).unwrap(),
            TerrainFeature::new(boxed(6.0, 0.0, 2.0, 2.0), FeatureKind::Slope { z0_m: 0.0, z1_m: 0.4 }).unwrap(),
            TerrainFeature::new(boxed(10.0, 0.0, 2.0, 2.0), FeatureKind::Stairs { z0_m: 0.0, z1_m: 0.6, treads: 2 })
                .unwrap(),
            TerrainFeature::new(boxed(14.0, 0.0, 2.0, 2.0), FeatureKind::Hole).unwrap(),
        ]);
        assert_eq!(t.ground(DVec2::new(0.0, 0.0)), Some(0.0));
        assert_eq!(t.ground(DVec2::new(2.5, 0.5)), Some(0.2));
        assert!((t.height(DVec2::new(6.5, 0.0)) - 0.3).abs() < 1e-12);
        assert!((t.height(DVec2::new(9.5, 0.0)) - 0.2).abs() < 1e-12);
        assert!((t.height(DVec2::new(10.5, 0.0)) - 0.4).abs() < 1e-12);
        assert_eq!(t.ground(DVec2::new(14.0, 0.0)), None);
        assert!(!t.is_flat() && Terrain::Flat.is_flat());
    }

    #[test]
    fn later_features_cover_earlier_ones() {
        let t = Terrain::from_features(vec![
            TerrainFeature::new(boxed(5.0, 0.0, 4.0, 4.0), FeatureKind::Hole).unwrap(),
            TerrainFeature::new(
                ObstacleShape::Cylinder { center: DVec2::new(5.0, 0.0), radius: 0.3 },
                FeatureKind::Platform { z_m: 0.1 },
            )
            .unwrap(),
        ]);
        assert_eq!(t.ground(DVec2::new(5.1, 0.0)), Some(0.1));
        assert_eq!(t.ground(DVec2::new(4.0, 0.0)), None);
        let p = t.profile(DVec2::new(0.0, 0.0), DVec2::X, -1.0, 10.0).unwrap();
        let pieces = p.pieces();
        assert_eq!(pieces.len(), 3, "{pieces:?}");
        assert!((pieces[0].x1_m - 3.0).abs() < 1e-9);
        assert!((pieces[1].x0_m - 4.7).abs() < 1e-9 && (pieces[1].x1_m - 5.3).abs() < 1e-9);
        assert_eq!(pieces[1].z0_m, 0.1);
        assert!((pieces[2].x0_m - 7.0).abs() < 1e-9);
    }

    #[test]
    fn profiles_cut_stairs_and_slopes_exactly() {
        let t = Terrain::from_features(vec![
            TerrainFeature::new(boxed(3.0, 0.0, 3.0, 2.0), FeatureKind::Stairs { z0_m: 0.0, z1_m: 0.8, treads: 3 })
                .unwrap(),
            TerrainFeature::new(boxed(6.0, 0.0, 3.0, 2.0), FeatureKind::Slope { z0_m: 0.8, z1_m: 0.2 }).unwrap(),
        ]);
        let p = t.profile(DVec2::new(0.0, 0.0), DVec2::X, 0.0, 9.0).unwrap();
        let z: Vec<(f64, f64, f64, f64)> = p.pieces().iter().map(|q| (q.x0_m, q.z0_m, q.x1_m, q.z1_m)).collect();
        assert_eq!(z.len(), 6, "{z:?}");
        assert!((z[1].1 - 0.2).abs() < 1e-12 && (z[1].0 - 1.5).abs() < 1e-9 && (z[1].2 - 2.5).abs() < 1e-9);
        assert!((z[3].1 - 0.6).abs() < 1e-12);
        assert!((z[4].1 - 0.8).abs() < 1e-12 && (z[4].3 - 0.2).abs() < 1e-12);
        // A diagonal cut crosses the treads at the same heights.
        let d = t.profile(DVec2::new(0.0, -1.0), DVec2::new(1.0, 0.3).normalize(), 0.0, 5.0).unwrap();
        assert!(d.pieces().iter().any(|q| (q.z0_m - 0.4).abs() < 1e-12));
    }

    #[test]
    fn a_strip_is_ground_only_where_every_line_agrees() {
        let t = Terrain::from_features(vec![
            // A hole beside the path: under the left lines only.
            TerrainFeature::new(boxed(2.0, 0.12, 0.4, 0.1), FeatureKind::Hole).unwrap(),
            // A step crossed at an angle: its edge is at different X on each line.
            TerrainFeature::new(
                ObstacleShape::Box { center: DVec2::new(5.0, 0.0), width: 2.0, height: 2.0, yaw: 0.3 },
                FeatureKind::Platform { z_m: 0.2 },
            )
            .unwrap(),
            // A gentle slope across the path: heights differ by under 2 cm across the strip.
            TerrainFeature::new(
                ObstacleShape::Box { center: DVec2::new(8.0, 0.0), width: 2.0, height: 1.0, yaw: FRAC_PI_2 },
                FeatureKind::Slope { z0_m: 0.0, z1_m: 0.12 },
            )
            .unwrap(),
        ]);
        let offsets = [-0.14, -0.04, 0.04, 0.14];
        let centre = t.profile(DVec2::ZERO, DVec2::X, 0.0, 10.0).unwrap();
        let strip = t.strip_profile(DVec2::ZERO, DVec2::X, 0.0, 10.0, &offsets, 0.03).unwrap();
        // The centre line sees no hole; the strip does.
        assert_eq!(centre.height_at(2.0), Some(0.0));
        assert_eq!(strip.height_at(2.0), None);
        assert_eq!(strip.height_at(1.7), Some(0.0));
        // Where the lines cross the step's edge at different X, there is no foothold; on the
        // step's top there is.
        let edge = [-0.14, 0.14].map(|y| t.profile(DVec2::new(0.0, y), DVec2::X, 0.0, 10.0).unwrap());
        let starts = edge.map(|p| p.pieces().iter().find(|q| q.z0_m == 0.2).unwrap().x0_m);
        let (lo, hi) = (starts[0].min(starts[1]), starts[0].max(starts[1]));
        assert!(hi - lo > 0.05, "{starts:?}");
        assert_eq!(strip.height_at(0.5 * (lo + hi)), None);
        assert_eq!(strip.height_at(5.0), Some(0.2));
        // Across the slope the strip stands at its highest line.
        let z = strip.height_at(8.0).unwrap();
        assert!((z - t.ground(DVec2::new(8.0, 0.14)).unwrap()).abs() < 1e-9 && z > 0.06 + 0.005, "{z}");
        // Every point of the strip is ground on every line, within the tolerance, at the highest.
        for x in (0..1000).map(|i| 0.005 + i as f64 * 0.01) {
            if let Some(z) = strip.height_at(x) {
                for y in offsets {
                    let g = t.ground(DVec2::new(x, y));
                    assert!(g.is_some_and(|g| g <= z + 1e-9 && g >= z - 0.03), "x {x} y {y}: {g:?} vs {z}");
                }
            }
        }
    }

    #[test]
    fn low_obstacles_become_ground() {
        let low = Obstacle::build(boxed(2.0, 0.0, 1.0, 1.0), 0.0, 0.3).unwrap();
        let tall = Obstacle::build(boxed(4.0, 0.0, 1.0, 1.0), 0.0, 2.0).unwrap();
        let t = Terrain::Flat.with_low_obstacles(&[low, tall]);
        assert_eq!(t.features().len(), 1);
        assert_eq!(t.ground(DVec2::new(2.0, 0.0)), Some(0.3));
    }

    #[test]
    fn bad_features_are_refused() {
        let cyl = ObstacleShape::Cylinder { center: DVec2::ZERO, radius: 1.0 };
        assert!(TerrainFeature::new(cyl.clone(), FeatureKind::Slope { z0_m: 0.0, z1_m: 1.0 }).is_err());
        assert!(
            TerrainFeature::new(boxed(0.0, 0.0, 1.0, 1.0), FeatureKind::Stairs { z0_m: 0.0, z1_m: 1.0, treads: 0 })
                .is_err()
        );
        assert!(TerrainFeature::new(cyl, FeatureKind::Platform { z_m: f64::NAN }).is_err());
        assert!(TerrainFeature::new(boxed(0.0, 0.0, -1.0, 1.0), FeatureKind::Hole).is_err());
    }
}
