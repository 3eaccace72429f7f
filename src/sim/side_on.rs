//! Side-on passage (issue 26, beyond the seeds: the database's intervals chosen as in seed 000
//! §3.2.2, the body held clear by capsules as in seed 002 §5): a character fits through a slot
//! narrower than its shoulders by turning side-on — chest and hips about 0.3 m deep instead of
//! 0.46 m wide — and stepping sideways through it.
//!
//! [`SideOn`] is the manoeuvre: standing in front of the gap (it stops first), the character
//! pivots on the spot until its side points through the gap's middle, side-steps along that
//! line until its disc has room past the gap, and pivots back to face the gap's way out. Its
//! choices at the switch points are explicit candidates of the database: a stop, the pivots
//! (warped to the heading wanted, the pivot's own drift of the root taken into account) and the
//! side steps (which play unwarped). While it side-steps, the body's extent in the plane is
//! [`Footprint::side_on`], a capsule along the shoulders, not the walking disc: every frame,
//! the 2-D collision count and the look-ahead use it. The capsule holds every bone of the side
//! steps (`the_side_on_capsule_holds_every_bone_of_the_side_steps`).

use glam::DVec2;

pub use super::body::{Footprint, SIDE_ON_FORWARD_M, SIDE_ON_HALF_AXIS_M, SIDE_ON_RADIUS_M};
use crate::anim::player::{Choice, SwitchPoint};
use crate::anim::{Database, Ground};
use crate::geom::wrap_angle;

/// A gap the way goes through: its middle, the unit direction through it, its width (metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gap {
    /// The middle of the gap.
    pub centre: DVec2,
    /// Unit direction of the way through it.
    pub through: DVec2,
    /// Width across, metres.
    pub width: f64,
}

/// Narrowest gap the side-on body passes, metres: the capsule's depth and the room
/// [`KEEP_M`] on both sides, and a little for the pivot's drift.
pub const SIDE_ON_PASSAGE_M: f64 = 2.0 * (SIDE_ON_RADIUS_M + KEEP_M) + 0.1;

/// Room the side-on capsule keeps from obstacles along a side step, metres.
pub const KEEP_M: f64 = 0.02;

/// The side steps go on until the root is this far past the gap's middle, metres.
const PAST_M: f64 = 0.5;

/// Turned back, a pivot is good enough within this of the way through, radians (11°).
const TURN_TOL: f64 = 0.2;

/// Side-on, a pivot is taken only when it brings the heading at least this much nearer the
/// one wanted, radians (3°).
const TURN_GAIN: f64 = 0.05;

/// Least cosine between the leading side and the way through the gap (20°).
const LEAD_COS: f64 = 0.94;

/// Most switch points the manoeuvre takes before it gives up.
const MAX_SWITCHES: u32 = 80;

/// Standing where the line to the gap's middle leaves the way through it by more than this
/// (cosine, 14°), the character first faces the gap and side-steps onto the way (or steps back
/// from the gap) until it leaves it by no more than [`ALIGN_DONE_COS`].
const ALIGN_COS: f64 = 0.97;

/// See [`ALIGN_COS`] (10°).
const ALIGN_DONE_COS: f64 = 0.985;

/// Side steps bring the character this near the way through the gap's middle, metres (half a
/// side step); steps back then make the slant small enough.
const ALIGN_M: f64 = 0.15;

/// A side step onto the way is taken only when it brings the character at least this much
/// nearer it, metres.
const ALIGN_GAIN_M: f64 = 0.05;

/// Depth of the gap the side-on capsule's slanted passage is checked against, metres (a wall's).
const DEPTH_M: f64 = 0.2;

/// How the room of a root path is measured ([`SideOn::choose`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stance {
    /// The walking disc's room beyond what it must keep, or beyond what it has at the path's
    /// start when less (never closer).
    Walking,
    /// The side-on capsule's room beyond [`KEEP_M`] along the heading given, or beyond what it
    /// has at the path's start when less.
    SideOn(f64),
    /// The room at the path's start beyond [`KEEP_M`] of the walking disc, or of the side-on
    /// capsule along the heading given (below zero: it does not fit there).
    Fits(Option<f64>),
}

/// Where the manoeuvre stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Coming to a stand.
    Stop,
    /// Facing the gap, side-stepping onto the way through its middle (when the line from where
    /// it stands to the middle is too far from that way for the side steps to lead through).
    Align,
    /// Pivoting side-on.
    Turn,
    /// Side-stepping through.
    Slide,
    /// Blocked in the gap: side-stepping back out the way it came, then given up.
    Retreat,
    /// Pivoting back to face the way out.
    TurnBack,
    /// Through and facing the way on.
    Done,
    /// Something was in the way: given up where it stands.
    Failed,
}

/// The side-on manoeuvre through one gap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SideOn {
    /// The gap.
    pub gap: Gap,
    /// Where it stands.
    pub phase: Phase,
    /// The side the side steps go to: +1 left, −1 right (the database's shuffle sign).
    side: i8,
    /// The unit direction of the side steps, fixed when the pivot side-on is chosen.
    travel: DVec2,
    /// The body plays a side step now (its extent is the side-on capsule).
    pub sideways: bool,
    /// The pivot to go on with once standing.
    resume: Phase,
    /// No room to step back from the gap.
    cornered: bool,
    switches: u32,
}

impl SideOn {
    /// The manoeuvre through `gap` for a body at `g`.
    pub fn new(gap: Gap, g: Ground) -> SideOn {
        // Side-on with the smaller pivot: turning right leaves the left side leading.
        let face = gap.through.to_angle();
        let right = wrap_angle(face - std::f64::consts::FRAC_PI_2 - g.yaw).abs();
        let left = wrap_angle(face + std::f64::consts::FRAC_PI_2 - g.yaw).abs();
        let side = if right <= left { 1 } else { -1 };
        SideOn {
            gap,
            phase: Phase::Stop,
            side,
            travel: gap.through,
            sideways: false,
            resume: Phase::Turn,
            cornered: false,
            switches: 0,
        }
    }

    /// True while the manoeuvre drives the body.
    pub fn active(&self) -> bool {
        !matches!(self.phase, Phase::Done | Phase::Failed)
    }

    /// The facing that points the leading side along `travel`.
    fn facing(&self, travel: DVec2) -> f64 {
        wrap_angle(travel.to_angle() - f64::from(self.side) * std::f64::consts::FRAC_PI_2)
    }

    /// The choice at `at`, with `room(path, stance)` the room a root path keeps (see
    /// [`Stance`]) and `path` scratch; `None` when the manoeuvre is
    /// over (the phase says how) and the body's own chooser takes over.
    pub fn choose(
        &mut self,
        db: &Database,
        at: &SwitchPoint,
        path: &mut Vec<DVec2>,
        room: &mut dyn FnMut(&[DVec2], Stance) -> f64,
        reach: f64,
        limits: &crate::anim::warp::WarpLimits,
    ) -> Option<Choice> {
        self.switches += 1;
        if self.switches > MAX_SWITCHES && self.active() {
            self.phase = if self.sideways { Phase::Retreat } else { Phase::Failed };
        }
        let cands = &db.candidates[at.ending];
        let p = DVec2::new(at.ground.x, at.ground.y);
        let standing = db.kinds[at.ending].ends_at_rest;
        let ok = |a: usize| at.reach_gap(db, a) <= reach;
        // Mid-step, the candidate that closes the step playing; else the first step of kind
        // `shuffle` (a side step either way, or a step back).
        let step = |mid: bool, shuffle: i8| {
            (0..cands.len()).find(|&a| {
                let iv = cands[a].interval;
                ok(a) && if mid { iv == db.successor[at.ending] } else { db.kinds[iv].shuffle == shuffle }
            })
        };
        // Phases handed over within this choice: a handover back to one already left here (the
        // character still stands where it did) would go round for ever.
        let mut left = 0u16;
        let bit = |phase: Phase| 1u16 << phase as u16;
        loop {
            if left & bit(self.phase) != 0 {
                self.phase = Phase::Failed;
            }
            left |= bit(self.phase);
            match self.phase {
                Phase::Done | Phase::Failed => {
                    self.sideways = false;
                    return None;
                }
                Phase::Stop => {
                    if standing {
                        self.phase = self.resume;
                        continue;
                    }
                    // The first candidate that stands or stops, clear for the disc.
                    let pick = (0..cands.len()).find(|&a| {
                        let k = db.kinds[cands[a].interval];
                        ok(a) && (k.stops || (k.in_place && k.spot_turn == 0)) && {
                            path.clear();
                            at.path(db, Choice::from(a), path);
                            room(path, Stance::Walking) >= 0.0
                        }
                    });
                    return match pick {
                        Some(a) => Some(Choice::from(a)),
                        None => {
                            self.phase = Phase::Failed;
                            None
                        }
                    };
                }
                Phase::Turn | Phase::TurnBack | Phase::Align => {
                    let back = self.phase == Phase::TurnBack;
                    // Aside from the way through the gap's middle (left of it: positive), and before it.
                    let rel = p - self.gap.centre;
                    let (aside, before) = (self.gap.through.perp_dot(rel), -self.gap.through.dot(rel));
                    let slant = if before > 0.0 { before / before.hypot(aside) } else { 0.0 };
                    // (Not when the line-up handed over to the pivot here: it found no step to take.)
                    if self.phase == Phase::Turn
                        && standing
                        && slant < ALIGN_COS
                        && (aside.abs() > ALIGN_M || !self.cornered)
                        && left & bit(Phase::Align) == 0
                    {
                        self.phase = Phase::Align;
                    }
                    let align = self.phase == Phase::Align;
                    if align && standing && slant >= ALIGN_DONE_COS {
                        self.phase = Phase::Turn;
                        continue;
                    }
                    let want = |q: DVec2| {
                        if back || align {
                            self.gap.through.to_angle()
                        } else {
                            // The side leads through the gap's middle from where it stands.
                            // The capsule's axis, ahead of the root, through the middle.
                            let mut face = self.facing(self.gap.through);
                            for _ in 0..3 {
                                let to = self.gap.centre - DVec2::from_angle(face) * SIDE_ON_FORWARD_M - q;
                                let travel =
                                    if to.dot(self.gap.through) > 0.05 { to.normalize() } else { self.gap.through };
                                face = self.facing(travel);
                            }
                            face
                        }
                    };
                    // Standing, it goes on when its leading side points through the gap: the
                    // line it side-steps along passes the gap's middle with room for the capsule.
                    let lead = DVec2::from_angle(at.ground.yaw + f64::from(self.side) * std::f64::consts::FRAC_PI_2);
                    let axis = p + DVec2::from_angle(at.ground.yaw) * SIDE_ON_FORWARD_M;
                    let off = lead.perp_dot(self.gap.centre - axis).abs();
                    // The capsule's strip, slanted through a gap of some depth, takes more of it.
                    let cos = lead.dot(self.gap.through).clamp(LEAD_COS, 1.0);
                    let tan = (1.0 - cos * cos).sqrt() / cos;
                    let taken = 2.0 * SIDE_ON_RADIUS_M / cos + DEPTH_M * tan;
                    let slack = 0.5 * (self.gap.width - taken) - KEEP_M - 0.01;
                    let lined_up = if back || align {
                        wrap_angle(want(p) - at.ground.yaw).abs() <= TURN_TOL
                    } else {
                        off <= slack
                            && lead.dot(self.gap.through) >= LEAD_COS
                            && room(&[p], Stance::Fits(Some(at.ground.yaw))) >= 0.0
                    };
                    // Mid-step: the step's other foot closes first.
                    let mid = db.kinds[at.ending].shuffle != 0 && !standing;
                    if align && lined_up && (standing || mid) {
                        // Facing the gap: a side step toward the way through its middle, or a
                        // step back from the gap once near that way.
                        let mut toward: i8 = if aside.abs() <= ALIGN_M {
                            2
                        } else if aside < 0.0 {
                            1
                        } else {
                            -1
                        };
                        let mut pick = step(mid, toward);
                        // A side step that would leave it hardly nearer the way (it overshoots)
                        // is not taken: it steps back instead. The step's first interval moves
                        // the root about half of the step.
                        if let Some(a) = pick.filter(|_| !mid && toward != 2) {
                            path.clear();
                            at.path(db, Choice::from(a), path);
                            let half =
                                path.last().map_or(0.0, |&q| self.gap.through.perp_dot(q - self.gap.centre) - aside);
                            if (aside + 2.0 * half).abs() > aside.abs() - ALIGN_GAIN_M {
                                toward = 2;
                                pick = step(mid, toward);
                            }
                        }
                        let clear = pick.is_some_and(|a| {
                            path.clear();
                            at.path(db, Choice::from(a), path);
                            mid || room(path, Stance::Walking) >= 0.0
                        });
                        let Some(a) = pick.filter(|_| clear) else {
                            // No room behind: side-on from here; none beside: given up.
                            self.phase = if toward == 2 { Phase::Turn } else { Phase::Failed };
                            self.cornered |= toward == 2;
                            continue;
                        };
                        self.sideways = false;
                        return Some(Choice::from(a));
                    }
                    if standing && lined_up {
                        if back {
                            self.phase = Phase::Done;
                        } else {
                            self.travel =
                                DVec2::from_angle(at.ground.yaw + f64::from(self.side) * std::f64::consts::FRAC_PI_2);
                            self.phase = Phase::Slide;
                        }
                        continue;
                    }
                    if !standing {
                        self.resume = self.phase;
                        self.phase = Phase::Stop;
                        continue;
                    }
                    // The pivot whose end, warped toward the heading wanted from where it ends,
                    // comes nearest to it.
                    let mut best: Option<(f64, Choice)> = None;
                    for (a, cand) in cands.iter().enumerate() {
                        let k = db.kinds[cand.interval];
                        if k.spot_turn == 0 || !ok(a) {
                            continue;
                        }
                        let mut target = want(p);
                        let mut choice = Choice::from(a);
                        for _ in 0..3 {
                            let direction = wrap_angle(target - at.ground.yaw);
                            choice = Choice { candidate: a, warp: at.warp_toward(db, a, direction, 0.0, limits) };
                            path.clear();
                            let then = at.path(db, choice, path);
                            target = want(DVec2::new(then.ground.x, then.ground.y));
                        }
                        path.clear();
                        let then = at.path(db, choice, path);
                        let err = wrap_angle(want(DVec2::new(then.ground.x, then.ground.y)) - then.ground.yaw).abs();
                        if room(path, Stance::Walking) >= 0.0 && best.is_none_or(|(e, _)| err < e - 1e-9) {
                            best = Some((err, choice));
                        }
                    }
                    // Side-on, a pivot that would leave it hardly nearer the heading wanted (the
                    // smallest pivot overshoots it either way, and the heading wanted moves with
                    // the pivot's drift) is not taken: it side-steps from where it stands if the
                    // capsule fits here (the side steps check their own room and back out if
                    // blocked), else gives up.
                    let now = wrap_angle(want(p) - at.ground.yaw).abs();
                    if self.phase == Phase::Turn && best.is_none_or(|(e, _)| e > now - TURN_GAIN) {
                        self.phase = if lead.dot(self.gap.through) >= LEAD_COS
                            && room(&[p], Stance::Fits(Some(at.ground.yaw))) >= 0.0
                        {
                            self.travel = lead;
                            Phase::Slide
                        } else {
                            Phase::Failed
                        };
                        continue;
                    }
                    return match best {
                        Some((_, c)) => {
                            self.sideways = false;
                            Some(c)
                        }
                        None => {
                            self.phase = Phase::Failed;
                            None
                        }
                    };
                }
                Phase::Slide | Phase::Retreat => {
                    let back = self.phase == Phase::Retreat;
                    let side = if back { -self.side } else { self.side };
                    let past = (p - self.gap.centre).dot(self.travel);
                    // Mid-step: the step's other foot closes.
                    let mid = db.kinds[at.ending].shuffle.abs() == 1 && !standing;
                    // Out of the gap where the walking disc fits again.
                    let out = !mid && past.abs() > PAST_M && room(&[p], Stance::Fits(None)) >= 0.0;
                    if out && !back && past > 0.0 {
                        self.phase = Phase::TurnBack;
                        continue;
                    }
                    if out && back && past < 0.0 {
                        // Out of the gap again, where the walking disc has room.
                        self.phase = Phase::Failed;
                        continue;
                    }
                    let pick = step(mid, side);
                    let clear = pick.is_some_and(|a| {
                        path.clear();
                        at.path(db, Choice::from(a), path);
                        mid || room(path, Stance::SideOn(at.ground.yaw)) >= 0.0
                    });
                    match pick.filter(|_| clear) {
                        Some(a) => {
                            self.sideways = true;
                            return Some(Choice::from(a));
                        }
                        // Blocked going on: back out the way it came.
                        None if !back => {
                            self.phase = Phase::Retreat;
                            continue;
                        }
                        // Blocked both ways: it stands side-on where it is.
                        None => return Some(Choice::from(0)),
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The capsule holds every bone of the side steps and of standing, in every frame of their
    /// clips, by forward kinematics (points 1 cm apart along each bone).
    #[test]
    fn the_side_on_capsule_holds_every_bone_of_the_side_steps() {
        let db = crate::builtin::database().unwrap();
        let sk = &db.skeleton;
        let mut g = Vec::new();
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        let mut worst = f64::NEG_INFINITY;
        for (ci, clip) in db.clips.iter().enumerate() {
            if !(clip.name.starts_with("side_step") || clip.name == "idle") {
                continue;
            }
            for (f, pose) in clip.frames.iter().enumerate() {
                let at = db.ground(ci, f as f64);
                sk.globals(pose, &mut g);
                for (i, j) in sk.joints().iter().enumerate() {
                    let mut ends = Vec::new();
                    if let Some(p) = j.parent {
                        ends.push((g[p].0, g[i].0));
                    }
                    if j.end_site.is_some() {
                        ends.push((g[i].0, sk.tip(&g, i)));
                    }
                    for (a, b) in ends {
                        for s in 0..=20 {
                            let q = a.lerp(b, f64::from(s) / 20.0);
                            let d = DVec2::new(q.x - at.x, q.y - at.y).rotate(DVec2::from_angle(-at.yaw));
                            lo = lo.min(d);
                            hi = hi.max(d);
                            let c = DVec2::new(SIDE_ON_FORWARD_M, d.y.clamp(-SIDE_ON_HALF_AXIS_M, SIDE_ON_HALF_AXIS_M));
                            worst = worst.max(d.distance(c) - SIDE_ON_RADIUS_M);
                        }
                    }
                }
            }
        }
        eprintln!("side-on bones: forward {:.3}..{:.3}, left {:.3}..{:.3}; worst {worst:.3}", lo.x, hi.x, lo.y, hi.y);
        assert!(worst <= 0.0, "a bone {worst} m outside the capsule");
    }
}
