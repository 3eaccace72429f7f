//! The tangent visibility graph over the rims of the grown obstacles, built as the searches
//! need it and kept for every later search in the same world.
//!
//! Rim `first[j] + i` is corner `i` of grown polygon `j` (radius `r`, its cone between the
//! normals of the corner's two edges), or the one rim of grown disc `j` (its whole circle).
//! A rim's *free arcs* are the directions of its cone in which its boundary lies outside every
//! other grown obstacle ([`FreeArcs`]). A *leg* leaves rim `k` bending one way round it and
//! meets rim `m` bending one way round that: the closed-form tangent of the two circles
//! ([`tangent`]), kept when it touches both rims on free arcs and is clear of every other
//! grown obstacle. A leg that touches a rim within its cone is a supporting line of that
//! grown obstacle, so only the other obstacles are tested against it; a taut path only bends
//! round the rims it touches in this way, so no other segment can be on a shortest path.
//!
//! Both a rim's free arcs and its legs are found the first time a search asks for them and
//! kept ([`OnceLock`]): searches in one world, on any thread, share them, and what a search
//! finds does not depend on what earlier searches left (a rim's legs are the same whenever
//! they are found). Looking for the legs leaving a rim one way walks the grown obstacles
//! nearest first from the rim's centre and keeps the directions of the legs already known to
//! be blocked: every point outside the rim lies on exactly one leg leaving it that way
//! ([`sight`]), so a convex stand-in inside a grown obstacle blocks a range of leg
//! directions beyond its farthest point. Rims in those directions and beyond are never
//! tested, whole parts of the spatial index whose box is hidden are passed over, and the walk
//! ends once every direction is hidden, so finding a rim's legs costs what is in sight of it,
//! not the size of the map.

use std::cell::RefCell;
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU8, Ordering};

use glam::DVec2;

use super::clearance::{Blocker, Clearance};
use super::rim::{ANGLE_SLACK, Circle, FreeArcs, Tangent, Turn, angle_of, tangent};
use crate::geom::Aabb;

/// A rim's index in the graph.
pub(crate) type RimId = u32;

/// A straight leg from a rim (or a free point) to a rim.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Leg {
    /// The rim it meets.
    pub(crate) to: RimId,
    /// The way the path bends round that rim.
    pub(crate) turn: Turn,
    /// Direction of the outward normal where it leaves its rim, radians (a point: unused).
    pub(crate) leave: f64,
    /// Direction of the outward normal where it meets `to`, radians.
    pub(crate) arrive: f64,
    /// Where it meets `to`, metres.
    pub(crate) at: DVec2,
    /// Length, metres.
    pub(crate) length: f64,
}

/// The legs leaving one rim one way, by rim met and turn there: every leg that touches both
/// rims on free arcs and is not hidden; whether it is also clear of the other grown obstacles
/// is tested the first time a search asks ([`Legs::is_clear`]) and kept.
#[derive(Debug, Default)]
pub(crate) struct Legs {
    list: Box<[Leg]>,
    /// Per leg: [`UNTESTED`], [`CLEAR`] or [`BLOCKED`].
    clear: Box<[AtomicU8]>,
}

/// States of [`Legs::clear`].
const UNTESTED: u8 = 0;
const CLEAR: u8 = 1;
const BLOCKED: u8 = 2;

impl Legs {
    fn new(list: Vec<Leg>) -> Legs {
        Legs { clear: list.iter().map(|_| AtomicU8::new(UNTESTED)).collect(), list: list.into() }
    }

    /// The legs.
    pub(crate) fn list(&self) -> &[Leg] {
        &self.list
    }

    /// Whether leg `i` is clear, `test` telling the first time. Every thread that asks gets
    /// the same answer (the test is a function of the leg alone).
    fn is_clear(&self, i: usize, test: impl FnOnce() -> bool) -> bool {
        match self.clear[i].load(Ordering::Relaxed) {
            CLEAR => true,
            BLOCKED => false,
            _ => {
                let clear = test();
                self.clear[i].store(if clear { CLEAR } else { BLOCKED }, Ordering::Relaxed);
                clear
            }
        }
    }
}

impl Clone for Legs {
    fn clone(&self) -> Legs {
        let clear = self.clear.iter().map(|c| AtomicU8::new(c.load(Ordering::Relaxed))).collect();
        Legs { list: self.list.clone(), clear }
    }
}

/// The normals a rim's boundary may have: all, or those between two unit normals (the
/// corner's edges' normals, counter-clockwise, less than π apart).
#[derive(Debug, Clone, Copy)]
enum Cone {
    Whole,
    Between(DVec2, DVec2),
}

impl Cone {
    /// Whether the unit normal `n` lies in the cone (within [`ANGLE_SLACK`]); cheap, with no
    /// angle computed.
    fn holds(self, n: DVec2) -> bool {
        match self {
            Cone::Whole => true,
            Cone::Between(lo, hi) => lo.perp_dot(n) >= -ANGLE_SLACK && n.perp_dot(hi) >= -ANGLE_SLACK,
        }
    }

    /// The cone as an angular range `(start, width)`, radians.
    fn range(self) -> (f64, f64) {
        match self {
            Cone::Whole => (-PI, TAU),
            Cone::Between(lo, hi) => (angle_of(lo), lo.perp_dot(hi).atan2(lo.dot(hi)).max(0.0)),
        }
    }
}

/// One rim as the walks see it.
#[derive(Debug, Clone, Copy)]
struct RimView {
    id: RimId,
    circle: Circle,
    cone: Cone,
    owner: usize,
}

/// The rims of the grown obstacles and what the searches have found of their legs.
#[derive(Debug, Clone)]
pub(crate) struct Graph {
    /// First rim of each grown obstacle, and the number of rims last.
    first: Vec<RimId>,
    /// Grown obstacle of each rim.
    owner: Vec<u32>,
    free: Vec<OnceLock<FreeArcs>>,
    /// The legs leaving each rim bending left round it, then those bending right (`2k + turn`).
    legs: Vec<OnceLock<Legs>>,
    /// Rounding slack on how far a rim's points lie outside its obstacle's indexed box, metres.
    stick_out: f64,
    /// How far a point may lie inside a rim and still count as on it, metres.
    touch: f64,
}

/// An occluder's shadow, waiting until the walk passes its far distance.
#[derive(Debug, Clone, Copy)]
struct Pending {
    far: f64,
    lo: f64,
    hi: f64,
}

impl Graph {
    /// The rims of `clearance`'s grown obstacles; their free arcs and legs are found later.
    pub(crate) fn new(clearance: &Clearance) -> Option<Graph> {
        let mut first = Vec::with_capacity(clearance.blockers().len() + 1);
        let mut owner = Vec::new();
        let mut span = 0.0f64;
        for (j, b) in clearance.blockers().iter().enumerate() {
            first.push(u32::try_from(owner.len()).ok()?);
            let count = match b {
                Blocker::Polygon { vertices, .. } => vertices.len(),
                Blocker::Disc { .. } => 1,
            };
            owner.extend(std::iter::repeat_n(u32::try_from(j).ok()?, count));
            if let Some(b) = clearance.grown_aabb(j) {
                span = span.max(b.min.abs().max_element()).max(b.max.abs().max_element());
            }
        }
        first.push(u32::try_from(owner.len()).ok()?);
        let rims = owner.len();
        let (_, eps) = clearance.radius_and_tolerance();
        Some(Graph {
            first,
            owner,
            free: (0..rims).map(|_| OnceLock::new()).collect(),
            legs: (0..2 * rims).map(|_| OnceLock::new()).collect(),
            stick_out: 1e-9 * span.max(1.0),
            touch: 2.0 * eps,
        })
    }

    /// Number of rims.
    pub(crate) fn rim_count(&self) -> usize {
        self.owner.len()
    }

    /// The circle of rim `k`.
    pub(crate) fn circle(&self, clearance: &Clearance, k: RimId) -> Circle {
        self.view(clearance, self.owner[k as usize] as usize, k).circle
    }

    /// Rim `k` of grown obstacle `j`.
    fn view(&self, clearance: &Clearance, j: usize, k: RimId) -> RimView {
        let (r, _) = clearance.radius_and_tolerance();
        match clearance.blocker(j) {
            Blocker::Polygon { vertices, normals } => {
                let i = (k - self.first[j]) as usize;
                let n = vertices.len();
                let cone = Cone::Between(normals[(i + n - 1) % n], normals[i]);
                RimView { id: k, circle: Circle { center: vertices[i], radius: r }, cone, owner: j }
            }
            Blocker::Disc { center, radius } => {
                RimView { id: k, circle: Circle { center: *center, radius: *radius }, cone: Cone::Whole, owner: j }
            }
        }
    }

    /// The free arcs of rim `k`, found once.
    pub(crate) fn free(&self, clearance: &Clearance, k: RimId) -> &FreeArcs {
        self.free[k as usize].get_or_init(|| {
            let rim = self.view(clearance, self.owner[k as usize] as usize, k);
            let mut near = Vec::new();
            clearance.near(rim.circle.center, rim.circle.radius, &mut near);
            near.retain(|&j| j != rim.owner);
            let mut cuts = Vec::new();
            if rim.circle.radius > 0.0 {
                near.iter().for_each(|&j| clearance.cuts(j, rim.circle, &mut cuts));
            }
            let (start, width) = rim.cone.range();
            FreeArcs::of(start, width, &mut cuts, |a| {
                let p = rim.circle.at(a);
                near.iter().any(|&j| clearance.blocks_point(j, p))
            })
        })
    }

    /// The legs leaving rim `k` bending `turn` round it, found once (always with hidden
    /// obstacles skipped).
    pub(crate) fn legs(&self, clearance: &Clearance, k: RimId, turn: Turn) -> &Legs {
        self.legs[2 * k as usize + turn as usize].get_or_init(|| self.find_legs(clearance, k, turn, true))
    }

    /// The legs leaving rim `k` bending `turn` round it, found now; `cull`: skip obstacles
    /// hidden behind nearer ones.
    pub(crate) fn find_legs(&self, clearance: &Clearance, k: RimId, turn: Turn, cull: bool) -> Legs {
        let source = self.view(clearance, self.owner[k as usize] as usize, k);
        let own = self.free(clearance, k);
        if own.is_empty() {
            return Legs::default();
        }
        let mut list = Vec::new();
        self.walk(clearance, source.circle, turn, Some(own), cull, |target, hidden| {
            if target.id == k {
                return;
            }
            for tb in Turn::BOTH {
                let Some(t) = tangent(source.circle, turn, target.circle, tb, self.touch) else { continue };
                if !(source.cone.holds(t.leave) && target.cone.holds(t.arrive)) || hidden(t.dir) {
                    continue;
                }
                let (leave, arrive) = (angle_of(t.leave), angle_of(t.arrive));
                if own.locate(leave).is_some() && self.free(clearance, target.id).locate(arrive).is_some() {
                    list.push(Leg { to: target.id, turn: tb, leave, arrive, at: t.to, length: t.length });
                }
            }
        });
        list.sort_by(|a, b| a.to.cmp(&b.to).then(a.turn.cmp(&b.turn)));
        Legs::new(list)
    }

    /// Whether leg `i` of `legs`, leaving rim `k`, is clear of the grown obstacles other than
    /// the two it touches (which it only touches: it leaves and meets them along a tangent).
    pub(crate) fn leg_clear(&self, clearance: &Clearance, k: RimId, legs: &Legs, i: usize) -> bool {
        legs.is_clear(i, || {
            let leg = &legs.list[i];
            let from = self.circle(clearance, k).at(leg.leave);
            let owners = [self.owner[k as usize] as usize, self.owner[leg.to as usize] as usize];
            clearance.segment_clear_except(from, leg.at, owners)
        })
    }

    /// The legs from the free point `p` to every rim it sees, bending either way round it.
    pub(crate) fn legs_from(&self, clearance: &Clearance, p: DVec2, cull: bool) -> Vec<Leg> {
        let point = Circle { center: p, radius: 0.0 };
        let mut out = Vec::new();
        self.walk(clearance, point, Turn::Left, None, cull, |target, hidden| {
            for tb in Turn::BOTH {
                let Some(t) = tangent(point, Turn::Left, target.circle, tb, self.touch) else { continue };
                if let Some(arrive) = self.touching(clearance, &target, &t, t.arrive, hidden, t.dir) {
                    out.push(Leg { to: target.id, turn: tb, leave: 0.0, arrive, at: t.to, length: t.length });
                }
            }
        });
        out.sort_by(|a, b| a.to.cmp(&b.to).then(a.turn.cmp(&b.turn)));
        out
    }

    /// The legs from every rim that sees the free point `p` to it, as `(rim, turn, leave,
    /// length)`, sorted by rim and turn.
    pub(crate) fn legs_to(&self, clearance: &Clearance, p: DVec2, cull: bool) -> Vec<(RimId, Turn, f64, f64)> {
        let point = Circle { center: p, radius: 0.0 };
        let mut out = Vec::new();
        self.walk(clearance, point, Turn::Left, None, cull, |target, hidden| {
            for ta in Turn::BOTH {
                let Some(t) = tangent(target.circle, ta, point, Turn::Left, self.touch) else { continue };
                if let Some(leave) = self.touching(clearance, &target, &t, t.leave, hidden, -t.dir) {
                    out.push((target.id, ta, leave, t.length));
                }
            }
        });
        out.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.cmp(&b.1)));
        out
    }

    /// For a leg `t` between a free point and `rim`, touching the rim with normal `normal`, and
    /// seen from the point in the direction `seen`: the normal's direction when the leg touches
    /// the rim on a free arc, is not hidden and is clear.
    fn touching(
        &self,
        clearance: &Clearance,
        rim: &RimView,
        t: &Tangent,
        normal: DVec2,
        hidden: &dyn Fn(DVec2) -> bool,
        seen: DVec2,
    ) -> Option<f64> {
        if !rim.cone.holds(normal) {
            return None;
        }
        let angle = angle_of(normal);
        (self.free(clearance, rim.id).locate(angle).is_some()
            && !hidden(seen)
            && clearance.segment_clear_except(t.from, t.to, [rim.owner, rim.owner]))
        .then_some(angle)
    }

    /// Calls `visit(rim, hidden)` for every rim that a leg leaving the circle `source`
    /// bending `turn` round it might reach, grown obstacles nearest its centre first;
    /// `hidden(direction)` tells whether such a leg in the direction `direction` to a point of
    /// that rim is known to be blocked (always `false` without `cull`). `arcs`: the source's
    /// free arcs, where legs leave it. With `cull`, the parts of the index whose box is hidden
    /// are passed over, and the walk ends once every direction is hidden.
    ///
    /// What hides what: every point `x` outside `source` lies on one leg leaving it bending
    /// `turn`, in the direction [`sight`] gives; a convex stand-in inside a grown obstacle
    /// hides the open range of directions of the legs that cross it, from the distance of its
    /// farthest point on (a leg's points grow farther from the centre along it). A point
    /// source sees alike whichever way the legs bend.
    fn walk(
        &self,
        clearance: &Clearance,
        source: Circle,
        turn: Turn,
        arcs: Option<&FreeArcs>,
        cull: bool,
        mut visit: impl FnMut(RimView, &dyn Fn(DVec2) -> bool),
    ) {
        let c = source.center;
        let (r, eps) = clearance.radius_and_tolerance();
        let mut shade = Shade::default();
        if let Some(FreeArcs::Arcs(arcs)) = arcs {
            // A leg leaves square to a normal on a free arc: bending left a quarter turn
            // counter-clockwise from it, bending right clockwise. No leg goes elsewhere.
            let quarter = turn.sign() * FRAC_PI_2;
            for (k, &(start, width)) in arcs.iter().enumerate() {
                let (next, _) = arcs[(k + 1) % arcs.len()];
                let gap = (next - start - width).rem_euclid(TAU);
                let gap = if gap == 0.0 && arcs.len() == 1 { TAU } else { gap };
                if gap > 1e-6 {
                    let lo = pseudo_angle(DVec2::from_angle(start + width + quarter));
                    let hi = pseudo_angle(DVec2::from_angle(start + width + gap + quarter));
                    let hi = if hi <= lo { hi + FULL_TURN } else { hi };
                    shade.add(lo + SHADE_SLACK, hi - SHADE_SLACK);
                }
            }
        }
        let sight = RefCell::new(Sight {
            source,
            turn,
            shade,
            pending: Vec::new(),
            outline: Vec::new(),
            dirs: Vec::new(),
            stick_out: self.stick_out,
        });
        let open = |b: &Aabb, dist: f64| {
            let mut sight = sight.borrow_mut();
            !cull || !(sight.pass(dist) || sight.hides(b))
        };
        clearance.visit_nearest(c, open, |j, dist| {
            let mut sight = sight.borrow_mut();
            if cull {
                if sight.pass(dist) {
                    return false;
                }
                // The obstacle's rims lie in its grown box: when that box is hidden, so are
                // they, and its shadow would hide nothing more.
                if clearance.grown_aabb(j).is_some_and(|b| sight.hides(&b)) {
                    return true;
                }
                sight.cast(clearance.blocker(j), r, eps);
            }
            let hidden = |direction: DVec2| cull && sight.shade.covers(pseudo_angle(direction));
            for k in self.first[j]..self.first[j + 1] {
                visit(self.view(clearance, j, k), &hidden);
            }
            true
        });
    }
}

/// What a walk knows is hidden from its source, for legs bending one way.
struct Sight {
    source: Circle,
    turn: Turn,
    /// The directions hidden.
    shade: Shade,
    /// Shadows of occluders the walk has not yet passed.
    pending: Vec<Pending>,
    /// Scratch.
    outline: Vec<DVec2>,
    dirs: Vec<DVec2>,
    stick_out: f64,
}

impl Sight {
    /// The walk has come `dist` metres from the source (everything from now on lies at least
    /// that far, give or take the stick-out): the shadows of the occluders passed join the
    /// shade. Whether every direction is hidden.
    fn pass(&mut self, dist: f64) -> bool {
        let reach = dist - self.stick_out;
        let mut i = 0;
        while i < self.pending.len() {
            if self.pending[i].far < reach {
                let q = self.pending.swap_remove(i);
                self.shade.add(q.lo, q.hi);
            } else {
                i += 1;
            }
        }
        self.shade.full()
    }

    /// Whether every point of the box `b` (grown by the stick-out) is hidden.
    fn hides(&mut self, b: &Aabb) -> bool {
        let b = b.expanded(self.stick_out);
        let corners = [b.min, DVec2::new(b.max.x, b.min.y), b.max, DVec2::new(b.min.x, b.max.y)];
        extent(self.source, self.turn, &corners, &mut self.dirs).is_some_and(|(lo, hi)| self.shade.covers_range(lo, hi))
    }

    /// Adds the shadow of a grown obstacle's stand-in, to join the shade once passed.
    fn cast(&mut self, blocker: &Blocker, r: f64, eps: f64) {
        let (source, turn) = (self.source, self.turn);
        let shadow = if stand_in(blocker, r, eps, &mut self.outline) {
            let far = self.outline.iter().map(|v| v.distance(source.center)).fold(0.0, f64::max);
            extent(source, turn, &self.outline, &mut self.dirs).map(|(lo, hi)| (far, lo, hi))
        } else if let Blocker::Disc { center, radius } = blocker {
            let disc = Circle { center: *center, radius: radius - 2.0 * eps - 1e-9 * radius };
            let side = |t| tangent(source, turn, disc, t, 0.0).map(|t| t.dir);
            match (side(Turn::Left), side(Turn::Right)) {
                (Some(lo), Some(hi)) if lo.perp_dot(hi) > 0.0 => {
                    let (lo, hi) = (pseudo_angle(lo), pseudo_angle(hi));
                    let far = source.center.distance(disc.center) + disc.radius;
                    Some((far, lo, if hi < lo { hi + FULL_TURN } else { hi }))
                }
                _ => None,
            }
        } else {
            None
        };
        if let Some((far, lo, hi)) = shadow {
            self.pending.push(Pending { far, lo: lo + SHADE_SLACK, hi: hi - SHADE_SLACK });
        }
    }
}

/// Slack (in [`pseudo_angle`] units, at most 1.6 radians each) by which a shadow is narrowed:
/// rounding never hides a leg that grazes an occluder's edge.
const SHADE_SLACK: f64 = 1e-9;

/// A full turn in [`pseudo_angle`] units.
const FULL_TURN: f64 = 4.0;

/// Half a turn in [`pseudo_angle`] units.
const HALF: f64 = 2.0;

/// A number in `(−2, 2]` that grows with the direction of `v` as its angle does over
/// `(−π, π]` (the "diamond angle": the turn measured along the square `|x| + |y| = 1`), for
/// ordering directions without trigonometry.
fn pseudo_angle(v: DVec2) -> f64 {
    let t = v.y / (v.x.abs() + v.y.abs());
    if v.x >= 0.0 {
        t
    } else if v.y >= 0.0 {
        2.0 - t
    } else {
        -2.0 - t
    }
}

/// The direction (not normalised) of the leg that leaves the circle `source` bending `turn`
/// round it and passes through `x`; `None` for `x` on or inside the circle. It is the closed
/// form of [`tangent`] to a circle of radius 0 at `x`.
fn sight(source: Circle, turn: Turn, x: DVec2) -> Option<DVec2> {
    let to = x - source.center;
    let k = -turn.sign() * source.radius;
    let l2 = to.length_squared() - k * k;
    (l2 > 0.0 && (k != 0.0 || to != DVec2::ZERO)).then(|| to * l2.sqrt() - to.perp() * k)
}

/// The range `(lo, hi)` ([`pseudo_angle`] units, `lo < hi`, less than a half turn apart) of
/// the directions of the legs
/// leaving `source` bending `turn` through the points `points` ([`sight`]); `None` when one
/// has none or they do not fit in an open half turn. `dirs` is scratch.
fn extent(source: Circle, turn: Turn, points: &[DVec2], dirs: &mut Vec<DVec2>) -> Option<(f64, f64)> {
    dirs.clear();
    for &p in points {
        dirs.push(sight(source, turn, p)?);
    }
    let first = *dirs.first()?;
    let (mut lo, mut hi) = (first, first);
    for &d in dirs.iter() {
        if lo.perp_dot(d) < 0.0 {
            lo = d;
        }
        if hi.perp_dot(d) > 0.0 {
            hi = d;
        }
    }
    let fits = lo.perp_dot(hi) > 0.0 && dirs.iter().all(|&d| lo.perp_dot(d) >= 0.0 && d.perp_dot(hi) >= 0.0);
    if !fits {
        return None;
    }
    let (a, b) = (pseudo_angle(lo), pseudo_angle(hi));
    Some((a, if b < a { b + FULL_TURN } else { b }))
}

/// A convex polygon inside grown obstacle `blocker`'s interior as the clearance tests count it
/// (closer than `r − ε` to the part), written to `out`: for a polygon, its edges moved out by
/// `r − 2ε` with each corner's arc replaced by three points on it (for `r ≤ 2ε`, the polygon
/// itself moved in by what that lacks). `false` for a disc, or when nothing is left.
fn stand_in(blocker: &Blocker, r: f64, eps: f64, out: &mut Vec<DVec2>) -> bool {
    out.clear();
    let Blocker::Polygon { vertices, normals } = blocker else { return false };
    let n = vertices.len();
    let reach = r - 2.0 * eps - 1e-9 * r;
    if reach > 0.0 {
        for k in 0..n {
            let (a, b) = (normals[(k + n - 1) % n], normals[k]);
            let mid = (a + b).normalize_or(b);
            out.extend([vertices[k] + a * reach, vertices[k] + mid * reach, vertices[k] + b * reach]);
        }
        return true;
    }
    // Move the edges in; give up when an edge would turn over.
    for k in 0..n {
        let (a, b) = (normals[(k + n - 1) % n], normals[k]);
        let c = 1.0 + a.dot(b);
        if !(c > 1e-9) {
            return false;
        }
        out.push(vertices[k] + (a + b) * (reach / c));
    }
    (0..n).all(|k| (out[(k + 1) % n] - out[k]).dot(vertices[(k + 1) % n] - vertices[k]) > 0.0)
}

/// The directions from one point known to be blocked beyond some distance: a union of open
/// angular intervals, kept sorted and disjoint, over directions in [`pseudo_angle`] units, `[-2, 2]` (an interval across
/// the seam is split, each piece running past it so the seam itself counts as covered).
#[derive(Debug, Default)]
struct Shade {
    intervals: Vec<(f64, f64)>,
}

impl Shade {
    fn add(&mut self, lo: f64, hi: f64) {
        // Bring `lo` into [-2, 2).
        let shift = ((lo + HALF) / FULL_TURN).floor() * FULL_TURN;
        let (lo, hi) = (lo - shift, hi - shift);
        if hi > HALF {
            self.insert(lo, HALF + 1.0);
            self.insert(-HALF - 1.0, hi - FULL_TURN);
        } else {
            self.insert(lo, hi);
        }
    }

    fn insert(&mut self, mut lo: f64, mut hi: f64) {
        // Merge with every interval it overlaps (open intervals merge only when they overlap).
        let at = self.intervals.partition_point(|&(_, h)| h <= lo);
        let mut end = at;
        while end < self.intervals.len() && self.intervals[end].0 < hi {
            lo = lo.min(self.intervals[end].0);
            hi = hi.max(self.intervals[end].1);
            end += 1;
        }
        self.intervals.splice(at..end, [(lo, hi)]);
    }

    /// Whether the direction `theta` (in `[-2, 2]`) is inside the shade.
    fn covers(&self, theta: f64) -> bool {
        let at = self.intervals.partition_point(|&(_, h)| h <= theta);
        self.intervals.get(at).is_some_and(|&(lo, _)| lo < theta)
    }

    /// Whether every direction of the closed range `[lo, hi]` (`hi - lo` less than a half
    /// turn) is inside the shade.
    fn covers_range(&self, lo: f64, hi: f64) -> bool {
        let shift = ((lo + HALF) / FULL_TURN).floor() * FULL_TURN;
        let (lo, hi) = (lo - shift, hi - shift);
        let inside = |lo: f64, hi: f64| {
            let at = self.intervals.partition_point(|&(_, h)| h <= lo);
            self.intervals.get(at).is_some_and(|&(l, h)| l < lo && hi < h)
        };
        if hi > HALF { inside(lo, HALF) && inside(-HALF, hi - FULL_TURN) } else { inside(lo, hi) }
    }

    /// Whether every direction is shaded.
    fn full(&self) -> bool {
        matches!(self.intervals.as_slice(), [(lo, hi)] if *lo < -HALF && *hi > HALF)
    }
}
