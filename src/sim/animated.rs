//! The animated body (seed 000 §3.2; DESIGN.md §3): the navigation loop drives the character
//! through the animation database. The fuzzy planner's turn rate and speed become the RL
//! controller's task: a desired heading — where the commanded turn rate would bring the heading
//! within [`HEADING_HORIZON_S`], but not past the direction the planner steers toward
//! ([`Command::toward`]), re-aimed at every step, since the planner closes the loop — and a
//! desired speed. At every switch point the candidates are ranked (by the trained policy from
//! the state: interval now ending, speed error, direction error; or by a baseline
//! [`Strategy`]) and the character **looks before it steps**: a candidate is taken only if the
//! root path it would play ([`SwitchPoint::path`], the cross-fade included), swept by the body's
//! disc with a clearance margin, stays clear, and — unless it stays in place — if from its end
//! a turn on the spot is clear too, so the character never walks where it could not turn round.
//! A character with nothing clear ahead stops or turns on the spot the way a person does — it
//! never pushes into a wall. One facing away from its way (more than 90°) whose policy would
//! stand and turn, but from a stance mid-stride that cannot reach that, stops first rather
//! than walk on the wrong way.
//!
//! In a world where things move (other agents), the rest of the interval playing is checked at
//! every step; when something unexpected blocks it, the character switches early with a short
//! blend. Planted feet stay locked through all of this (see [`crate::anim::player`]). The disc
//! invariant still holds as a last resort: a frame whose root would end inside something is not
//! taken (the root holds; the locked feet do not move).

use std::sync::Arc;

use glam::DVec2;
use rand_chacha::ChaCha8Rng;

use super::body::{Body, Command, OpenSpace, Space, StepOutcome, is_free};
use super::footing::Footing;
use super::side_on::{Footprint, Gap, Phase, SideOn, Stance};
use super::upper_body::UpperBodyState;
use crate::anim::player::{Choice, Chooser, PlaybackMetrics, Player, PlayerParams, SwitchPoint};
use crate::anim::policy::{Errors, Policy, Ranker, Strategy, Task};
use crate::anim::warp::Warp;
use crate::anim::{Database, Ground};
use crate::geom::wrap_angle;
use crate::world::Pose;

/// Largest direction error the desired heading may run ahead of the character, radians.
pub const MAX_DIRECTION_ERROR: f64 = 0.9 * std::f64::consts::PI;
/// The desired heading is where the commanded turn rate leads within this time, seconds.
pub const HEADING_HORIZON_S: f64 = 1.0;
/// Commanded speed from which standing still counts as being held, m/s.
pub const HELD_SPEED_MPS: f64 = 0.2;
/// Half-width of the speed band over which [`Body::turn_limit`] looks at the database, m/s.
const TURN_BAND_MPS: f64 = 0.25;
/// Step of the turn-ability table, m/s.
const TURN_TABLE_STEP: f64 = 0.05;

/// A database with its trained policy, playback parameters and look-ahead, shared by every
/// agent.
#[derive(Debug)]
pub struct Animation {
    /// The database.
    pub db: Database,
    /// The policy trained on it.
    pub policy: Policy,
    /// Playback parameters.
    pub player: PlayerParams,
    /// How candidates are ranked (the learnt policy).
    pub strategy: Strategy,
    /// Gap the body's disc keeps from obstacles along a candidate's path, metres (0.03, the room
    /// the kinematic disc keeps).
    pub clearance_m: f64,
    /// How the footstep planner steps on uneven terrain (planning, or the nominal step alone).
    pub footsteps: crate::footstep::PlannerMode,
    /// Largest turn rate at speeds `0, 0.05, 0.1, …` m/s, radians per second.
    turn_ability: Vec<f64>,
    /// The database has side steps either way and turns on the spot: the character can pass a
    /// gap side-on ([`super::side_on`]).
    side_on: bool,
}

impl Animation {
    /// The animation of `db` with `policy`, default playback, the learnt strategy.
    pub fn new(db: Database, policy: Policy) -> Animation {
        let top = db.max_speed() + TURN_BAND_MPS;
        let steps = (top / TURN_TABLE_STEP).ceil() as usize + 1;
        // Sustained turning: an interval and its natural successor together (turning clips turn
        // in bursts at the plants).
        let rate = |i: usize| {
            let (a, b) = (&db.intervals[i], &db.intervals[db.successor[i]]);
            if db.kinds[i].in_place {
                a.turn().abs() / a.duration.max(1e-9)
            } else {
                (a.turn() + b.turn()).abs() / (a.duration + b.duration).max(1e-9)
            }
        };
        let mut turn_ability: Vec<f64> = (0..steps)
            .map(|k| {
                let v = k as f64 * TURN_TABLE_STEP;
                (0..db.intervals.len())
                    .filter(|&i| {
                        let speed = if db.kinds[i].in_place { 0.0 } else { db.intervals[i].speed };
                        (speed - v).abs() <= TURN_BAND_MPS
                    })
                    .map(rate)
                    .fold(0.0, f64::max)
            })
            .collect();
        let has = |f: &dyn Fn(&crate::anim::db::IntervalKind) -> bool| db.kinds.iter().any(f);
        let side_on = has(&|k| k.shuffle > 0) && has(&|k| k.shuffle < 0) && has(&|k| k.spot_turn != 0);
        // Speeds no interval comes near take the nearest speeds' ability (the larger).
        let known: Vec<usize> = (0..steps).filter(|&k| turn_ability[k] > 0.0).collect();
        for k in 0..steps {
            if turn_ability[k] == 0.0 {
                let below = known.iter().rev().find(|&&j| j < k).map(|&j| (k - j, turn_ability[j]));
                let above = known.iter().find(|&&j| j > k).map(|&j| (j - k, turn_ability[j]));
                turn_ability[k] = match (below, above) {
                    (Some(b), Some(a)) if b.0 == a.0 => b.1.max(a.1),
                    (Some(b), Some(a)) => {
                        if b.0 < a.0 {
                            b.1
                        } else {
                            a.1
                        }
                    }
                    (Some(b), None) => b.1,
                    (None, Some(a)) => a.1,
                    (None, None) => 0.0,
                };
            }
        }
        Animation {
            db,
            policy,
            player: PlayerParams::default(),
            strategy: Strategy::Learnt,
            clearance_m: 0.03,
            footsteps: crate::footstep::PlannerMode::Window,
            turn_ability,
            side_on,
        }
    }

    /// The same with the footstep planner in `mode` on uneven terrain.
    pub fn with_footsteps(mut self, mode: crate::footstep::PlannerMode) -> Animation {
        self.footsteps = mode;
        self
    }

    /// The same with playback parameters `player`.
    pub fn with_player(mut self, player: PlayerParams) -> Animation {
        self.player = player;
        self
    }

    /// The same with candidates ranked by `strategy`.
    pub fn with_strategy(mut self, strategy: Strategy) -> Animation {
        self.strategy = strategy;
        self
    }

    /// The largest turn rate the character can follow at `speed`, radians per second: the
    /// fastest sustained turn (an interval with its natural successor) among the intervals
    /// within 0.25 m/s of it (turns on the spot count as speed 0; speeds no interval comes near
    /// take their nearest neighbours').
    pub fn turn_limit(&self, speed: f64) -> f64 {
        let k = if speed.is_finite() { (speed.max(0.0) / TURN_TABLE_STEP).round() as usize } else { 0 };
        self.turn_ability[k.min(self.turn_ability.len() - 1)]
    }
}

/// A shared [`Animation`]; equal when it is the same one.
#[derive(Debug, Clone)]
pub struct AnimationHandle(pub Arc<Animation>);

impl PartialEq for AnimationHandle {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// Command tracking of an animated body.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Tracking {
    /// Σ squared distance between the commanded path and the root path, m².
    pub sq_distance: f64,
    /// Σ squared direction error, rad².
    pub sq_direction: f64,
    /// Σ squared speed error, (m/s)².
    pub sq_speed: f64,
    /// Samples (steps).
    pub samples: u64,
}

impl Tracking {
    /// RMS distance between the commanded path (the commands integrated from the root at the
    /// last switch point) and the root path, metres.
    pub fn rms_path_m(&self) -> f64 {
        (self.sq_distance / self.samples.max(1) as f64).sqrt()
    }
    /// RMS direction error, radians.
    pub fn rms_direction(&self) -> f64 {
        (self.sq_direction / self.samples.max(1) as f64).sqrt()
    }
    /// RMS speed error, m/s.
    pub fn rms_speed(&self) -> f64 {
        (self.sq_speed / self.samples.max(1) as f64).sqrt()
    }
}

/// A character driven by the animation database.
#[derive(Debug, Clone)]
pub struct AnimatedBody {
    anim: Arc<Animation>,
    player: Player,
    radius: f64,
    desired_heading: f64,
    command: Command,
    speed: f64,
    commanded: Ground,
    switches: u64,
    rng: ChaCha8Rng,
    /// The interval playing was taken because every moving candidate ahead was blocked.
    held: bool,
    /// How long the character has been held still, seconds.
    held_s: f64,
    order: Vec<usize>,
    path: Vec<DVec2>,
    /// Command tracking so far.
    pub tracking: Tracking,
    /// The feet on uneven terrain (none on flat ground: the database's steps play unchanged).
    footing: Option<Box<Footing>>,
    /// Switches of the player the footing has planned for.
    footing_switches: u64,
    /// Every frame played since [`AnimatedBody::record_motion`], when recording.
    motion: Option<Vec<crate::anim::Pose>>,
    /// The upper body among obstacles it can touch (none: the database's upper body plays).
    upper: Option<Box<UpperBodyState>>,
    /// Switches of the player the upper body has taken its plan at.
    upper_switches: u64,
    /// The side-on manoeuvre through a narrow gap, while it runs (see [`super::side_on`]).
    side_on: Option<SideOn>,
}

/// The look-ahead chooser: ranks the candidates and takes the best one whose path is clear.
struct LookAhead<'a> {
    anim: &'a Animation,
    space: &'a mut dyn Space,
    radius: f64,
    command: Command,
    desired: f64,
    rng: &'a mut ChaCha8Rng,
    order: &'a mut Vec<usize>,
    path: &'a mut Vec<DVec2>,
    held: bool,
    /// Held still longer than [`RESTLESS_S`].
    restless: bool,
    /// The upper body, which plans every candidate clear for the legs (and refuses those it
    /// cannot make free), with the offsets at the switch point.
    upper: Option<(&'a mut UpperBodyState, crate::anim::body::UpperConfig)>,
    /// Candidates the upper body refused at this switch point (bit per candidate).
    refused: u64,
}

/// After being held still this long, a character takes any clear turn or step before standing
/// on, seconds.
pub const RESTLESS_S: f64 = 1.0;

/// Why a candidate may or may not be taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Eligibility {
    /// Its path (and a stop or turn after it) keeps the clearance.
    Clear,
    /// Something is in the way.
    Blocked,
    /// Its start cannot reach the feet planted now.
    OutOfReach,
}

/// Farthest a candidate's start pose may put a planted foot from where it is held, metres:
/// beyond it, holding the foot would stretch the leg past its reach (a step that cannot follow
/// from this stance).
pub const LOCK_REACH_M: f64 = 0.2;

/// Room the heel and toe of a landing foot keep from obstacles, metres (about half a foot's
/// width).
pub const FOOT_ROOM_M: f64 = 0.05;

/// Smallest change of the stride factor worth warping the rest of a step for.
const RESTRIDE_STEP: f64 = 0.02;

/// Allowance added to every clearance check of a sampled root path for the curve between its
/// points, metres.
const PATH_ALLOWANCE_M: f64 = 0.005;
/// Room a side the character needs beyond its disc and margin to walk through a gap rather
/// than past it, metres: its clips curve and sway, and it must be able to stop or turn round
/// after every step (0.85 m in all).
const PASSAGE_SLACK_M: f64 = 0.095;

/// Room the body keeps from obstacles whatever it plays, metres: a frame whose root would end
/// closer than this, and closer than it is now, is not taken.
pub const KEEP_ROOM_M: f64 = 0.02;

/// A root moving from `from` to `to` keeps [`KEEP_ROOM_M`] (or, when it is already closer, gets
/// no closer) — the last-resort guard of every played frame.
fn keeps_room(space: &mut dyn Space, from: DVec2, to: DVec2, radius: f64) -> bool {
    let want = radius + KEEP_ROOM_M;
    let after = space.clearance(to, want + 1e-9);
    after >= want || (is_free(space, to, radius) && after >= space.clearance(from, want + 1e-9))
}

/// [`keeps_room`] for the side-on capsule: the capsule at `to` keeps [`super::side_on::KEEP_M`]
/// or, when it is already closer at `from`, gets no closer.
fn side_on_keeps_room(space: &mut dyn Space, from: Ground, to: Ground) -> bool {
    let keep = super::side_on::KEEP_M;
    let after = Footprint::side_on(to).room(space, keep + 1e-9);
    after >= keep - 1e-9 || (after >= 0.0 && after >= Footprint::side_on(from).room(space, keep + 1e-9))
}

/// The room at `from` for a body that wants `want` metres (centre to obstacle): what there is,
/// looked for up to `want` (beyond it, as good as `want`), the path allowance taken off.
fn room_now(space: &mut dyn Space, from: DVec2, want: f64) -> f64 {
    space.clearance(from, want + PATH_ALLOWANCE_M) - PATH_ALLOWANCE_M
}

/// The root path `pts` keeps `need` metres (plus [`PATH_ALLOWANCE_M`] for the curve between
/// its points) from everything in `space`.
fn path_keeps(space: &mut dyn Space, pts: &[DVec2], need: f64) -> bool {
    let need = need + PATH_ALLOWANCE_M;
    match pts {
        [] => true,
        [p] => space.clearance(*p, need) >= need,
        _ => {
            // Room around the start for the whole path settles it with one query.
            let reach = pts.iter().map(|p| p.distance_squared(pts[0])).fold(0.0, f64::max).sqrt();
            let room = reach + need;
            space.clearance(pts[0], room + 1e-9) >= room
                || pts.windows(2).all(|w| space.segment_clearance(w[0], w[1], need) >= need)
        }
    }
}

/// Both feet where a candidate starts (`start`: its feet placed on their ground reference) and
/// where it ends (`end`) keep [`FOOT_ROOM_M`] from obstacles, heel and toe, and so does the way
/// between (a foot stepping into a corridor does not cut the corner of its wall).
fn feet_keep_room(
    space: &mut dyn Space,
    start: (&crate::anim::db::FeetAt, Ground),
    end: (&crate::anim::db::FeetAt, Ground),
) -> bool {
    let place = |(feet, at): (&crate::anim::db::FeetAt, Ground), foot: usize, k: usize| {
        let p = feet.points[foot][k];
        let w = at.then(Ground { x: p.x, y: p.y, yaw: 0.0 });
        DVec2::new(w.x, w.y)
    };
    // Room around the start's root for every point settles it at once.
    let root = DVec2::new(start.1.x, start.1.y);
    let points = || (0..2).flat_map(|foot| (0..2).map(move |k| (foot, k)));
    let reach = points()
        .flat_map(|(foot, k)| [place(start, foot, k), place(end, foot, k)])
        .map(|p| p.distance(root))
        .fold(0.0, f64::max);
    let room = reach + FOOT_ROOM_M;
    if space.clearance(root, room + 1e-9) >= room {
        return true;
    }
    points().all(|(foot, k)| {
        let (a, b) = (place(start, foot, k), place(end, foot, k));
        space.segment_clearance(a, b, FOOT_ROOM_M) >= FOOT_ROOM_M
    })
}

/// Candidates the last resort plans the upper body for, best first (each failed plan searches
/// its whole roadmap).
const LAST_RESORT_TRIES: usize = 3;

/// Clearance standing or turning on the spot may give up below the margin, metres (the pelvis
/// shifts over the feet).
const IN_PLACE_SLACK_M: f64 = 0.02;

impl LookAhead<'_> {
    /// The clearances paths from `from` must keep (before [`PATH_ALLOWANCE_M`]), for moving
    /// candidates and for those that stay in place: the margin (a little less for turning on
    /// the spot or stopping), or what there is now if less. The path's sampled points, its end
    /// included, are checked with the allowance added, so a character never ends a path closer
    /// than it started or than the margin: clearance does not erode from switch to switch, and
    /// one that stands too close can still turn or move away.
    fn needs(&mut self, from: DVec2) -> (f64, f64) {
        let want = self.radius + self.anim.clearance_m;
        let now = room_now(self.space, from, want);
        // Held still for a while with nothing clear, a turn on the spot may come as close as
        // the room every frame keeps (the frame guard holds the root there): standing on
        // never gets the character out.
        let in_place =
            if self.restless { self.radius + KEEP_ROOM_M - PATH_ALLOWANCE_M } else { now.min(want - IN_PLACE_SLACK_M) };
        (now.min(want), in_place)
    }

    fn clear(&mut self, need: f64) -> bool {
        path_keeps(self.space, self.path, need)
    }

    /// Candidate `a` at `at` may be taken: its start can reach the feet planted now (within
    /// [`LOCK_REACH_M`]), its path keeps the clearance, and — unless it stays in place — so
    /// does a turn on the spot or a stop after it, so the character never walks where it could
    /// not stop or turn round.
    fn eligible(&mut self, db: &Database, at: &SwitchPoint, a: usize, needs: (f64, f64)) -> Eligibility {
        if at.reach_gap(db, a) > LOCK_REACH_M {
            return Eligibility::OutOfReach;
        }
        let choice = self.choice(db, at, a);
        let legs = self.eligible_for_legs(db, at, choice, needs);
        match &mut self.upper {
            Some((u, _)) if legs == Eligibility::Clear => {
                if u.admits(db, at, choice, self.command.speed) {
                    legs
                } else {
                    self.refused |= 1u64 << a.min(63);
                    Eligibility::Blocked
                }
            }
            _ => legs,
        }
    }

    /// Candidate `a` at `at` with the warp that brings it nearest to the desired heading and the
    /// commanded speed (the policy's model warps alike, [`crate::anim::policy::transition`]).
    fn choice(&self, db: &Database, at: &SwitchPoint, a: usize) -> Choice {
        let direction = wrap_angle(self.desired - at.ground.yaw);
        let limits = &self.anim.policy.params.warp;
        Choice { candidate: a, warp: at.warp_toward(db, a, direction, self.command.speed, limits) }
    }

    /// [`LookAhead::eligible`] for the legs' disc alone, `choice` being one whose start the feet reach.
    fn eligible_for_legs(&mut self, db: &Database, at: &SwitchPoint, choice: Choice, needs: (f64, f64)) -> Eligibility {
        let next = db.candidates[at.ending][choice.candidate].interval;
        let in_place = db.kinds[next].in_place;
        self.path.clear();
        let then = at.path(db, choice, self.path);
        // Only a turn on the spot may give up some of the margin (to turn away from a wall).
        if !self.clear(if db.kinds[next].spot_turn != 0 { needs.1 } else { needs.0 }) {
            return Eligibility::Blocked;
        }
        // A step never puts a foot beside the body's disc into a wall (steps that turn or start
        // place a foot well to the side, and a cross-fade carries a swinging foot toward where
        // the candidate starts it).
        if !feet_keep_room(self.space, (db.feet_at(next, false), at.ground), (db.feet_at(next, true), then.ground)) {
            return Eligibility::Blocked;
        }
        if in_place {
            return Eligibility::Clear;
        }
        for b in 0..db.candidates[next].len() {
            let kind = db.kinds[db.candidates[next][b].interval];
            if (kind.spot_turn == 0 && !kind.stops) || then.reach_gap(db, b) > LOCK_REACH_M {
                continue;
            }
            self.path.clear();
            then.path(db, Choice::from(b), self.path);
            if self.clear(needs.1) {
                return Eligibility::Clear;
            }
        }
        Eligibility::Blocked
    }

    /// For choosing when nothing is clear: whether candidate `a`'s feet at `at` keep their room
    /// where it starts, where it ends and between ([`feet_keep_room`]), and the smallest
    /// clearance along its path.
    fn fallback_room(&mut self, db: &Database, at: &SwitchPoint, a: usize) -> (bool, f64) {
        let choice = self.choice(db, at, a);
        let next = db.candidates[at.ending][a].interval;
        self.path.clear();
        let then = at.path(db, choice, self.path);
        let feet =
            feet_keep_room(self.space, (db.feet_at(next, false), at.ground), (db.feet_at(next, true), then.ground));
        let far = self.radius + 1.0;
        let room = match self.path.as_slice() {
            [] => far,
            [p] => self.space.clearance(*p, far),
            pts => pts.windows(2).map(|w| self.space.segment_clearance(w[0], w[1], far)).fold(far, f64::min),
        };
        (feet, room)
    }
}

impl Chooser for LookAhead<'_> {
    fn choose(&mut self, db: &Database, at: &SwitchPoint) -> Choice {
        let errors = Errors {
            speed: self.command.speed - at.warp().speed(&db.intervals[at.ending]),
            direction: wrap_angle(self.desired - at.ground.yaw),
        };
        // The desired heading already holds the commanded turn (re-aimed at every step): the
        // task is to reach that heading at the commanded speed.
        let task = Task { turn_rate: 0.0, speed: self.command.speed };
        let ranker = Ranker { strategy: self.anim.strategy, policy: &self.anim.policy };
        ranker.rank(db, at.ending, errors, task, self.rng, self.order);
        // Held still for a while: side steps and steps back too, after everything else that
        // moves.
        if self.restless {
            self.order.extend(db.policy_actions[at.ending]..db.candidates[at.ending].len());
        }
        // Facing away from where it should go, the policy's first choice stands and turns, but
        // this stance cannot reach it (the feet are apart mid-stride): the way there is to stop
        // first, so the candidates that bring the character to rest go before the rest, in the
        // policy's order (else it walks on the wrong way, never reaching a stance to turn from).
        if errors.direction.abs() > std::f64::consts::FRAC_PI_2
            && let Some(&first) = self.order.first()
            && db.kinds[db.candidates[at.ending][first].interval].in_place
            && at.reach_gap(db, first) > LOCK_REACH_M
        {
            let stops = |a: &usize| {
                let k = db.kinds[db.candidates[at.ending][*a].interval];
                k.stops && !k.in_place
            };
            let (mut front, back): (Vec<usize>, Vec<usize>) = self.order.iter().partition(|a| stops(a));
            front.extend(back);
            *self.order = front;
        }
        if let Some((u, start)) = &mut self.upper {
            u.begin_choice(*start);
        }
        self.refused = 0;
        let needs = self.needs(DVec2::new(at.ground.x, at.ground.y));
        let mut blocked = false;
        let order = std::mem::take(self.order);
        let mut pick = None;
        // Held still for a while: anything that turns or moves comes before standing on.
        let standing = |a: usize| {
            let k = db.kinds[db.candidates[at.ending][a].interval];
            k.in_place && k.spot_turn == 0
        };
        let passes: &[bool] = if self.restless { &[true, false] } else { &[false] };
        'search: for &skip_standing in passes {
            for &a in &order {
                if skip_standing && standing(a) {
                    continue;
                }
                match self.eligible(db, at, a, needs) {
                    Eligibility::Clear => {
                        pick = Some(a);
                        break 'search;
                    }
                    Eligibility::Blocked => blocked = true,
                    Eligibility::OutOfReach => {}
                }
            }
        }
        *self.order = order;
        let cands = &db.candidates[at.ending];
        let a = pick.unwrap_or_else(|| {
            // Nothing keeps the margin: the candidate whose path keeps the most room (the
            // last-resort guard keeps the root out of anything) among those whose feet keep
            // theirs, if any — but never one that moves where the upper body could not follow.
            let room: Vec<(bool, f64)> = (0..cands.len())
                .map(|a| {
                    let moves = !db.kinds[cands[a].interval].in_place;
                    if moves && self.refused & (1u64 << a.min(63)) != 0 {
                        (false, f64::NEG_INFINITY)
                    } else {
                        self.fallback_room(db, at, a)
                    }
                })
                .collect();
            let key = |a: usize| room[a];
            let mut ranked: Vec<usize> = (0..cands.len()).collect();
            ranked.sort_by(|&x, &y| key(y).0.cmp(&key(x).0).then(key(y).1.total_cmp(&key(x).1)).then(x.cmp(&y)));
            // The first in that order over whose own interval the upper body keeps clear, else
            // the one whose upper body, held, keeps the most room — never giving up the feet's
            // room for it.
            let first = ranked.first().copied().unwrap_or(0);
            let feet = key(first).0;
            let mut least_bad = (first, f64::NEG_INFINITY);
            let tier = ranked.into_iter().take_while(|&a| key(a).0 == feet && key(a).1 > f64::NEG_INFINITY);
            for a in tier.take(LAST_RESORT_TRIES) {
                let choice = self.choice(db, at, a);
                match self.upper.as_mut().map_or(Ok(()), |(u, _)| u.settles(db, at, choice)) {
                    Ok(()) => return a,
                    Err(room) if room > least_bad.1 => least_bad = (a, room),
                    Err(_) => {}
                }
            }
            least_bad.0
        });
        // Held: something the character wanted was blocked by obstacles, and it stands still
        // instead (turning on the spot is doing something about it).
        let kind = db.kinds[cands[a].interval];
        self.held = blocked && kind.in_place && kind.spot_turn == 0;
        let choice = self.choice(db, at, a);
        if let Some((u, _)) = &mut self.upper {
            u.end_choice(db, at, choice);
        }
        choice
    }
}

/// The side-on manoeuvre's choices while it runs, the look-ahead's after.
struct SideOnChooser<'a, 'b> {
    side: &'a mut SideOn,
    look: LookAhead<'b>,
}

impl Chooser for SideOnChooser<'_, '_> {
    fn choose(&mut self, db: &Database, at: &SwitchPoint) -> Choice {
        let radius = self.look.radius;
        let limits = self.look.anim.policy.params.warp;
        let space = &mut *self.look.space;
        let path = &mut *self.look.path;
        // The room a root path keeps, measured as each stance asks (see `Stance`).
        let mut room = |pts: &[DVec2], stance: Stance| -> f64 {
            let Some(&first) = pts.first() else { return 0.0 };
            match stance {
                Stance::Fits(yaw) => {
                    let keep = super::side_on::KEEP_M;
                    let fp = match yaw {
                        Some(yaw) => Footprint::side_on(Ground { x: first.x, y: first.y, yaw }),
                        None => Footprint::Disc { centre: first, radius },
                    };
                    fp.room(space, keep + 1.0) - keep
                }
                Stance::Walking => {
                    let want = radius + KEEP_ROOM_M;
                    let need = space.clearance(first, want + 1e-9).min(want) - 1e-6;
                    let far = want + 1.0;
                    let least = match pts {
                        [p] => space.clearance(*p, far),
                        _ => pts.windows(2).map(|w| space.segment_clearance(w[0], w[1], far)).fold(far, f64::min),
                    };
                    least - need
                }
                Stance::SideOn(yaw) => {
                    let keep = super::side_on::KEEP_M;
                    let fp = |p: DVec2| Footprint::side_on(Ground { x: p.x, y: p.y, yaw });
                    let need = fp(first).room(space, keep + 1e-9).min(keep) - 1e-6;
                    pts.iter().map(|&p| fp(p).room(space, keep + 1.0)).fold(f64::INFINITY, f64::min) - need
                }
            }
        };
        match self.side.choose(db, at, path, &mut room, LOCK_REACH_M, &limits) {
            Some(c) => {
                self.look.held = false;
                c
            }
            None => self.look.choose(db, at),
        }
    }
}

impl AnimatedBody {
    /// A character standing at `pose` in the slowest interval of the database.
    pub fn new(anim: Arc<Animation>, pose: Pose, radius: f64) -> AnimatedBody {
        let db = &anim.db;
        let start = (0..db.intervals.len())
            .min_by(|&a, &b| db.intervals[a].speed.total_cmp(&db.intervals[b].speed).then(a.cmp(&b)))
            .unwrap_or(0);
        let at = Ground { x: pose.position.x, y: pose.position.y, yaw: pose.yaw };
        let player = Player::new(db, start, at, anim.player);
        // The random baseline's stream, keyed by where the character starts.
        let key = pose.position.x.to_bits() ^ pose.position.y.to_bits().rotate_left(21) ^ pose.yaw.to_bits();
        AnimatedBody {
            player,
            radius,
            desired_heading: pose.yaw,
            command: Command::default(),
            speed: 0.0,
            commanded: at,
            switches: 0,
            rng: crate::rng::stream(key, 0, 0x7a9d),
            held: false,
            held_s: 0.0,
            order: Vec::new(),
            path: Vec::new(),
            tracking: Tracking::default(),
            footing: None,
            footing_switches: 0,
            motion: None,
            upper: None,
            upper_switches: 0,
            side_on: None,
            anim,
        }
    }

    /// Starts recording the motion: the pose now, then every frame played
    /// ([`AnimatedBody::motion`]).
    pub fn record_motion(&mut self) {
        self.motion = Some(vec![self.world_pose()]);
    }

    /// The frames recorded since [`AnimatedBody::record_motion`] (none when not recording), one
    /// every `1 / frame_rate` seconds: world poses (metres, Z up), the legs on the ground on
    /// uneven terrain ([`Footing::pose_legs`]).
    pub fn motion(&self) -> Option<&[crate::anim::Pose]> {
        self.motion.as_deref()
    }

    /// The skeleton's pose in the world now: on uneven terrain, the legs on the ground
    /// ([`Footing::pose_legs`]).
    pub fn world_pose(&self) -> crate::anim::Pose {
        let mut pose = self.player.pose().clone();
        if let Some(f) = self.footing.as_deref() {
            let db = &self.anim.db;
            let duration = db.intervals[self.player.interval()].duration;
            let progress = if duration > 0.0 { self.player.time_in_interval(db) / duration } else { 0.0 };
            f.pose_legs(&db.skeleton, &mut pose, progress);
        }
        if let Some(u) = self.upper.as_deref() {
            let c = u.offsets(self.player.time_in_interval(&self.anim.db));
            u.planner_body().apply(&mut pose, &c);
        }
        pose
    }

    /// Passes `gap` side-on (see [`super::side_on`]): from now on, until the manoeuvre is over,
    /// the character stops, pivots side-on, side-steps through the gap and pivots back,
    /// whatever it is commanded. Nothing happens while a manoeuvre runs already.
    pub fn pass_side_on(&mut self, gap: Gap) {
        if !self.side_on.is_some_and(|m| m.active()) {
            self.side_on = Some(SideOn::new(gap, self.player.ground()));
        }
    }

    /// The gap of a side-on manoeuvre that gave up, once: the manoeuvre is then forgotten.
    pub fn take_failed_side_on(&mut self) -> Option<Gap> {
        let m = self.side_on.filter(|m| m.phase == Phase::Failed)?;
        self.side_on = None;
        Some(m.gap)
    }

    /// The side-on manoeuvre, running or the last one's end.
    pub fn side_on(&self) -> Option<&SideOn> {
        self.side_on.as_ref()
    }

    /// How the last side-on manoeuvre stands ([`Phase::Done`] once through).
    pub fn side_on_phase(&self) -> Option<Phase> {
        self.side_on.map(|m| m.phase)
    }

    /// Gives the character an upper body that plans around the obstacles it can touch (see
    /// [`super::upper_body`]).
    pub fn set_upper_body(&mut self, upper: UpperBodyState) {
        self.upper_switches = self.player.metrics.switches;
        self.upper = Some(Box::new(upper));
    }

    /// The upper body's planner state, if it plans.
    pub fn upper_body(&self) -> Option<&UpperBodyState> {
        self.upper.as_deref()
    }

    /// The upper body's offsets now (zero when it does not plan).
    pub fn upper_offsets(&self) -> crate::anim::body::UpperConfig {
        self.upper.as_deref().map_or_else(Default::default, |u| u.offsets(self.player.time_in_interval(&self.anim.db)))
    }

    /// Puts the character's feet on uneven terrain: from now on every step of a moving
    /// interval is planned by `footing` (see [`super::footing`]).
    pub fn set_footing(&mut self, mut footing: Footing) {
        footing.decide(&self.anim.db, self.player.interval(), self.player.ground());
        self.footing_switches = self.player.metrics.switches;
        self.footing = Some(Box::new(footing));
    }

    /// The feet on uneven terrain, if any.
    pub fn footing(&self) -> Option<&Footing> {
        self.footing.as_deref()
    }

    /// The player (pose, footprints, playback metrics).
    pub fn player(&self) -> &Player {
        &self.player
    }

    /// The shared animation.
    pub fn animation(&self) -> &Animation {
        &self.anim
    }

    /// The direction error and speed error the policy sees now.
    pub fn errors(&self) -> Errors {
        let db = &self.anim.db;
        Errors {
            speed: self.command.speed - self.player.warp().speed(&db.intervals[self.player.interval()]),
            direction: wrap_angle(self.desired_heading - self.player.ground().yaw),
        }
    }

    /// True while the character stands still because what it wanted to do next was blocked by
    /// obstacles.
    pub fn held(&self) -> bool {
        self.held
    }

    /// Playback measurements.
    pub fn metrics(&self) -> PlaybackMetrics {
        self.player.metrics
    }

    /// The choice the character would make now at the end of the interval playing, among the
    /// candidates there (an index into them): ranking and clearance checks through `space`, as
    /// at every switch point.
    pub fn choose_next(&mut self, space: &mut dyn Space) -> Choice {
        let anim = Arc::clone(&self.anim);
        let at = self.player.upcoming_switch(&anim.db);
        let mut chooser = LookAhead {
            anim: &anim,
            space,
            radius: self.radius,
            command: self.command,
            desired: self.desired_heading,
            rng: &mut self.rng,
            order: &mut self.order,
            path: &mut self.path,
            held: false,
            restless: self.held_s > RESTLESS_S,
            upper: None,
            refused: 0,
        };
        chooser.choose(&anim.db, &at)
    }

    /// Stride warping within a step: when the commanded speed has changed since the interval
    /// playing began, the rest of it plays with the stride that meets the new speed (within the
    /// limits), if the path it then takes keeps the clearance the look-ahead keeps and the feet
    /// where it ends keep theirs — and the upper body is not moving for anything over the step
    /// (its plan was made for the step as chosen).
    fn restride(&mut self, space: &mut dyn Space) {
        let anim = Arc::clone(&self.anim);
        let db = &anim.db;
        let limits = &anim.policy.params.warp;
        let i = self.player.interval();
        let iv = &db.intervals[i];
        let now = self.player.warp();
        if db.kinds[i].in_place || iv.speed < limits.min_speed_mps {
            return;
        }
        let end = self.player.time_in_interval(db) + self.player.time_to_switch(db);
        if self.upper.as_deref().is_some_and(|u| u.active(end)) {
            return;
        }
        let stride = (self.command.speed / iv.speed).clamp(limits.stride.0, limits.stride.1);
        if (stride - now.stride).abs() < RESTRIDE_STEP {
            return;
        }
        let warp = Warp { stride, ..now };
        self.path.clear();
        let end = self.player.remaining_path_with(db, warp, &mut self.path);
        let g = self.player.ground();
        let want = self.radius + anim.clearance_m;
        let need = room_now(space, DVec2::new(g.x, g.y), want).min(want);
        // The step lands where the new stride puts it: its feet keep their room there too.
        if path_keeps(space, &self.path, need)
            && feet_keep_room(space, (db.feet_at(i, true), end), (db.feet_at(i, true), end))
        {
            self.player.rewarp(warp);
        }
    }

    /// When the rest of the interval playing is no longer clear (something moved into it),
    /// switches early to the best clear candidate.
    fn early_switch(&mut self, space: &mut dyn Space) {
        let anim = Arc::clone(&self.anim);
        let db = &anim.db;
        self.path.clear();
        self.player.remaining_path(db, &mut self.path);
        let need = self.radius - 1e-6;
        let blocked = match self.path.as_slice() {
            [] | [_] => false,
            pts => pts.windows(2).any(|w| space.segment_clearance(w[0], w[1], need) < need),
        };
        if !blocked {
            return;
        }
        let at = self.player.switch_point_now();
        let start = self.upper_offsets();
        let mut chooser = LookAhead {
            anim: &anim,
            space,
            radius: self.radius,
            command: self.command,
            desired: self.desired_heading,
            rng: &mut self.rng,
            order: &mut self.order,
            path: &mut self.path,
            held: false,
            restless: self.held_s > RESTLESS_S,
            upper: self.upper.as_deref_mut().map(|u| (u, start)),
            refused: 0,
        };
        let choice = chooser.choose(db, &at);
        self.held = chooser.held;
        self.player.switch_now(db, choice);
        if let Some(u) = self.upper.as_deref_mut() {
            u.switched();
            self.upper_switches = self.player.metrics.switches;
        }
    }
}

impl Body for AnimatedBody {
    fn pose(&self) -> Pose {
        let g = self.player.ground();
        Pose { position: DVec2::new(g.x, g.y), yaw: wrap_angle(g.yaw) }
    }

    fn speed(&self) -> f64 {
        self.speed
    }

    fn radius(&self) -> f64 {
        self.radius
    }

    fn passage_m(&self) -> f64 {
        2.0 * (self.radius + self.anim.clearance_m + PASSAGE_SLACK_M)
    }

    /// Side-on, when the database has side steps either way and turns on the spot.
    fn narrowest_passage_m(&self) -> Option<f64> {
        self.anim.side_on.then_some(super::side_on::SIDE_ON_PASSAGE_M)
    }

    fn footprint(&self) -> Footprint {
        match self.side_on {
            Some(m) if m.sideways => Footprint::side_on(self.player.ground()),
            _ => {
                let g = self.player.ground();
                Footprint::Disc { centre: DVec2::new(g.x, g.y), radius: self.radius }
            }
        }
    }

    fn turn_limit(&self, speed: f64) -> f64 {
        self.anim.turn_limit(speed)
    }

    fn step(&mut self, command: Command, dt: f64, space: &mut dyn Space) -> StepOutcome {
        let turn = if command.turn_rate.is_finite() { command.turn_rate } else { 0.0 };
        let speed = if command.speed.is_finite() { command.speed.max(0.0) } else { 0.0 };
        let toward = command.toward.filter(|t| t.is_finite());
        self.command = Command { turn_rate: turn, speed, toward };
        let before = self.player.ground();
        // Where the turn leads within the horizon, but not past the direction the planner
        // steers toward.
        let mut ahead = (turn * HEADING_HORIZON_S).clamp(-MAX_DIRECTION_ERROR, MAX_DIRECTION_ERROR);
        if let Some(t) = toward {
            let rel = wrap_angle(t - before.yaw);
            if rel * ahead > 0.0 && ahead.abs() > rel.abs() {
                ahead = rel;
            }
        }
        self.desired_heading = before.yaw + ahead;
        let manoeuvring = self.side_on.is_some_and(|m| m.active());
        if space.changes() && !manoeuvring {
            self.early_switch(space);
        }
        if !manoeuvring {
            self.restride(space);
        }
        let frames = ((dt * self.player.params.frame_rate) + 1e-9).floor().max(1.0) as usize;
        let anim = Arc::clone(&self.anim);
        let mut outcome = StepOutcome::default();
        for _ in 0..frames {
            let prev = self.player.ground();
            // The offsets at the end of the interval playing, where the next choice starts.
            let start = self.upper.as_deref().map(|u| {
                let db = &anim.db;
                let end = self.player.time_in_interval(db) + self.player.time_to_switch(db);
                u.offsets(end)
            });
            let mut chooser = LookAhead {
                anim: &anim,
                space: &mut *space,
                radius: self.radius,
                command: self.command,
                desired: self.desired_heading,
                rng: &mut self.rng,
                order: &mut self.order,
                path: &mut self.path,
                held: self.held,
                restless: self.held_s > RESTLESS_S,
                upper: self.upper.as_deref_mut().zip(start),
                refused: 0,
            };
            let sideways_before = self.side_on.is_some_and(|m| m.sideways);
            match self.side_on.as_mut().filter(|m| m.active()) {
                Some(side) => {
                    let mut both = SideOnChooser { side, look: chooser };
                    self.player.advance_frame(&anim.db, &mut both);
                    self.held = both.look.held;
                }
                None => {
                    self.player.advance_frame(&anim.db, &mut chooser);
                    self.held = chooser.held;
                }
            }
            let sideways = sideways_before || self.side_on.is_some_and(|m| m.sideways);
            let mut now = self.player.ground();
            if let Some(f) = self.footing.as_deref_mut() {
                if self.player.metrics.switches != self.footing_switches {
                    self.footing_switches = self.player.metrics.switches;
                    f.decide(&anim.db, self.player.interval(), prev);
                }
                // The adapted step: the root follows the planned hip (held when stopped).
                let db = &anim.db;
                let duration = db.intervals[self.player.interval()].duration;
                let progress = if duration > 0.0 { self.player.time_in_interval(db) / duration } else { 1.0 };
                if let Some(root) = f.root_at(progress, prev, now) {
                    now = root;
                    self.player.hold(db, now);
                } else if f.stopped().is_some() {
                    now = Ground { yaw: now.yaw, ..prev };
                    self.player.hold(db, now);
                }
                if f.stopped().is_some() {
                    outcome.held = true;
                }
            }
            let to = DVec2::new(now.x, now.y);
            let from = DVec2::new(prev.x, prev.y);
            let room_kept =
                if sideways { side_on_keeps_room(space, prev, now) } else { keeps_room(space, from, to, self.radius) };
            if to != from && !room_kept {
                // Last resort: the root stays, the locked feet with it.
                self.player.hold(&anim.db, Ground { yaw: now.yaw, ..prev });
                outcome.blocked = true;
            } else {
                outcome.moved_m += from.distance(to);
            }
            if let Some(u) = self.upper.as_deref_mut()
                && self.player.metrics.switches != self.upper_switches
            {
                self.upper_switches = self.player.metrics.switches;
                u.switched();
            }
            if self.motion.is_some() || self.upper.is_some() {
                let pose = self.world_pose();
                let c = self.upper_offsets();
                if let Some(u) = self.upper.as_deref_mut() {
                    u.measure(&pose, &c);
                }
                if let Some(m) = self.motion.as_mut() {
                    m.push(pose);
                }
            }
        }
        outcome.held = (self.held || outcome.held) && speed >= HELD_SPEED_MPS;
        self.held_s = if self.held { self.held_s + dt } else { 0.0 };
        self.speed = outcome.moved_m / dt;
        // Tracking: the commanded unicycle from the root at the last switch point.
        let g = self.player.ground();
        if self.player.metrics.switches != self.switches {
            self.switches = self.player.metrics.switches;
            self.commanded = g;
        } else {
            let c = &mut self.commanded;
            c.yaw += turn * dt;
            c.x += speed * dt * c.yaw.cos();
            c.y += speed * dt * c.yaw.sin();
        }
        let t = &mut self.tracking;
        t.sq_distance += (self.commanded.x - g.x).powi(2) + (self.commanded.y - g.y).powi(2);
        t.sq_direction += wrap_angle(self.desired_heading - g.yaw).powi(2);
        t.sq_speed += (speed - self.speed).powi(2);
        t.samples += 1;
        outcome
    }
}

/// Command tracking figures of an animated character on open ground (DESIGN.md §3).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct TrackingFigures {
    /// Seconds from a commanded 90° heading change to the left, while walking, until the
    /// heading is within 10° of it; mean over [`PHASES`] starting phases of the stride.
    pub turn_left_90_s: f64,
    /// The same to the right.
    pub turn_right_90_s: f64,
    /// Seconds from a commanded speed change (slow walk to walk) until the speed over the last
    /// half second is within 10 % of it; mean over the starting phases.
    pub speed_up_s: f64,
    /// The same from walk to slow walk.
    pub slow_down_s: f64,
    /// The slowest of the starting phases for each of the four: left, right, up, down.
    pub worst_s: [f64; 4],
    /// RMS distance between the commanded path and the root path over a 60 s run of varied
    /// commands from the planner's ranges, metres.
    pub rms_path_m: f64,
    /// Foot skating (heel and toe points) over all of the above, cm per frame.
    pub foot_skating_cm_per_frame: f64,
    /// Share of foot plants that slid less than 2 cm, over all of the above.
    pub steady_plant_share: f64,
    /// Mean pose distance at transitions over all of the above.
    pub transition_cost: f64,
    /// Transitions per second over all of the above.
    pub transitions_per_s: f64,
}

/// Starting phases of the stride over which each latency of [`measure_tracking`] is averaged.
pub const PHASES: usize = 16;

/// Runs the scripted tracking tests on open ground; a time of 10 s means the command was not met
/// within 10 s. Each latency starts from a character that has walked (or slow-walked) for 4 s,
/// at [`PHASES`] phases spread over one stride.
pub fn measure_tracking(anim: &Arc<Animation>, walk_speed: f64, slow_speed: f64) -> TrackingFigures {
    const DT: f64 = 0.05;
    const CAP_S: f64 = 10.0;
    let start = Pose { position: DVec2::ZERO, yaw: 0.0 };
    let mut all = PlaybackMetrics::default();
    let mut sim_time = 0.0;
    // A character that has settled into `speed`, then walked on to phase `k` of a stride.
    let settle = |speed: f64, k: usize, time: &mut f64| {
        let mut b = AnimatedBody::new(anim.clone(), start, 0.3);
        for _ in 0..(4.0 / DT) as usize {
            b.step(Command { turn_rate: 0.0, speed, toward: None }, DT, &mut OpenSpace);
        }
        let stride = 2.0 * anim.db.intervals[b.player.interval()].duration;
        let frames = (k as f64 * stride * b.player.params.frame_rate / PHASES as f64).round() as usize;
        for _ in 0..frames {
            b.step(Command { turn_rate: 0.0, speed, toward: None }, 1.0 / b.player.params.frame_rate, &mut OpenSpace);
        }
        *time += 4.0 + frames as f64 / b.player.params.frame_rate;
        b
    };
    let mut latencies = [0.0f64; 4];
    let mut worst = [0.0f64; 4];
    for k in 0..PHASES {
        // A commanded heading change: the command is the turn rate that would close the remaining
        // heading error within the horizon, as a planner steering to a fixed heading commands.
        for (slot, sign) in [(0usize, 1.0f64), (1, -1.0)] {
            let mut b = settle(walk_speed, k, &mut sim_time);
            let target = b.player.ground().yaw + sign * std::f64::consts::FRAC_PI_2;
            let mut t = 0.0;
            while wrap_angle(target - b.player.ground().yaw).abs() > 10f64.to_radians() && t < CAP_S {
                let turn_rate = wrap_angle(target - b.player.ground().yaw) / HEADING_HORIZON_S;
                b.step(Command { turn_rate, speed: walk_speed, toward: None }, DT, &mut OpenSpace);
                t += DT;
            }
            sim_time += t;
            all.absorb(&b.metrics());
            latencies[slot] += t / PHASES as f64;
            worst[slot] = worst[slot].max(t);
        }
        for (slot, from, to) in [(2usize, slow_speed, walk_speed), (3, walk_speed, slow_speed)] {
            let mut b = settle(from, k, &mut sim_time);
            let window = (0.5 / DT) as usize;
            let mut recent: Vec<f64> = Vec::new();
            let mut t = 0.0;
            loop {
                let out = b.step(Command { turn_rate: 0.0, speed: to, toward: None }, DT, &mut OpenSpace);
                t += DT;
                recent.push(out.moved_m);
                if recent.len() > window {
                    recent.remove(0);
                }
                let v = recent.iter().sum::<f64>() / (recent.len() as f64 * DT);
                if (recent.len() == window && (v - to).abs() <= 0.1 * to) || t >= CAP_S {
                    break;
                }
            }
            sim_time += t;
            all.absorb(&b.metrics());
            latencies[slot] += t / PHASES as f64;
            worst[slot] = worst[slot].max(t);
        }
    }
    // Varied commands: a new (turn, speed) every 2 s, from a fixed stream.
    let mut b = AnimatedBody::new(anim.clone(), start, 0.3);
    let mut rng = crate::rng::stream(2024, 0, 7);
    let mut command = Command::default();
    for k in 0..(60.0 / DT) as usize {
        if k % 40 == 0 {
            command = Command {
                turn_rate: crate::rng::uniform(&mut rng, -0.8, 0.8),
                speed: crate::rng::uniform(&mut rng, slow_speed, walk_speed),
                toward: None,
            };
        }
        b.step(command, DT, &mut OpenSpace);
    }
    sim_time += 60.0;
    all.absorb(&b.metrics());
    TrackingFigures {
        turn_left_90_s: latencies[0],
        turn_right_90_s: latencies[1],
        speed_up_s: latencies[2],
        slow_down_s: latencies[3],
        worst_s: worst,
        rms_path_m: b.tracking.rms_path_m(),
        foot_skating_cm_per_frame: all.foot_skating_cm_per_frame(),
        steady_plant_share: all.steady_plant_share(),
        transition_cost: all.mean_transition_cost(),
        transitions_per_s: all.transitions as f64 / sim_time.max(1e-9),
    }
}
