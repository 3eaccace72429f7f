//! The animation database (seed 000 §3.2, §3.2.1; DESIGN.md §3): clips cut into intervals that
//! begin and end at foot plants, the pose distance of Eq. 1, the interval distance of Eq. 2, the
//! K nearest neighbours of every interval with the weights of Eq. 3, and the candidates at each
//! switch point (the natural successor and its neighbours).
//!
//! Intervals are found from foot contacts (the heights and speeds of each foot's heel and toe)
//! or given by hand. Each interval is resampled at `n + 1` normalized times in its own frame —
//! start on the origin, facing +X — so comparing two intervals is a flat loop over precomputed
//! samples.
//!
//! Beyond the seed, the database knows what the controller's safety rules need: the root motion
//! of every clip frame by frame ([`Database::ground`] is a lookup), which contact points touch
//! the ground in every frame (for foot locking and honest skating figures), which intervals end
//! at rest or stay in place, and the left–right mirror of every interval. Candidate lists are
//! built mirror-symmetric (the candidates of an interval's mirror are the mirrors of its
//! candidates, in the same order), and every interval can reach a stop, a turn on the spot to
//! either side and a way to get going in one switch: where the K pose neighbours lack them,
//! the nearest such intervals are added, weighted by Eq. 3 like any candidate.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::clip::{Clip, Ground};
use super::skeleton::{Pose, Skeleton, SlerpArc, angle_between};
use crate::geom::wrap_angle;

/// Parameters of the database. Every field documents its default.
#[derive(Debug, Clone, PartialEq)]
pub struct DbParams {
    /// Neighbours per interval, K (6).
    pub k: usize,
    /// Normalized time samples per interval for Eq. 2 are `n + 1` (n = 10).
    pub samples: usize,
    /// Joint weights of Eq. 1.
    pub weights: WeightParams,
    /// Foot contact detection.
    pub contacts: ContactParams,
    /// Shortest interval kept, seconds (0.15): plants closer than this are merged.
    pub min_interval_s: f64,
    /// Longest interval, seconds (1.0): longer stretches without a plant (standing) are split.
    pub max_interval_s: f64,
    /// Most neighbours taken from one clip (1), so near-copies of one motion (the steps of a
    /// cyclic clip) do not crowd out the alternatives; when the clips cannot fill K this way,
    /// the nearest remaining intervals fill the list.
    pub max_per_clip: usize,
}

impl Default for DbParams {
    fn default() -> Self {
        DbParams {
            k: 6,
            samples: 10,
            weights: WeightParams::default(),
            contacts: ContactParams::default(),
            min_interval_s: 0.15,
            max_interval_s: 1.0,
            max_per_clip: 1,
        }
    }
}

/// How Eq. 1 weighs joints: `w_i = depth_decay^depth · (1 + length_gain · ℓ_i / ℓ_max)`, with `ℓ_i`
/// the reach of joint `i` (the farthest bind-pose point its rotation swings: descendants and end
/// sites); joints high in the hierarchy and long bones weigh more. Joints without rotation channels weigh nothing.
#[derive(Debug, Clone, PartialEq)]
pub struct WeightParams {
    /// Weight of the root position term, per square metre (4).
    pub root_position: f64,
    /// Factor per level of depth (0.8).
    pub depth_decay: f64,
    /// Gain of the bone-length term (1).
    pub length_gain: f64,
    /// Explicit weights by joint name, replacing the computed ones.
    pub overrides: Vec<(String, f64)>,
}

impl Default for WeightParams {
    fn default() -> Self {
        WeightParams { root_position: 4.0, depth_decay: 0.8, length_gain: 1.0, overrides: Vec::new() }
    }
}

impl WeightParams {
    /// The weight of every joint of `skeleton`.
    pub fn joint_weights(&self, skeleton: &Skeleton) -> Vec<f64> {
        let depth = skeleton.depths();
        let len = skeleton.reaches();
        let lmax = len.iter().cloned().fold(0.0, f64::max).max(1e-9);
        skeleton
            .joints()
            .iter()
            .enumerate()
            .map(|(i, j)| {
                if let Some((_, w)) = self.overrides.iter().find(|(n, _)| *n == j.name) {
                    return *w;
                }
                let rotates = i == 0 || j.channels.iter().any(|c| !c.is_position());
                if !rotates {
                    return 0.0;
                }
                self.depth_decay.powi(depth[i] as i32) * (1.0 + self.length_gain * len[i] / lmax)
            })
            .collect()
    }
}

/// Foot contact detection: a contact point (heel or toe) is on the ground while its height above
/// its lowest point in the clip is below `height_m` and its horizontal speed below `speed_mps`; a
/// foot is on the ground while either of its points is.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactParams {
    /// Height threshold, metres (0.05).
    pub height_m: f64,
    /// Speed threshold, metres per second (0.5).
    pub speed_mps: f64,
    /// Contacts or gaps shorter than this many frames are ignored (3).
    pub min_frames: usize,
    /// Names of the two foot joints (left, right); when empty, found by name
    /// (`LeftFoot`/`RightFoot`, `LeftAnkle`/`RightAnkle`, `l_foot`/`r_foot` …).
    pub feet: Vec<String>,
    /// The heel and toe of the left foot in its joint's frame, metres (the right foot's are
    /// their mirror images); when `None`, found from the skeleton ([`contact_points`]).
    pub points: Option<[DVec3; 2]>,
}

impl Default for ContactParams {
    fn default() -> Self {
        ContactParams { height_m: 0.05, speed_mps: 0.5, min_frames: 3, feet: Vec::new(), points: None }
    }
}

/// A root translation over an interval below this counts as staying in place, metres.
pub const IN_PLACE_M: f64 = 0.1;
/// A root speed over the last [`REST_WINDOW_S`] of an interval below this counts as at rest, m/s.
pub const REST_SPEED_MPS: f64 = 0.05;
/// Window at the end of an interval over which rest is judged, seconds.
pub const REST_WINDOW_S: f64 = 0.15;
/// A heading change over an in-place interval of at least this is a turn on the spot, radians.
pub const SPOT_TURN_RAD: f64 = 20.0 * std::f64::consts::PI / 180.0;
/// Smallest heading change of a moving interval that counts as a sharp turn, radians (40°).
pub const SHARP_TURN_RAD: f64 = 40.0 * std::f64::consts::PI / 180.0;
/// Largest spacing of the root-path points kept for clearance checks, metres.
pub const SWEEP_SPACING_M: f64 = 0.1;
/// Largest heading change between two kept points, radians (5°).
pub const SWEEP_TURN_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;
/// Largest distance of the root path from the chord between two kept points, metres.
pub const SWEEP_DEVIATION_M: f64 = 0.002;
/// Largest Eq. 2 distance between an interval's mirror image and another interval for the two
/// to count as mirrors.
pub const MIRROR_TOLERANCE: f64 = 1e-4;

/// Eq. 2 distance below which a mirror image is exact (a clip mirrored frame by frame).
const EXACT_MIRROR: f64 = 1e-9;

/// What an interval does, as far as stopping and turning are concerned.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IntervalKind {
    /// The root is at rest by the interval's end (a stop, standing).
    pub ends_at_rest: bool,
    /// The root moves less than [`IN_PLACE_M`] over the interval (standing, turning on the spot).
    pub in_place: bool,
    /// Turns on the spot: in place, heading change at least [`SPOT_TURN_RAD`]; +1 left, −1
    /// right, 0 not a turn on the spot.
    pub spot_turn: i8,
    /// Comes to rest within two intervals: ends at rest, or its natural successor does.
    pub stops: bool,
    /// Gets going: the root moves at least [`IN_PLACE_M`] from where it started.
    pub goes: bool,
    /// Turns sharply while moving: not in place, heading change at least [`SHARP_TURN_RAD`];
    /// +1 left, −1 right, 0 not a sharp turn.
    pub sharp_turn: i8,
    /// Part of a step that does not go forward ([`Database::shuffle_of`]): +1 to the left, −1 to
    /// the right, 2 back, 0 none. Side steps and steps back are taken only to get out of a
    /// tight place (they come after the other candidates, [`Database::policy_actions`]).
    pub shuffle: i8,
}

impl IntervalKind {
    /// Safe to end a look-ahead on: standing, stopping or turning on the spot.
    pub fn is_brake(&self) -> bool {
        self.ends_at_rest || self.in_place
    }
}

/// A side step or a step back ([`IntervalKind::shuffle`]) goes at least this far from the start
/// heading, radians (60°; 120° for a step back).
pub const SHUFFLE_RAD: f64 = std::f64::consts::FRAC_PI_3;

/// A candidate list (interval, Eq. 2 distance) and how many of it the policy ranks.
type RankedList = (Vec<(usize, f64)>, usize);

/// Intervals looked along a clip for where a step comes to rest ([`Database::shuffle_of`]).
const SHUFFLE_REACH: usize = 3;

/// Why a database cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DbError {
    /// No clips.
    #[error("the database has no clips")]
    NoClips,
    /// Clips with different skeletons.
    #[error("clip '{0}' has a different skeleton from the first clip")]
    SkeletonMismatch(String),
    /// The feet could not be found.
    #[error("cannot find the foot joints (tried {0}); name them explicitly")]
    NoFeet(String),
    /// A clip frame has the wrong number of rotations or non-finite values.
    #[error("clip '{0}' frame {1} is malformed")]
    BadFrame(String, usize),
    /// A hand-written interval is outside its clip.
    #[error("interval {0} of clip '{1}' ({2}..{3}) is outside the clip or empty")]
    BadInterval(usize, String, usize, usize),
    /// A hand-written interval names an unknown clip.
    #[error("interval {0} names unknown clip '{1}'")]
    UnknownClip(usize, String),
    /// Fewer intervals than needed for the neighbour search.
    #[error("found {0} intervals; at least {1} (K + 1) are needed")]
    TooFewIntervals(usize, usize),
    /// Frame time not positive.
    #[error("clip '{0}' has a non-positive frame time")]
    FrameTime(String),
    /// K or the number of samples outside its range.
    #[error("{0}")]
    Params(String),
}

/// Most neighbours per interval, K.
pub const MAX_K: usize = 64;

/// Most normalized time samples per interval (Eq. 2).
pub const MAX_SAMPLES: usize = 1000;

/// A hand-written interval: frames `start..=end` of the clip named `clip`.
#[derive(Debug, Clone, PartialEq)]
pub struct IntervalSpec {
    /// Clip name.
    pub clip: String,
    /// First frame.
    pub start: usize,
    /// Last frame.
    pub end: usize,
}

/// One interval: frames `start..=end` of a clip, from foot plant to foot plant.
#[derive(Debug, Clone, PartialEq)]
pub struct Interval {
    /// Index of the clip.
    pub clip: usize,
    /// First frame.
    pub start: usize,
    /// Last frame.
    pub end: usize,
    /// Duration, seconds.
    pub duration: f64,
    /// The ground reference at the end relative to the one at the start (root motion).
    pub motion: Ground,
    /// Mean horizontal root speed, metres per second.
    pub speed: f64,
    /// Which foot plants at the start (0 left, 1 right; 2 both or unknown).
    pub foot: u8,
}

impl Interval {
    /// Heading change over the interval, radians.
    pub fn turn(&self) -> f64 {
        self.motion.yaw
    }
}

/// A choice at a switch point: an interval and its neighbour weight (Eq. 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    /// Interval index.
    pub interval: usize,
    /// Weight `w_a` among the candidates, summing to 1.
    pub weight: f64,
    /// Interval distance (Eq. 2) from the natural successor (0 for the successor itself).
    pub distance: f64,
    /// Continues the ending interval's motion without a transition: its clip's next frames,
    /// or a start pose equal to the ending pose (pose distance below [`SEAMLESS`]).
    pub seamless: bool,
}

/// Pose distance (Eq. 1) below which a switch continues the motion seamlessly, needing no
/// transition.
pub const SEAMLESS: f64 = 1e-4;

/// The animation database.
#[derive(Debug, Clone)]
pub struct Database {
    /// The skeleton shared by every clip.
    pub skeleton: Skeleton,
    /// The clips.
    pub clips: Vec<Clip>,
    /// The intervals, clip by clip in time order.
    pub intervals: Vec<Interval>,
    /// What each interval does (stops, stays in place, turns on the spot).
    pub kinds: Vec<IntervalKind>,
    /// The K nearest neighbours of every interval with their distances, nearest first.
    pub neighbours: Vec<Vec<(usize, f64)>>,
    /// The natural successor of every interval: the next interval of its clip, or the interval
    /// whose start pose is nearest to its end pose when the clip ends there.
    pub successor: Vec<usize>,
    /// Candidates at the end of every interval: its successor first, then the successor's
    /// neighbours, then any stop or turn on the spot the neighbours lack; after a standing
    /// interval, side steps and steps back last.
    pub candidates: Vec<Vec<Candidate>>,
    /// How many of each interval's candidates the policy ranks: all but the side steps and steps
    /// back at the end of the list, which only a character held in a tight place takes.
    pub policy_actions: Vec<usize>,
    /// The left–right mirror of every interval, when the database holds it.
    pub mirror: Vec<Option<usize>>,
    /// For intervals with a mirror: `mirror_candidate[i][a]` is the index, among the candidates
    /// of `mirror[i]`, of the mirror of candidate `a` of `i` (empty without a mirror).
    pub mirror_candidate: Vec<Vec<usize>>,
    /// The joint weights of Eq. 1.
    pub joint_weights: Vec<f64>,
    /// The foot joints (left, right).
    pub feet: [usize; 2],
    /// Heel and toe of each foot in the foot joint's frame, metres ([`contact_points`]).
    pub contact_points: [[DVec3; 2]; 2],
    /// Lowest height of each contact point over the database, metres (its height on the ground).
    pub point_floor: [[f64; 2]; 2],
    /// The ε of Eq. 3.
    pub epsilon: f64,
    /// Parameters it was built with.
    pub params: DbParams,
    /// Heading of the root's forward axis in the bind pose, radians.
    pub forward_offset: f64,
    samples: Vec<Vec<Pose>>,
    /// Ground reference of every frame of every clip.
    tracks: Vec<Vec<Ground>>,
    /// Contact bits of every frame of every clip ([`detect_contacts`]).
    contacts: Vec<Vec<u8>>,
    /// Per clip and frame: frames so far in which no foot stands flat ([`turn_freedom`]).
    freedom: Vec<Vec<f64>>,
    /// Per interval and sweep frame: the root's motion from the kept frame before (the
    /// interval's start for the first) in that frame's ground frame, and the share of a bend
    /// turned over it.
    sweep_steps: Vec<Vec<(Ground, f64)>>,
    /// Per interval, clip frames after its start whose root positions are at most
    /// [`SWEEP_SPACING_M`] apart, ending with its last frame.
    sweep_frames: Vec<Vec<usize>>,
    /// Per interval, the feet at its first and last frame: contact bits and the heel and toe
    /// positions in the interval's ground frame at that frame.
    ends: Vec<[FeetAt; 2]>,
    /// Per clip, the arc of every joint's rotation from each frame to the next (frame by
    /// frame, joint by joint), for sampling between frames.
    arcs: Vec<Vec<SlerpArc>>,
}

/// Where the feet are in a frame: contact bits ([`contact_bit`]) and the heel and toe of each
/// foot in the frame's own ground frame (root above the origin, facing +X), metres.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FeetAt {
    /// Contact bits.
    pub bits: u8,
    /// `[foot][0 heel, 1 toe]`.
    pub points: [[DVec3; 2]; 2],
}

/// Finds the left and right foot joints: by the two `names` given, else by joint names (namespace
/// prefixes, case and separators ignored), else by the shape of the hierarchy
/// ([`rig::locate_feet`](super::rig::locate_feet)).
pub fn find_feet(skeleton: &Skeleton, names: &[String]) -> Result<[usize; 2], DbError> {
    match super::rig::locate_feet(skeleton, names) {
        Some((feet, _)) => Ok(feet),
        None if names.len() == 2 => Err(DbError::NoFeet(names.join(", "))),
        None => Err(DbError::NoFeet(
            "LeftFoot/RightFoot, LeftAnkle/RightAnkle and their variants, then the shape of the hierarchy".into(),
        )),
    }
}

/// Heading of the root's forward axis in the bind pose: perpendicular to the line from the
/// right foot's hip to the left's, so a character standing with its left side toward +Y faces
/// +X (0).
pub fn forward_offset(skeleton: &Skeleton, feet: [usize; 2]) -> f64 {
    let p = skeleton.positions(&skeleton.bind_pose());
    let lateral = p[feet[0]] - p[feet[1]];
    let f = lateral.cross(DVec3::Z);
    if f.x.abs() + f.y.abs() < 1e-9 { 0.0 } else { f.y.atan2(f.x) }
}

/// The heel and the toe of each foot (`[foot][0]` heel, `[foot][1]` toe) in the foot joint's
/// own frame, metres. The toe is the foot's farthest tip in the bind pose (an end site or a toe
/// joint below it); the heel lies at the toe's height under the ankle, a quarter of the foot's
/// length behind it. A foot without anything below it has both points at the ankle.
pub fn contact_points(skeleton: &Skeleton, feet: [usize; 2]) -> [[DVec3; 2]; 2] {
    let mut g = Vec::new();
    skeleton.globals(&skeleton.bind_pose(), &mut g);
    let joints = skeleton.joints();
    let below = |j: usize, foot: usize| {
        let mut k = Some(j);
        while let Some(x) = k {
            if x == foot {
                return true;
            }
            k = joints[x].parent;
        }
        false
    };
    feet.map(|f| {
        let ankle = g[f].0;
        let mut toe = ankle;
        for j in (f..joints.len()).filter(|&j| below(j, f)) {
            let mut tips = vec![g[j].0];
            if let Some(e) = joints[j].end_site {
                tips.push(g[j].0 + g[j].1 * e);
            }
            for t in tips {
                if (t - ankle).truncate().length() > (toe - ankle).truncate().length() {
                    toe = t;
                }
            }
        }
        let forward = (toe - ankle).truncate();
        let heel = DVec3::new(ankle.x - 0.25 * forward.x, ankle.y - 0.25 * forward.y, toe.z);
        let inv = g[f].1.inverse();
        [inv * (heel - ankle), inv * (toe - ankle)]
    })
}

/// Bit of `foot`'s heel (`point` 0) or toe (`point` 1) in a frame's contact bits.
pub fn contact_bit(foot: usize, point: usize) -> u8 {
    1 << (2 * foot + point)
}

/// World positions of the heel and toe of each foot, from the globals of a pose.
pub fn point_positions(
    globals: &[(DVec3, glam::DQuat)],
    feet: [usize; 2],
    points: &[[DVec3; 2]; 2],
) -> [[DVec3; 2]; 2] {
    [0, 1].map(|f| {
        let (p, q) = globals[feet[f]];
        [p + q * points[f][0], p + q * points[f][1]]
    })
}

/// Contacts of a clip: per frame, the bits ([`contact_bit`]) of the heels and toes on the
/// ground. A foot's contact runs and gaps shorter than `min_frames` are dropped first, then a
/// point counts as down only while its foot is.
pub fn detect_contacts(
    skeleton: &Skeleton,
    clip: &Clip,
    feet: [usize; 2],
    points: &[[DVec3; 2]; 2],
    params: &ContactParams,
) -> Vec<u8> {
    let mut globals = Vec::new();
    let pos: Vec<[[DVec3; 2]; 2]> = clip
        .frames
        .iter()
        .map(|frame| {
            skeleton.globals(frame, &mut globals);
            point_positions(&globals, feet, points)
        })
        .collect();
    let n = pos.len();
    let mut bits = vec![0u8; n];
    for f in 0..2 {
        let mut foot = vec![false; n];
        for k in 0..2 {
            let floor = pos.iter().map(|p| p[f][k].z).fold(f64::INFINITY, f64::min);
            for i in 0..n {
                let (a, b) = if i == 0 { (0, 1.min(n - 1)) } else { (i - 1, i) };
                let d = pos[b][f][k] - pos[a][f][k];
                let speed = (d.x * d.x + d.y * d.y).sqrt() / clip.frame_time;
                if pos[i][f][k].z - floor < params.height_m && speed < params.speed_mps {
                    bits[i] |= contact_bit(f, k);
                    foot[i] = true;
                }
            }
        }
        // Drop short gaps, then short contacts.
        fill_runs(&mut foot, false, params.min_frames);
        fill_runs(&mut foot, true, params.min_frames);
        for i in 0..n {
            let both = contact_bit(f, 0) | contact_bit(f, 1);
            if !foot[i] {
                bits[i] &= !both;
            } else if bits[i] & both == 0 {
                // A gap filled in: the lower point is down.
                let k = usize::from(pos[i][f][1].z < pos[i][f][0].z);
                bits[i] |= contact_bit(f, k);
            }
        }
    }
    bits
}

/// Per foot, whether it is on the ground in each frame of `bits`.
pub fn foot_contacts(bits: &[u8]) -> [Vec<bool>; 2] {
    [0, 1].map(|f| bits.iter().map(|b| b & (contact_bit(f, 0) | contact_bit(f, 1)) != 0).collect())
}

/// Flips interior runs of `value` shorter than `min` frames.
fn fill_runs(v: &mut [bool], value: bool, min: usize) {
    let n = v.len();
    let mut i = 0;
    while i < n {
        if v[i] != value {
            i += 1;
            continue;
        }
        let s = i;
        while i < n && v[i] == value {
            i += 1;
        }
        if s > 0 && i < n && i - s < min {
            v[s..i].iter_mut().for_each(|x| *x = !value);
        }
    }
}

/// Cuts a clip into intervals at foot plants: the first frame when a foot is down there, every
/// frame a foot touches down, and the last frame when a foot is down there; stretches longer
/// than `max_frames` are split evenly and boundaries closer than `min_frames` merged.
pub fn plant_boundaries(contacts: &[Vec<bool>; 2], min_frames: usize, max_frames: usize) -> Vec<(usize, u8)> {
    let n = contacts[0].len();
    if n < 2 {
        return Vec::new();
    }
    let mut raw: Vec<(usize, u8)> = Vec::new();
    for i in 0..n {
        let touch = |f: usize| contacts[f][i] && (i == 0 || !contacts[f][i - 1]);
        let down = |f: usize| contacts[f][i];
        let foot = match (touch(0), touch(1)) {
            (true, false) => Some(0),
            (false, true) => Some(1),
            (true, true) => Some(2),
            _ if (i == n - 1) && (down(0) || down(1)) => Some(2),
            _ => None,
        };
        if let Some(f) = foot {
            raw.push((i, f));
        }
    }
    let mut kept: Vec<(usize, u8)> = Vec::new();
    for (i, f) in raw {
        match kept.last() {
            None => kept.push((i, f)),
            Some(&(last, _)) if i - last >= min_frames.max(1) => kept.push((i, f)),
            Some(_) if i == n - 1 && kept.len() > 1 => {
                // Keep the clip's end as a boundary: it joins the clip to its continuation.
                kept.pop();
                if kept.last().is_none_or(|&(l, _)| i - l >= min_frames.max(1)) {
                    kept.push((i, f));
                }
            }
            Some(_) => {}
        }
    }
    let mut out = Vec::new();
    for w in kept.windows(2) {
        out.push(w[0]);
        let (a, b) = (w[0].0, w[1].0);
        let parts = (b - a).div_ceil(max_frames.max(1));
        for p in 1..parts {
            out.push((a + (b - a) * p / parts, 2));
        }
    }
    if let Some(&l) = kept.last() {
        out.push(l);
    }
    out
}

impl Database {
    /// Builds a database: finds intervals (or takes `manual` ones), samples them, finds the K
    /// nearest neighbours of each (in parallel; the result does not depend on the number of
    /// threads) and the candidates at each switch point.
    pub fn build(
        clips: Vec<Clip>,
        skeleton: Skeleton,
        params: DbParams,
        manual: Option<&[IntervalSpec]>,
    ) -> Result<Database, DbError> {
        if clips.is_empty() {
            return Err(DbError::NoClips);
        }
        if !(1..=MAX_K).contains(&params.k) {
            return Err(DbError::Params(format!(
                "K (neighbours per interval) must be in 1..={MAX_K}, found {}",
                params.k
            )));
        }
        if !(1..=MAX_SAMPLES).contains(&params.samples) {
            return Err(DbError::Params(format!(
                "samples per interval must be in 1..={MAX_SAMPLES}, found {}",
                params.samples
            )));
        }
        for c in &clips {
            if !(c.frame_time > 0.0) || !c.frame_time.is_finite() {
                return Err(DbError::FrameTime(c.name.clone()));
            }
            for (i, f) in c.frames.iter().enumerate() {
                if f.rotations.len() != skeleton.len()
                    || !f.root.is_finite()
                    || f.rotations.iter().any(|q| !q.is_finite())
                {
                    return Err(DbError::BadFrame(c.name.clone(), i));
                }
            }
        }
        let feet = find_feet(&skeleton, &params.contacts.feet)?;
        let forward = forward_offset(&skeleton, feet);
        let points = match params.contacts.points {
            Some([heel, toe]) => {
                let mirror = |v: DVec3| DVec3::new(v.x, -v.y, v.z);
                [[heel, toe], [mirror(heel), mirror(toe)]]
            }
            None => contact_points(&skeleton, feet),
        };
        let contacts: Vec<Vec<u8>> =
            clips.iter().map(|c| detect_contacts(&skeleton, c, feet, &points, &params.contacts)).collect();
        let mut spans: Vec<(usize, usize, usize, u8)> = Vec::new();
        match manual {
            Some(list) => {
                for (k, s) in list.iter().enumerate() {
                    let ci = clips
                        .iter()
                        .position(|c| c.name == s.clip)
                        .ok_or_else(|| DbError::UnknownClip(k + 1, s.clip.clone()))?;
                    if s.end <= s.start || s.end >= clips[ci].frames.len() {
                        return Err(DbError::BadInterval(k + 1, s.clip.clone(), s.start, s.end));
                    }
                    // The foot that touches down at the start, if one does.
                    let feet_down = foot_contacts(&contacts[ci]);
                    let touch = |f: usize| feet_down[f][s.start] && (s.start == 0 || !feet_down[f][s.start - 1]);
                    let foot = match (touch(0), touch(1)) {
                        (true, false) => 0,
                        (false, true) => 1,
                        _ => 2,
                    };
                    spans.push((ci, s.start, s.end, foot));
                }
            }
            None => {
                for (ci, c) in clips.iter().enumerate() {
                    let min = (params.min_interval_s / c.frame_time).round() as usize;
                    let max = (params.max_interval_s / c.frame_time).round() as usize;
                    let b = plant_boundaries(&foot_contacts(&contacts[ci]), min, max);
                    for w in b.windows(2) {
                        spans.push((ci, w[0].0, w[1].0, w[0].1));
                    }
                }
            }
        }
        if spans.len() < params.k + 1 {
            return Err(DbError::TooFewIntervals(spans.len(), params.k + 1));
        }
        let mut globals = Vec::new();
        let mut floor = [[f64::INFINITY; 2]; 2];
        for c in &clips {
            for f in &c.frames {
                skeleton.globals(f, &mut globals);
                let p = point_positions(&globals, feet, &points);
                for (k, fl) in floor.iter_mut().enumerate() {
                    for (j, x) in fl.iter_mut().enumerate() {
                        *x = x.min(p[k][j].z);
                    }
                }
            }
        }
        let tracks: Vec<Vec<Ground>> =
            clips.iter().map(|c| c.frames.iter().map(|f| Ground::of(f, forward)).collect()).collect();
        let n = params.samples.max(1);
        let mut intervals = Vec::with_capacity(spans.len());
        let mut samples = Vec::with_capacity(spans.len());
        let mut sweep_frames = Vec::with_capacity(spans.len());
        for &(ci, s, e, foot) in &spans {
            let c = &clips[ci];
            let track = &tracks[ci];
            let (g0, g1) = (track[s], track[e]);
            let duration = (e - s) as f64 * c.frame_time;
            let at = |f: usize| DVec2::new(track[f].x, track[f].y);
            let path: f64 = (s..e).map(|f| at(f).distance(at(f + 1))).sum();
            // Keep a frame when going on to the next would stretch the chord from the last kept
            // point beyond the spacing, or let the path between them stray from that chord by
            // more than [`SWEEP_DEVIATION_M`] (loops of turning on the spot), or turn the heading
            // more than [`SWEEP_TURN_RAD`] (a warped interval turns each piece by its own); and
            // keep the frames where a foot comes to stand flat or leaves it (a warp's bend
            // turns only while none does, `bend_share`).
            let mut sweep = Vec::new();
            let mut last = s;
            for f in s + 1..=e {
                let stray = |to: usize| {
                    let (a, b) = (at(last), at(to));
                    (last + 1..to).any(|k| {
                        let p = at(k);
                        let ab = b - a;
                        let t = if ab.length_squared() > 0.0 {
                            ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
                        } else {
                            0.0
                        };
                        p.distance(a + ab * t) > SWEEP_DEVIATION_M
                    })
                };
                let turned = |to: usize| crate::geom::wrap_angle(track[to].yaw - track[last].yaw).abs();
                let free = |j: usize| no_foot_flat(contacts[ci][j]);
                if f == e
                    || at(f + 1).distance(at(last)) > SWEEP_SPACING_M
                    || turned(f + 1) > SWEEP_TURN_RAD
                    || free(f + 1) != free(f)
                    || stray(f + 1)
                {
                    sweep.push(f);
                    last = f;
                }
            }
            sweep_frames.push(sweep);
            intervals.push(Interval {
                clip: ci,
                start: s,
                end: e,
                duration,
                motion: g0.to_local(g1),
                speed: path / duration,
                foot,
            });
            samples.push(
                (0..=n)
                    .map(|j| {
                        let mut p = c.sample_frame(s as f64 + (e - s) as f64 * j as f64 / n as f64);
                        g0.transform_pose(&mut p, true);
                        p
                    })
                    .collect(),
            );
        }
        let joint_weights = params.weights.joint_weights(&skeleton);
        let mut db = Database {
            skeleton,
            clips,
            intervals,
            kinds: Vec::new(),
            neighbours: Vec::new(),
            successor: Vec::new(),
            candidates: Vec::new(),
            policy_actions: Vec::new(),
            mirror: Vec::new(),
            mirror_candidate: Vec::new(),
            joint_weights,
            feet,
            contact_points: points,
            point_floor: floor,
            epsilon: 0.0,
            params,
            forward_offset: forward,
            samples,
            tracks,
            freedom: contacts.iter().map(|c| turn_freedom(c)).collect(),
            contacts,
            sweep_frames,
            sweep_steps: Vec::new(),
            ends: Vec::new(),
            arcs: Vec::new(),
        };
        db.sweep_steps = (0..db.intervals.len())
            .map(|i| {
                let iv = &db.intervals[i];
                let mut prev = iv.start;
                db.sweep_frames[i]
                    .iter()
                    .map(|&f| {
                        let d = db.tracks[iv.clip][prev].to_local(db.tracks[iv.clip][f]);
                        let share = db.bend_share(i, prev as f64, f as f64);
                        prev = f;
                        (d, share)
                    })
                    .collect()
            })
            .collect();
        db.arcs = db
            .clips
            .iter()
            .map(|c| {
                c.frames
                    .windows(2)
                    .flat_map(|w| w[0].rotations.iter().zip(&w[1].rotations).map(|(&a, &b)| SlerpArc::new(a, b)))
                    .collect()
            })
            .collect();
        db.ends = (0..db.intervals.len()).map(|i| db.feet_at_ends(i)).collect();
        db.mirror = db.find_mirrors();
        // Mirrors share their measured motion exactly (mirrored), so that left and right
        // choices never part on rounding.
        for i in 0..db.intervals.len() {
            if let Some(m) = db.mirror[i]
                && m > i
            {
                let a = db.intervals[i].motion;
                db.intervals[m].speed = db.intervals[i].speed;
                db.intervals[m].motion = Ground { x: a.x, y: -a.y, yaw: -a.yaw };
            }
        }
        let shuffles: Vec<i8> = (0..db.intervals.len()).map(|i| db.shuffle_of(i)).collect();
        db.kinds = shuffles.iter().map(|&shuffle| IntervalKind { shuffle, ..IntervalKind::default() }).collect();
        db.neighbours = db.nearest_neighbours();
        db.symmetrize_neighbours();
        db.successor = (0..db.intervals.len()).map(|i| db.natural_successor(i)).collect();
        for i in 0..db.intervals.len() {
            if let Some(m) = db.mirror[i]
                && i < m
                && let Some(s) = db.mirror[db.successor[i]]
            {
                db.successor[m] = s;
            }
        }
        db.kinds = (0..db.intervals.len()).map(|i| IntervalKind { shuffle: shuffles[i], ..db.kind_of(i) }).collect();
        let mean: f64 = db.neighbours.iter().flatten().map(|&(_, d)| d).sum::<f64>()
            / db.neighbours.iter().map(Vec::len).sum::<usize>().max(1) as f64;
        db.epsilon = (0.5 * mean).max(1e-6);
        (db.candidates, db.policy_actions) = db.build_candidates();
        db.mirror_candidate = (0..db.intervals.len())
            .map(|i| match db.mirror[i] {
                Some(m) => {
                    let want: Vec<Option<usize>> = db.candidates[i]
                        .iter()
                        .map(|c| {
                            db.mirror[c.interval].and_then(|mc| db.candidates[m].iter().position(|x| x.interval == mc))
                        })
                        .collect();
                    if want.iter().all(Option::is_some) { want.into_iter().flatten().collect() } else { Vec::new() }
                }
                None => Vec::new(),
            })
            .collect();
        Ok(db)
    }

    /// The feet at the first and last frame of interval `i`, each in its own ground frame.
    fn feet_at_ends(&self, i: usize) -> [FeetAt; 2] {
        let iv = &self.intervals[i];
        let mut g = Vec::new();
        [iv.start, iv.end].map(|f| {
            let p = self.relative_pose(iv.clip, f as f64);
            self.skeleton.globals(&p, &mut g);
            FeetAt { bits: self.contacts[iv.clip][f], points: point_positions(&g, self.feet, &self.contact_points) }
        })
    }

    /// The feet at the start (`end` false) or the end of interval `i`, in the ground frame of
    /// that frame.
    pub fn feet_at(&self, i: usize, end: bool) -> &FeetAt {
        &self.ends[i][usize::from(end)]
    }

    /// Whether the root is at rest by the end of interval `j`.
    fn rests(&self, j: usize) -> bool {
        let iv = &self.intervals[j];
        let ft = self.clips[iv.clip].frame_time;
        let back = ((REST_WINDOW_S / ft).round() as usize).clamp(1, iv.end - iv.start);
        let (a, b) = (self.tracks[iv.clip][iv.end - back], self.tracks[iv.clip][iv.end]);
        (b.x - a.x).hypot(b.y - a.y) / (back as f64 * ft) < REST_SPEED_MPS
    }

    /// Whether interval `i` is part of a side step or a step back ([`IntervalKind::shuffle`]):
    /// along its clip it comes to rest within [`SHUFFLE_REACH`] intervals, having moved at least
    /// [`IN_PLACE_M`] at least [`SHUFFLE_RAD`] away from its start heading (twice that: back)
    /// and turned less than [`SPOT_TURN_RAD`].
    pub fn shuffle_of(&self, i: usize) -> i8 {
        let iv = &self.intervals[i];
        let mut last = i;
        while !self.rests(last) {
            let next = last + 1;
            let joined =
                self.intervals.get(next).is_some_and(|n| n.clip == iv.clip && n.start == self.intervals[last].end);
            if !joined || next - i >= SHUFFLE_REACH {
                return 0;
            }
            last = next;
        }
        let track = &self.tracks[iv.clip];
        let d = track[iv.start].to_local(track[self.intervals[last].end]);
        let heading = d.y.atan2(d.x).abs();
        if d.x.hypot(d.y) < IN_PLACE_M || d.yaw.abs() >= SPOT_TURN_RAD || heading < SHUFFLE_RAD {
            0
        } else if heading > 2.0 * SHUFFLE_RAD {
            2
        } else {
            d.y.signum() as i8
        }
    }

    /// The kind of interval `i`; needs the successors.
    fn kind_of(&self, i: usize) -> IntervalKind {
        let rest = |j: usize| self.rests(j);
        let iv = &self.intervals[i];
        let track = &self.tracks[iv.clip];
        let g0 = track[iv.start];
        let far = (iv.start..=iv.end).map(|f| (track[f].x - g0.x).hypot(track[f].y - g0.y)).fold(0.0, f64::max);
        let in_place = far < IN_PLACE_M;
        let spot_turn = if in_place && iv.turn().abs() >= SPOT_TURN_RAD { iv.turn().signum() as i8 } else { 0 };
        let sharp_turn = if !in_place && iv.turn().abs() >= SHARP_TURN_RAD { iv.turn().signum() as i8 } else { 0 };
        let ends_at_rest = rest(i);
        let moving = |j: usize| {
            let jv = &self.intervals[j];
            let t = &self.tracks[jv.clip];
            (t[jv.end].x - t[jv.start].x).hypot(t[jv.end].y - t[jv.start].y) >= IN_PLACE_M
        };
        IntervalKind {
            ends_at_rest,
            in_place,
            spot_turn,
            stops: ends_at_rest || rest(self.successor[i]),
            goes: moving(i),
            sharp_turn,
            shuffle: 0,
        }
    }

    /// The mirror of every interval: the interval whose samples equal its mirrored samples within
    /// [`MIRROR_TOLERANCE`] — itself if it is symmetric, else preferably an exact mirror image,
    /// the one at the same place in the clip's mirror clip — kept only where the pairing is
    /// mutual.
    fn find_mirrors(&self) -> Vec<Option<usize>> {
        let pairs = super::clip::mirror_pairs(&self.skeleton);
        let (w, wr) = (&self.joint_weights, self.params.weights.root_position);
        let n = self.intervals.len();
        let position = |i: usize| {
            let iv = &self.intervals[i];
            self.intervals[..i].iter().filter(|x| x.clip == iv.clip).count()
        };
        // Mirror clips: the same length, and the mirror image of one's frames (relative to its
        // first frame's ground) is the other's, at the start, the middle and the end.
        let relative = |c: usize, f: usize| {
            let mut p = self.clips[c].frames[f].clone();
            Ground::of(&self.clips[c].frames[0], self.forward_offset).transform_pose(&mut p, true);
            p
        };
        let mirror_clip: Vec<Option<usize>> = (0..self.clips.len())
            .map(|c| {
                let n = self.clips[c].frames.len();
                (0..self.clips.len()).find(|&d| {
                    d != c
                        && self.clips[d].frames.len() == n
                        && [0, n / 2, n - 1].iter().all(|&f| {
                            self.pose_distance(&relative(c, f).mirrored(&pairs), &relative(d, f)) < EXACT_MIRROR
                        })
                })
            })
            .collect();
        let found: Vec<Option<usize>> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mirrored: Vec<Pose> = self.samples[i].iter().map(|p| p.mirrored(&pairs)).collect();
                let iv = &self.intervals[i];
                let mut matches: Vec<(usize, f64)> = (0..n)
                    .map(|j| (j, interval_distance(w, wr, &mirrored, &self.samples[j], MIRROR_TOLERANCE)))
                    .filter(|&(_, d)| d < MIRROR_TOLERANCE)
                    .collect();
                // Itself first, then exact mirrors (a clip and its mirror image) before near
                // copies, then the interval at the same place in a clip of the same length.
                let rank = |&(j, d): &(usize, f64)| {
                    let jv = &self.intervals[j];
                    let twin = mirror_clip[iv.clip] == Some(jv.clip) && position(j) == position(i);
                    (j != i, d > EXACT_MIRROR, !twin, j)
                };
                matches.sort_by_key(rank);
                matches.first().map(|m| m.0)
            })
            .collect();
        (0..n).map(|i| found[i].filter(|&j| found[j] == Some(i))).collect()
    }

    /// Makes the neighbour lists mirror-symmetric: the neighbours of an interval's mirror are
    /// the mirrors of its neighbours (computed for the lower index of each pair), and a symmetric
    /// interval's list holds the mirror of each of its neighbours.
    fn symmetrize_neighbours(&mut self) {
        let n = self.intervals.len();
        for i in 0..n {
            match self.mirror[i] {
                Some(m) if m > i => {
                    let mapped: Option<Vec<(usize, f64)>> =
                        self.neighbours[i].iter().map(|&(j, d)| self.mirror[j].map(|mj| (mj, d))).collect();
                    if let Some(list) = mapped {
                        self.neighbours[m] = list;
                    }
                }
                Some(m) if m == i => {
                    let mut list = self.neighbours[i].clone();
                    for &(j, d) in &self.neighbours[i] {
                        if let Some(mj) = self.mirror[j]
                            && mj != i
                            && !list.iter().any(|&(x, _)| x == mj)
                        {
                            list.push((mj, d));
                        }
                    }
                    list.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
                    self.neighbours[i] = list;
                }
                _ => {}
            }
        }
    }

    /// The candidates after every interval: its successor, the successor's neighbours, and —
    /// where none of those stops, turns on the spot to one side, gets going, or (after a moving
    /// interval) turns sharply to one side while moving — the interval nearest to the successor
    /// (Eq. 2) that does, with the mirror of anything added to a symmetric interval; after an
    /// interval that ends at rest, the nearest side step to each side and step back come last.
    /// Mirror pairs get mirrored lists in the same order. Also returns how many of each list
    /// the policy ranks (all but those side steps and steps back).
    fn build_candidates(&self) -> (Vec<Vec<Candidate>>, Vec<usize>) {
        let n = self.intervals.len();
        let nearest_where = |s: usize, want: &dyn Fn(&IntervalKind) -> bool| -> Option<(usize, f64)> {
            let mut best: Option<(usize, f64)> = None;
            for j in (0..n).filter(|&j| want(&self.kinds[j])) {
                let d = self.interval_distance(s, j);
                if best.is_none_or(|b| d < b.1) {
                    best = Some((j, d));
                }
            }
            best
        };
        let list = |i: usize| -> (Vec<(usize, f64)>, usize) {
            let s = self.successor[i];
            let mut c = vec![(s, 0.0)];
            c.extend(self.neighbours[s].iter().copied());
            let wants: [&dyn Fn(&IntervalKind) -> bool; 9] = [
                &|k| k.shuffle == 0 && (k.stops || k.in_place),
                &|k| k.shuffle == 0 && k.spot_turn > 0,
                &|k| k.shuffle == 0 && k.spot_turn < 0,
                &|k| k.shuffle == 0 && k.goes,
                &|k| k.sharp_turn > 0,
                &|k| k.sharp_turn < 0,
                &|k| k.shuffle == 1,
                &|k| k.shuffle == -1,
                &|k| k.shuffle == 2,
            ];
            let moving = self.kinds[i].goes;
            let resting = self.kinds[i].ends_at_rest;
            let mut ranked = 0;
            for (w, want) in wants.into_iter().enumerate() {
                if (w == 4 || w == 5) && !moving || w >= 6 && !resting {
                    continue;
                }
                if w == 6 {
                    ranked = c.len();
                }
                if !c.iter().any(|&(j, _)| want(&self.kinds[j]))
                    && let Some((j, d)) = nearest_where(s, want)
                {
                    c.push((j, d));
                    if self.mirror[i] == Some(i)
                        && let Some(mj) = self.mirror[j]
                        && !c.iter().any(|&(x, _)| x == mj)
                    {
                        c.push((mj, d));
                    }
                }
            }
            if !resting {
                ranked = c.len();
            }
            (c, ranked)
        };
        let mut lists: Vec<Option<RankedList>> = vec![None; n];
        for i in 0..n {
            if lists[i].is_some() {
                continue;
            }
            let (l, ranked) = list(i);
            if let Some(m) = self.mirror[i]
                && m != i
            {
                let mapped: Option<Vec<(usize, f64)>> =
                    l.iter().map(|&(j, d)| self.mirror[j].map(|x| (x, d))).collect();
                if let Some(ml) = mapped {
                    lists[m] = Some((ml, ranked));
                }
            }
            lists[i] = Some((l, ranked));
        }
        let ranked: Vec<usize> = lists.iter().map(|l| l.as_ref().map_or(0, |l| l.1)).collect();
        let lists = lists
            .into_iter()
            .enumerate()
            .map(|(i, l)| {
                let c = l.map(|l| l.0).unwrap_or_default();
                let iv = &self.intervals[i];
                let end = self.relative_pose(iv.clip, iv.end as f64);
                // The policy's actions share the weight of Eq. 3.
                let total: f64 = c[..ranked[i]].iter().map(|&(_, d)| 1.0 / (d + self.epsilon)).sum();
                c.into_iter()
                    .map(|(j, d)| {
                        let jv = &self.intervals[j];
                        let seamless = (jv.clip == iv.clip && jv.start == iv.end)
                            || self.pose_distance(&end, &self.samples[j][0]) < SEAMLESS;
                        Candidate { interval: j, weight: 1.0 / (d + self.epsilon) / total, distance: d, seamless }
                    })
                    .collect()
            })
            .collect();
        (lists, ranked)
    }

    /// Pose distance, Eq. 1: `w_root·|r − r'|² + Σ_i w_i·θ(q_i, q'_i)²`.
    pub fn pose_distance(&self, a: &Pose, b: &Pose) -> f64 {
        pose_distance(&self.joint_weights, self.params.weights.root_position, a, b, f64::INFINITY)
    }

    /// Interval distance, Eq. 2: the mean of Eq. 1 over `n + 1` normalized times, both
    /// intervals in their own frames.
    pub fn interval_distance(&self, a: usize, b: usize) -> f64 {
        interval_distance(
            &self.joint_weights,
            self.params.weights.root_position,
            &self.samples[a],
            &self.samples[b],
            f64::INFINITY,
        )
    }

    /// The `n + 1` samples of interval `i` in its own frame.
    pub fn samples(&self, i: usize) -> &[Pose] {
        &self.samples[i]
    }

    fn nearest_neighbours(&self) -> Vec<Vec<(usize, f64)>> {
        let k = self.params.k;
        let per_clip = self.params.max_per_clip.max(1);
        let (w, wr) = (&self.joint_weights, self.params.weights.root_position);
        (0..self.intervals.len())
            .into_par_iter()
            .map(|i| {
                let mut best = self.k_best(i, k, per_clip, w, wr);
                if best.len() < k {
                    // Too few clips for the per-clip limit: fill with the nearest of the rest.
                    for (j, d) in self.k_best(i, k, usize::MAX, w, wr) {
                        if best.len() < k && !best.iter().any(|&(b, _)| b == j) {
                            best.push((j, d));
                        }
                    }
                    best.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
                }
                best
            })
            .collect()
    }

    /// The `k` intervals nearest to `i` (Eq. 2), at most `per_clip` from any one clip, nearest
    /// first (ties by index). Candidates are abandoned as soon as they cannot enter the list.
    fn k_best(&self, i: usize, k: usize, per_clip: usize, w: &[f64], wr: f64) -> Vec<(usize, f64)> {
        let mut best: Vec<(usize, f64)> = Vec::with_capacity(k + 1);
        for j in 0..self.intervals.len() {
            if j == i || self.kinds[j].shuffle != 0 {
                continue;
            }
            let bound = if best.len() == k { best[k - 1].1 } else { f64::INFINITY };
            let clip = self.intervals[j].clip;
            let same: Vec<usize> = (0..best.len()).filter(|&b| self.intervals[best[b].0].clip == clip).collect();
            // A clip at its limit only lets in something nearer than its farthest entry.
            let bound =
                if same.len() >= per_clip { bound.min(best[*same.last().expect("limit ≥ 1")].1) } else { bound };
            let d = interval_distance(w, wr, &self.samples[i], &self.samples[j], bound);
            if d < bound {
                if same.len() >= per_clip {
                    best.remove(*same.last().expect("limit ≥ 1"));
                }
                let at = best.partition_point(|&(_, e)| e <= d);
                best.insert(at, (j, d));
                best.truncate(k);
            }
        }
        best
    }

    fn natural_successor(&self, i: usize) -> usize {
        let iv = &self.intervals[i];
        if self.intervals.get(i + 1).is_some_and(|n| n.clip == iv.clip && n.start == iv.end) {
            return i + 1;
        }
        // The clip ends here: continue with the interval whose start pose is nearest to this
        // end pose (both relative to their ground reference).
        let end = self.relative_pose(iv.clip, iv.end as f64);
        let mut best = (usize::MAX, f64::INFINITY);
        for j in 0..self.intervals.len() {
            if j == i || self.kinds[j].shuffle != 0 {
                continue;
            }
            // The first sample of an interval is its start pose in its own frame.
            let d = self.pose_distance(&end, &self.samples[j][0]);
            if d < best.1 {
                best = (j, d);
            }
        }
        best.0
    }

    /// The pose of clip `clip` at fractional frame `f`, relative to its own ground reference
    /// (root above the origin, facing +X).
    pub fn relative_pose(&self, clip: usize, f: f64) -> Pose {
        let mut p = Pose { root: DVec3::ZERO, rotations: Vec::with_capacity(self.skeleton.len()) };
        self.relative_pose_into(clip, f, &mut p);
        p
    }

    /// [`relative_pose`](Self::relative_pose) into `out`, without allocating once `out` has
    /// room: the clip sampled as [`Clip::sample_frame`] samples it, through the kept arcs.
    pub fn relative_pose_into(&self, clip: usize, f: f64, out: &mut Pose) {
        let c = &self.clips[clip];
        let last = c.frames.len() - 1;
        let x = (f * c.frame_time / c.frame_time).clamp(0.0, last as f64);
        let i = (x.floor() as usize).min(last);
        let t = x - i as f64;
        if i == last {
            out.blend_from(&c.frames[i], &c.frames[i], t);
        } else {
            let (a, b) = (&c.frames[i], &c.frames[i + 1]);
            let joints = a.rotations.len();
            out.root = a.root.lerp(b.root, t);
            out.rotations.clear();
            out.rotations.extend(self.arcs[clip][i * joints..(i + 1) * joints].iter().map(|arc| arc.at(t)));
        }
        Ground::of(out, self.forward_offset).transform_pose(out, true);
    }

    /// The ground reference of clip `clip` at fractional frame `f` (clamped to the clip),
    /// interpolated between the two frames around it.
    pub fn ground(&self, clip: usize, f: f64) -> Ground {
        let track = &self.tracks[clip];
        let last = track.len() - 1;
        let f = if f.is_finite() { f.clamp(0.0, last as f64) } else { 0.0 };
        let i = (f.floor() as usize).min(last);
        let (a, b) = (track[i], track[(i + 1).min(last)]);
        let t = f - i as f64;
        if t == 0.0 {
            return a;
        }
        Ground { x: a.x + (b.x - a.x) * t, y: a.y + (b.y - a.y) * t, yaw: a.yaw + wrap_angle(b.yaw - a.yaw) * t }
    }

    /// The contact bits ([`contact_bit`]) of clip `clip` at fractional frame `f` (nearest frame).
    pub fn contacts(&self, clip: usize, f: f64) -> u8 {
        let c = &self.contacts[clip];
        let i = if f.is_finite() { (f.round().max(0.0) as usize).min(c.len() - 1) } else { 0 };
        c[i]
    }

    /// The share of interval `i`'s turning freedom between its clip frames `a` and `b` (within
    /// it): how much of a bend added to the interval turns there. A bend turns the body while
    /// no foot stands flat (on its heel, on its toe, or in the air), as the clips themselves
    /// turn, so planted feet pivot on a point instead of sliding; an interval with no such
    /// frame spreads it over its time.
    pub fn bend_share(&self, i: usize, a: f64, b: f64) -> f64 {
        let iv = &self.intervals[i];
        let c = &self.freedom[iv.clip];
        let at = |f: f64| {
            let f = f.clamp(iv.start as f64, iv.end as f64);
            let j = (f as usize).min(c.len() - 1);
            let t = f - j as f64;
            c[j] + (c[(j + 1).min(c.len() - 1)] - c[j]) * t
        };
        let total = c[iv.end] - c[iv.start];
        if total >= 1.0 {
            (at(b) - at(a)) / total
        } else {
            (b.clamp(iv.start as f64, iv.end as f64) - a.clamp(iv.start as f64, iv.end as f64))
                / (iv.end - iv.start).max(1) as f64
        }
    }

    /// Clip frames of interval `i` after its start whose root positions are at most
    /// [`SWEEP_SPACING_M`] apart, with the path between two of them within
    /// [`SWEEP_DEVIATION_M`] of the segment joining them, ending with its last frame: the points
    /// a clearance check of its root path visits.
    pub fn sweep_frames(&self, i: usize) -> &[usize] {
        &self.sweep_frames[i]
    }

    /// For each of [`Self::sweep_frames`]`(i)`: the root's motion from the kept frame before
    /// (the interval's start for the first), in that frame's ground frame, and the share of a
    /// warp's bend turned over it ([`Self::bend_share`]).
    pub fn sweep_steps(&self, i: usize) -> &[(Ground, f64)] {
        &self.sweep_steps[i]
    }

    /// A fingerprint of the structure (clip names and lengths, intervals, candidates) that a
    /// trained policy depends on; FNV-1a 64.
    pub fn fingerprint(&self) -> u64 {
        let mut h = Fnv::default();
        for c in &self.clips {
            h.bytes(c.name.as_bytes());
            h.u64(c.frames.len() as u64);
        }
        for (i, iv) in self.intervals.iter().enumerate() {
            h.u64(iv.clip as u64);
            h.u64(iv.start as u64);
            h.u64(iv.end as u64);
            for c in &self.candidates[i] {
                h.u64(c.interval as u64);
            }
        }
        h.0
    }

    /// Largest mean interval speed, metres per second.
    pub fn max_speed(&self) -> f64 {
        self.intervals.iter().map(|i| i.speed).fold(0.0, f64::max)
    }
}

/// No foot stands flat (heel and toe both on the ground) by the contact bits `bits`.
fn no_foot_flat(bits: u8) -> bool {
    !(0..2).any(|f| bits & contact_bit(f, 0) != 0 && bits & contact_bit(f, 1) != 0)
}

/// The running count of frames in which no foot stands flat (heel and toe both on the ground),
/// from a clip's contact bits: `out[j]` counts the frame pairs before frame `j`, a pair counting
/// by the share of its two frames that are free.
fn turn_freedom(contacts: &[u8]) -> Vec<f64> {
    let free = |bits: u8| if no_foot_flat(bits) { 1.0 } else { 0.0 };
    let mut out = Vec::with_capacity(contacts.len());
    let mut sum = 0.0;
    out.push(0.0);
    for w in contacts.windows(2) {
        sum += 0.5 * (free(w[0]) + free(w[1]));
        out.push(sum);
    }
    out
}

/// FNV-1a, 64 bits.
#[derive(Debug, Clone, Copy)]
pub struct Fnv(pub u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    /// Hashes bytes.
    pub fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= u64::from(x);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }

    /// Hashes a number (little endian).
    pub fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }
}

/// Eq. 1, stopping early once the sum exceeds `bound`.
fn pose_distance(weights: &[f64], w_root: f64, a: &Pose, b: &Pose, bound: f64) -> f64 {
    let mut d = w_root * a.root.distance_squared(b.root);
    for ((&w, &qa), &qb) in weights.iter().zip(&a.rotations).zip(&b.rotations) {
        if w > 0.0 {
            let t = angle_between(qa, qb);
            d += w * t * t;
            if d > bound {
                return d;
            }
        }
    }
    d
}

/// Eq. 2, stopping early (returning a value ≥ `bound`) once the mean must exceed `bound`. A
/// cheap lower bound comes first — `θ² ≥ 8·(1 − |⟨q, q'⟩|)`, no arc cosines — so most far-apart
/// pairs are dismissed before the exact sum.
fn interval_distance(weights: &[f64], w_root: f64, a: &[Pose], b: &[Pose], bound: f64) -> f64 {
    let m = a.len().min(b.len()) as f64;
    let total_bound = bound * m;
    if bound.is_finite() {
        let mut lower = 0.0;
        for (pa, pb) in a.iter().zip(b) {
            lower += w_root * pa.root.distance_squared(pb.root);
            for ((&w, &qa), &qb) in weights.iter().zip(&pa.rotations).zip(&pb.rotations) {
                lower += w * 8.0 * (1.0 - qa.dot(qb).abs()).max(0.0);
            }
            if lower > total_bound {
                return f64::INFINITY;
            }
        }
    }
    let mut sum = 0.0;
    for (pa, pb) in a.iter().zip(b) {
        sum += pose_distance(weights, w_root, pa, pb, total_bound - sum);
        if sum > total_bound {
            return f64::INFINITY;
        }
    }
    sum / m
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::anim::skeleton::Joint;
    use glam::DQuat;

    fn skeleton() -> Skeleton {
        let j = |n: &str, p: Option<usize>, o: DVec3| Joint {
            name: n.into(),
            parent: p,
            offset: o,
            channels: vec![crate::anim::Channel::YRotation],
            end_site: None,
        };
        Skeleton::new(vec![
            j("Hips", None, DVec3::new(0.0, 0.0, 0.9)),
            j("LeftUpLeg", Some(0), DVec3::new(0.0, 0.1, 0.0)),
            j("LeftFoot", Some(1), DVec3::new(0.0, 0.0, -0.85)),
            j("RightUpLeg", Some(0), DVec3::new(0.0, -0.1, 0.0)),
            j("RightFoot", Some(3), DVec3::new(0.0, 0.0, -0.85)),
        ])
        .unwrap()
    }

    /// A clip whose root moves forward at `speed` while turning at `turn` rad/s, with the legs
    /// swinging at `phase`; both feet stay near the ground, so intervals are given by hand.
    fn clip(name: &str, speed: f64, turn: f64, phase: f64) -> Clip {
        let s = skeleton();
        let frames = (0..61)
            .map(|i| {
                let t = i as f64 / 60.0;
                let mut p = s.bind_pose();
                let yaw = turn * t;
                let d = if turn.abs() < 1e-9 {
                    DVec3::new(speed * t, 0.0, 0.0)
                } else {
                    let r = speed / turn;
                    DVec3::new(r * yaw.sin(), r * (1.0 - yaw.cos()), 0.0)
                };
                p.root += d;
                p.rotations[0] = DQuat::from_rotation_z(yaw);
                let swing = 0.4 * (std::f64::consts::TAU * t + phase).sin();
                p.rotations[1] = DQuat::from_rotation_y(swing);
                p.rotations[3] = DQuat::from_rotation_y(-swing);
                p
            })
            .collect();
        Clip { name: name.into(), frame_time: 1.0 / 60.0, frames }
    }

    pub(crate) fn database() -> Database {
        let clips: Vec<Clip> = (0..8)
            .map(|k| clip(&format!("c{k}"), 0.5 + 0.2 * k as f64, 0.1 * (k as f64 - 4.0), 0.3 * k as f64))
            .collect();
        let manual: Vec<IntervalSpec> = clips
            .iter()
            .flat_map(|c| {
                [(0, 20), (20, 40), (40, 60)].map(|(s, e)| IntervalSpec { clip: c.name.clone(), start: s, end: e })
            })
            .collect();
        Database::build(clips, skeleton(), DbParams { k: 4, ..DbParams::default() }, Some(&manual)).unwrap()
    }

    /// The intervals of `db` as a hand-written list.
    pub(crate) fn manual(db: &Database) -> Vec<IntervalSpec> {
        db.intervals
            .iter()
            .map(|i| IntervalSpec { clip: db.clips[i.clip].name.clone(), start: i.start, end: i.end })
            .collect()
    }

    #[test]
    fn k_zero_or_too_large_is_an_error() {
        let db = database();
        let specs = manual(&db);
        for k in [0, MAX_K + 1] {
            let params = DbParams { k, ..DbParams::default() };
            let err = Database::build(db.clips.clone(), db.skeleton.clone(), params, Some(&specs)).unwrap_err();
            assert!(matches!(err, DbError::Params(_)), "{err}");
        }
    }

    #[test]
    fn interval_distance_is_a_symmetric_premetric() {
        let db = database();
        for a in 0..db.intervals.len() {
            assert!(db.interval_distance(a, a) < 1e-12);
            for b in 0..db.intervals.len() {
                let (x, y) = (db.interval_distance(a, b), db.interval_distance(b, a));
                assert!(x >= 0.0 && (x - y).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn eq1_by_hand() {
        let db = database();
        let s = &db.skeleton;
        let a = s.bind_pose();
        let mut b = s.bind_pose();
        b.root.x += 0.5;
        b.rotations[1] = DQuat::from_rotation_y(0.3);
        let w = &db.joint_weights;
        let expect = 4.0 * 0.25 + w[1] * 0.09;
        assert!((db.pose_distance(&a, &b) - expect).abs() < 1e-12);
        // Deeper joints and shorter bones weigh less.
        assert!(w[0] > w[1] && w[1] > w[2]);
    }

    #[test]
    fn neighbours_match_brute_force_and_weights_follow_eq3() {
        let db = database();
        let n = db.intervals.len();
        for i in 0..n {
            let mut all: Vec<(usize, f64)> =
                (0..n).filter(|&j| j != i).map(|j| (j, db.interval_distance(i, j))).collect();
            all.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            // At most one per clip: the nearest of each clip, nearest first.
            let mut want: Vec<usize> = Vec::new();
            for &(j, _) in &all {
                if want.len() < 4 && !want.iter().any(|&w| db.intervals[w].clip == db.intervals[j].clip) {
                    want.push(j);
                }
            }
            let got: Vec<usize> = db.neighbours[i].iter().map(|x| x.0).collect();
            assert_eq!(got, want, "interval {i}");
            let c = &db.candidates[i];
            assert_eq!(c.len(), 5);
            assert_eq!(c[0].interval, db.successor[i]);
            let sum: f64 = c.iter().map(|c| c.weight).sum();
            assert!((sum - 1.0).abs() < 1e-12);
            let inv: f64 = c.iter().map(|c| 1.0 / (c.distance + db.epsilon)).sum();
            for x in c {
                assert!((x.weight - 1.0 / (x.distance + db.epsilon) / inv).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn successors_follow_clips_and_motion_is_measured() {
        let db = database();
        assert_eq!(db.successor[0], 1);
        assert_eq!(db.successor[1], 2);
        // The last interval of a clip continues somewhere else than itself.
        assert_ne!(db.successor[2], 2);
        let iv = &db.intervals[4 * 3 + 1];
        assert!((iv.speed - 1.3).abs() < 1e-3, "{}", iv.speed);
        assert!(iv.turn().abs() < 1e-9);
        let turning = &db.intervals[0];
        assert!((turning.turn() - (-0.4 / 3.0)).abs() < 1e-9);
    }

    #[test]
    fn plants_cut_intervals() {
        let c = |s: &str| s.chars().map(|c| c == '#').collect::<Vec<bool>>();
        let l = c("####......########......####");
        let r = c("#######......######.....####");
        let b = plant_boundaries(&[l, r], 2, 100);
        let frames: Vec<usize> = b.iter().map(|x| x.0).collect();
        // Both feet down at the start, left touches at 10, right at 13, both at 24, end at 27.
        assert_eq!(frames, vec![0, 10, 13, 24, 27]);
        assert_eq!(b.iter().map(|x| x.1).collect::<Vec<_>>(), vec![2, 0, 1, 2, 2]);
        // Touchdowns closer than the minimum merge into the earlier one; the clip's end replaces
        // a boundary too close to it.
        let b = plant_boundaries(&[c("####......########......####"), c("#######......######.....####")], 4, 100);
        assert_eq!(b.iter().map(|x| x.0).collect::<Vec<_>>(), vec![0, 10, 27]);
        // Long stretches are split.
        let all = vec![true; 31];
        let b = plant_boundaries(&[all.clone(), all], 2, 10);
        assert_eq!(b.iter().map(|x| x.0).collect::<Vec<_>>(), vec![0, 10, 20, 30]);
    }

    #[test]
    fn bad_databases_are_errors() {
        let clips = vec![clip("a", 1.0, 0.0, 0.0)];
        let one = [IntervalSpec { clip: "a".into(), start: 0, end: 30 }];
        assert!(matches!(
            Database::build(clips.clone(), skeleton(), DbParams::default(), Some(&one)),
            Err(DbError::TooFewIntervals(1, 7))
        ));
        let bad = [IntervalSpec { clip: "a".into(), start: 0, end: 99 }];
        assert!(matches!(
            Database::build(clips.clone(), skeleton(), DbParams::default(), Some(&bad)),
            Err(DbError::BadInterval(..))
        ));
        let unknown = [IntervalSpec { clip: "b".into(), start: 0, end: 9 }];
        assert!(matches!(
            Database::build(clips, skeleton(), DbParams::default(), Some(&unknown)),
            Err(DbError::UnknownClip(..))
        ));
        assert!(matches!(Database::build(vec![], skeleton(), DbParams::default(), None), Err(DbError::NoClips)));
    }
}
