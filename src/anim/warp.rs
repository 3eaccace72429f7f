//! Animation warping (beyond seed 000 §3.2, as game engines warp root motion): an interval
//! plays with its root motion changed so that it ends where the controller wants it to, not
//! only where some clip happens to go.
//!
//! - *Turn warping*: the interval's own root yaw is scaled ([`WarpLimits::turn_scale`], wider
//!   for turns on the spot) and a bend is added ([`WarpLimits::bend_rad`] at most), so that the
//!   interval ends at the heading asked for. The bend turns while no foot stands flat, as the
//!   clips themselves turn ([`super::db::Database::bend_share`]), so a planted foot pivots on
//!   its heel or toe rather than sliding (the built-in actor's hips cannot twist).
//! - *Stride warping*: the root's horizontal travel is scaled ([`WarpLimits::stride`]), so the
//!   speed asked for is met within one step.
//!
//! The warp changes only the root; planted feet stay where they touched down (the player's foot
//! locking and two-bone leg IK, see [`super::player`]), so a longer stride stretches the stance
//! and a bent step pivots the planted foot on its heel or ball. A warp is chosen per candidate at a
//! switch point by [`Warp::toward`], a pure function of the candidate and the errors, so the
//! look-ahead sweeps exactly the path playback will take and the policy's model
//! ([`super::policy::transition`]) sees the same motion.
//!
//! A warped increment keeps the arc's length: the interval's increment `(dx, dy, dψ)`, over
//! which a share `u` of the bend `b` turns, becomes `(k·R(φ)(dx, dy), ψ')` with
//! `ψ' = s·dψ + b·u`, the chord turned by `φ = (ψ' − dψ) / 2` and lengthened by
//! `k = stride · sinc(ψ'/2) / sinc(dψ/2)`, which is exact for arcs of constant curvature
//! whatever the increment's length, so coarse look-ahead segments and single frames give the
//! same path.

use super::clip::Ground;
use super::db::{Interval, IntervalKind};
use crate::geom::wrap_angle;

/// How far warping may change an interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WarpLimits {
    /// Range of the factor on a moving interval's own yaw (0.5–1.5).
    pub turn_scale: (f64, f64),
    /// Range of the factor on a turn on the spot's yaw (1/3–1.5: a 45° turn covers 15°–67.5°).
    pub spot_scale: (f64, f64),
    /// Largest yaw added to a moving interval, radians (8°, about one step).
    pub bend_rad: f64,
    /// Range of the factor on a moving interval's travel (0.75–1.25).
    pub stride: (f64, f64),
    /// Slowest interval whose stride is warped, m/s (0.15: slower ones are standing or
    /// shuffling, where a longer stride has no meaning).
    pub min_speed_mps: f64,
}

impl Default for WarpLimits {
    fn default() -> Self {
        WarpLimits {
            turn_scale: (0.5, 1.5),
            spot_scale: (1.0 / 3.0, 1.5),
            bend_rad: 8f64.to_radians(),
            stride: (0.75, 1.25),
            min_speed_mps: 0.15,
        }
    }
}

impl WarpLimits {
    /// No warping at all: every interval plays as recorded.
    pub const NONE: WarpLimits = WarpLimits {
        turn_scale: (1.0, 1.0),
        spot_scale: (1.0, 1.0),
        bend_rad: 0.0,
        stride: (1.0, 1.0),
        min_speed_mps: 0.0,
    };

    /// Finite, each range ordered within (0, 4], the bend within [0, π/2].
    pub fn valid(&self) -> bool {
        let range = |(lo, hi): (f64, f64)| lo > 0.0 && lo <= hi && hi <= 4.0;
        range(self.turn_scale)
            && range(self.spot_scale)
            && range(self.stride)
            && (0.0..=std::f64::consts::FRAC_PI_2).contains(&self.bend_rad)
            && (0.0..=10.0).contains(&self.min_speed_mps)
    }
}

/// The warp one interval plays with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Warp {
    /// Factor on the interval's own root yaw (1: as recorded).
    pub turn_scale: f64,
    /// Yaw added over the whole interval, radians, turned while no foot stands flat
    /// ([`super::db::Database::bend_share`]).
    pub bend: f64,
    /// Factor on the root's horizontal travel (1: as recorded).
    pub stride: f64,
}

impl Default for Warp {
    fn default() -> Self {
        Warp::NONE
    }
}

impl Warp {
    /// The interval as recorded.
    pub const NONE: Warp = Warp { turn_scale: 1.0, bend: 0.0, stride: 1.0 };

    /// The warp that brings interval `iv` (of kind `kind`) closest to turning by `direction`
    /// radians (the desired heading less the heading where it starts) and moving at `speed` m/s,
    /// within `limits`: its own yaw scaled as little as needed, then bent by what is left, and
    /// its travel scaled toward the speed. Standing intervals are not warped; a turn on the spot
    /// is scaled only.
    pub fn toward(iv: &Interval, kind: IntervalKind, direction: f64, speed: f64, limits: &WarpLimits) -> Warp {
        let direction = if direction.is_finite() { wrap_angle(direction) } else { 0.0 };
        let (want, turn) = (direction, iv.turn());
        // Side steps and steps back play as recorded: both feet carry the body sideways or
        // back, and a scaled or bent root would drag the planted one.
        if kind.shuffle != 0 {
            return Warp::NONE;
        }
        if kind.in_place {
            if kind.spot_turn == 0 || turn.abs() < 1e-6 {
                return Warp::NONE;
            }
            let (lo, hi) = limits.spot_scale;
            let s = if want * turn > 0.0 { (want / turn).clamp(lo, hi) } else { lo };
            return Warp { turn_scale: s, ..Warp::NONE };
        }
        let (lo, hi) = limits.turn_scale;
        // Intervals that turn less than the bend can add keep their own yaw.
        let s = if turn.abs() > limits.bend_rad {
            if want * turn > 0.0 { (want / turn).clamp(lo, hi) } else { lo }
        } else {
            1.0
        };
        let bend = (want - s * turn).clamp(-limits.bend_rad, limits.bend_rad);
        let stride = if iv.speed >= limits.min_speed_mps && speed.is_finite() {
            (speed.max(0.0) / iv.speed).clamp(limits.stride.0, limits.stride.1)
        } else {
            1.0
        };
        Warp { turn_scale: s, bend, stride }
    }

    /// The heading change of interval `iv` played with this warp, radians.
    pub fn turn(&self, iv: &Interval) -> f64 {
        iv.turn() * self.turn_scale + self.bend
    }

    /// The mean speed of interval `iv` played with this warp, m/s.
    pub fn speed(&self, iv: &Interval) -> f64 {
        iv.speed * self.stride
    }

    /// A root increment `d` (in the frame where it starts) over which `share` of the bend turns,
    /// warped (as the module documentation says).
    pub fn apply(&self, d: Ground, share: f64) -> Ground {
        if self.turn_scale == 1.0 && self.bend == 0.0 {
            return Ground { x: self.stride * d.x, y: self.stride * d.y, yaw: d.yaw };
        }
        let yaw = d.yaw * self.turn_scale + self.bend * share;
        // The chord turns by half the change of yaw and keeps the arc's length.
        let (s, c) = small_sin_cos(0.5 * (yaw - d.yaw));
        let k = self.stride * sinc(0.5 * yaw) / sinc(0.5 * d.yaw);
        Ground { x: k * (c * d.x - s * d.y), y: k * (s * d.x + c * d.y), yaw }
    }
}

/// sin(x) / x, 1 at 0 (by its series below 0.05, within 1e-15).
fn sinc(x: f64) -> f64 {
    let x2 = x * x;
    if x.abs() < 0.05 { 1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0)) } else { x.sin() / x }
}

/// (sin x, cos x), by their series below 0.05 (within 1e-15): warps and sweep pieces turn by
/// little.
fn small_sin_cos(x: f64) -> (f64, f64) {
    if x.abs() < 0.05 {
        let x2 = x * x;
        (
            x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0))),
            1.0 - x2 / 2.0 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0)),
        )
    } else {
        x.sin_cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn interval(turn: f64, speed: f64) -> Interval {
        Interval {
            clip: 0,
            start: 0,
            end: 30,
            duration: 0.5,
            motion: Ground { x: speed * 0.5, y: 0.0, yaw: turn },
            speed,
            foot: 0,
        }
    }

    const MOVING: IntervalKind = IntervalKind {
        ends_at_rest: false,
        in_place: false,
        spot_turn: 0,
        stops: false,
        goes: true,
        sharp_turn: 0,
        shuffle: 0,
    };

    #[test]
    fn warps_reach_the_heading_and_speed_within_their_limits() {
        let l = WarpLimits::default();
        let walk = interval(0.0, 1.35);
        let w = Warp::toward(&walk, MOVING, 0.05, 1.5, &l);
        assert!((w.turn(&walk) - 0.05).abs() < 1e-12);
        assert!((w.speed(&walk) - 1.5).abs() < 1e-12);
        // A bend is bounded, a stride too.
        let w = Warp::toward(&walk, MOVING, 1.0, 3.0, &l);
        assert!((w.turn(&walk) - l.bend_rad).abs() < 1e-12);
        assert!((w.stride - 1.25).abs() < 1e-12);
        // A 45° turn scaled toward 60°, and toward 10° by its least scale plus the bend.
        let left = interval(45f64.to_radians(), 1.35);
        assert!(
            (Warp::toward(&left, MOVING, 60f64.to_radians(), 1.35, &l).turn(&left) - 60f64.to_radians()).abs() < 1e-12
        );
        let w = Warp::toward(&left, MOVING, 10f64.to_radians(), 1.35, &l);
        assert!((w.turn_scale - 0.5).abs() < 1e-12);
        assert!((w.turn(&left) - 14.5f64.to_radians()).abs() < 1e-9);
        // A turn on the spot scales only; standing never warps.
        let spot = IntervalKind { in_place: true, spot_turn: 1, ..MOVING };
        let pivot = interval(45f64.to_radians(), 0.05);
        let w = Warp::toward(&pivot, spot, 20f64.to_radians(), 1.0, &l);
        assert!((w.turn(&pivot) - 20f64.to_radians()).abs() < 1e-12 && w.stride == 1.0);
        let stand = IntervalKind { in_place: true, ..MOVING };
        assert_eq!(Warp::toward(&interval(0.0, 0.0), stand, 1.0, 1.0, &l), Warp::NONE);
    }

    #[test]
    fn the_series_match_the_functions() {
        for k in -100..=100 {
            let x = k as f64 * 0.0005;
            let (s, c) = small_sin_cos(x);
            assert!((s - x.sin()).abs() < 1e-15 && (c - x.cos()).abs() < 1e-15, "{x}");
            if x != 0.0 {
                assert!((sinc(x) - x.sin() / x).abs() < 1e-15, "{x}");
            }
        }
    }

    #[test]
    fn warped_arcs_are_the_same_in_one_piece_or_many() {
        // A constant-curvature arc warped in one increment or in 40 ends in the same place.
        let w = Warp { turn_scale: 1.4, bend: 0.15, stride: 1.2 };
        let (r, total) = (2.0, 0.6f64);
        let arc = |a: f64| Ground { x: r * a.sin(), y: r * (1.0 - a.cos()), yaw: a };
        let whole = w.apply(arc(total), 1.0);
        let mut g = Ground::default();
        for _ in 0..40 {
            g = g.then(w.apply(arc(total / 40.0), 1.0 / 40.0));
        }
        assert!((g.x - whole.x).abs() < 1e-9 && (g.y - whole.y).abs() < 1e-9, "{g:?} {whole:?}");
        assert!((g.yaw - whole.yaw).abs() < 1e-12);
        assert_eq!(Warp::NONE.apply(arc(total), 1.0), arc(total));
    }
}
