//! Reading an unknown motion-capture rig (seed 000 §3.2, DESIGN.md §3): which joints are the
//! feet and which length unit the file is written in, so a BVH export from any tool builds a
//! database without flags.
//!
//! Feet are found by name first — after dropping namespace prefixes such as `mixamorig:` or
//! `Armature|` and ignoring case, `_`, `.`, `-` and spaces, so `LeftFoot`, `mixamorig:LeftFoot`,
//! `foot_l`, `L_Ankle` and `Foot.L` all name a left foot — and by the shape of the hierarchy when
//! names fail: the two chains that split from one joint and both reach down to the floor are the
//! legs, and on each the foot is the lowest joint whose bone comes down into it.
//!
//! The unit is read from the leg: hips to ankle along the bones, a standing adult's leg is
//! [`LEG_LENGTH_M`] long to within a factor of [`LEG_TOLERANCE`]. Of the usual units
//! ([`UNITS`]: metres, CMU's 0.056444 m, inches, centimetres, millimetres) the one that makes
//! the leg human is chosen; their factors are far enough apart that at most one fits.
//!
//! Pure functions of the skeleton's bind pose; left is the side of larger Y (a BVH file's +X,
//! the left of a character facing +Z, as the usual exporters write it).

use glam::DVec3;

use super::skeleton::Skeleton;

/// Length of a standing adult's leg from the root joint (the hips) to the ankle along the bones,
/// metres.
pub const LEG_LENGTH_M: f64 = 0.9;

/// Factor within which a human leg is known: lengths in `[LEG_LENGTH_M / 1.3, LEG_LENGTH_M ·
/// 1.3]` count as human.
pub const LEG_TOLERANCE: f64 = 1.3;

/// A length unit a motion-capture file may be written in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LengthUnit {
    /// What the unit is called in messages.
    pub name: &'static str,
    /// Metres per file unit (the BVH import scale).
    pub metres: f64,
}

/// The units tried, largest first. Neighbours differ by a factor of at least 2.2, more than
/// [`LEG_TOLERANCE`]², so a leg fits one unit at most.
pub const UNITS: [LengthUnit; 5] = [
    LengthUnit { name: "metres", metres: 1.0 },
    LengthUnit { name: "CMU units", metres: 0.056444 },
    LengthUnit { name: "inches", metres: 0.0254 },
    LengthUnit { name: "centimetres", metres: 0.01 },
    LengthUnit { name: "millimetres", metres: 0.001 },
];

/// How the feet were found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FeetFrom {
    /// The names given by the caller.
    Given,
    /// Joint names.
    Name,
    /// The shape of the hierarchy.
    Topology,
}

/// The unit read from a skeleton.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitGuess {
    /// The unit chosen.
    pub unit: LengthUnit,
    /// The leg, root to ankle along the bones, in file units (the mean of both legs).
    pub leg_length: f64,
    /// Whether the leg is human in that unit; when false, the unit is only the nearest one and
    /// the caller should say so.
    pub human: bool,
}

impl UnitGuess {
    /// The leg length in metres in the chosen unit.
    pub fn leg_length_m(&self) -> f64 {
        self.leg_length * self.unit.metres
    }
}

/// The joint name without a namespace prefix: the part after the last `:` or `|`.
pub fn base_name(name: &str) -> &str {
    name.rsplit([':', '|']).next().unwrap_or(name)
}

/// The joint name reduced for comparison: no prefix, lower case, no `_ . - ` or spaces.
fn key(name: &str) -> String {
    base_name(name).chars().filter(|c| !matches!(c, '_' | '.' | '-' | ' ')).flat_map(char::to_lowercase).collect()
}

/// Which side and part a reduced name denotes: `(side, part)` with side `l` or `r`.
fn side_and_part(key: &str) -> Option<(char, &str)> {
    for part in ["foot", "ankle"] {
        for (side, words) in [('l', ["left", "l"]), ('r', ["right", "r"])] {
            for w in words {
                if key == format!("{w}{part}") || key == format!("{part}{w}") {
                    return Some((side, part));
                }
            }
        }
    }
    None
}

/// The left and right foot joints, and how they were found: by the `names` given (two names,
/// matched exactly or without their namespace prefixes), else by joint names, else by the shape
/// of the hierarchy. `None` when none of these finds two feet.
pub fn locate_feet(skeleton: &Skeleton, names: &[String]) -> Option<([usize; 2], FeetFrom)> {
    let joints = skeleton.joints();
    if names.len() == 2 {
        let find =
            |n: &str| skeleton.find(n).or_else(|| joints.iter().position(|j| base_name(&j.name) == base_name(n)));
        return match (find(&names[0]), find(&names[1])) {
            (Some(l), Some(r)) if l != r => Some(([l, r], FeetFrom::Given)),
            _ => None,
        };
    }
    for part in ["foot", "ankle"] {
        let find = |side: char| {
            joints.iter().position(|j| side_and_part(&key(&j.name)).is_some_and(|(s, p)| s == side && p == part))
        };
        if let (Some(l), Some(r)) = (find('l'), find('r')) {
            return Some(([l, r], FeetFrom::Name));
        }
    }
    feet_by_topology(skeleton).map(|f| (f, FeetFrom::Topology))
}

/// The feet from the hierarchy alone: the highest joint with two child chains that both reach
/// the floor (the lowest quarter of the height below that joint) is the hips; under each, the
/// path to its lowest tip is a leg, and its foot is the lowest joint on it whose bone from the
/// parent points down more than sideways.
pub fn feet_by_topology(skeleton: &Skeleton) -> Option<[usize; 2]> {
    let joints = skeleton.joints();
    let n = joints.len();
    let mut g = Vec::with_capacity(n);
    skeleton.globals(&skeleton.bind_pose(), &mut g);
    let tip = |i: usize| skeleton.tip(&g, i).z;
    // Lowest tip in each subtree and the joint that owns it (children come after parents).
    let mut low: Vec<(f64, usize)> = (0..n).map(|i| (tip(i).min(g[i].0.z), i)).collect();
    for i in (1..n).rev() {
        if let Some(p) = joints[i].parent
            && low[i].0 < low[p].0
        {
            low[p] = low[i];
        }
    }
    let children = |h: usize| (h + 1..n).filter(move |&c| joints[c].parent == Some(h));
    for h in 0..n {
        let mut kids: Vec<usize> = children(h).collect();
        if kids.len() < 2 {
            continue;
        }
        kids.sort_by(|&a, &b| low[a].0.total_cmp(&low[b].0).then(a.cmp(&b)));
        let (a, b) = (kids[0], kids[1]);
        let top = g[h].0.z;
        let span = top - low[h].0;
        if !(span > 1e-9) || low[b].0 > low[h].0 + 0.25 * span {
            continue;
        }
        let feet = [a, b].map(|c| foot_on_path(skeleton, &g, h, low[c].1));
        let [fa, fb] = feet;
        if fa == fb {
            continue;
        }
        return Some(if g[fa].0.y >= g[fb].0.y { [fa, fb] } else { [fb, fa] });
    }
    None
}

/// The foot on the path from `hips` down to `leaf`: the lowest joint whose bone from its parent
/// points down more than sideways, or the leaf itself.
fn foot_on_path(skeleton: &Skeleton, g: &[(DVec3, glam::DQuat)], hips: usize, leaf: usize) -> usize {
    let joints = skeleton.joints();
    let mut j = leaf;
    while j != hips {
        let Some(p) = joints[j].parent else { break };
        let bone = g[j].0 - g[p].0;
        if -bone.z > bone.truncate().length() {
            return j;
        }
        j = p;
    }
    leaf
}

/// The leg length in file units: the mean over both feet of the bone lengths from the root down
/// to the foot.
pub fn leg_length(skeleton: &Skeleton, feet: [usize; 2]) -> f64 {
    let joints = skeleton.joints();
    let chain = |mut j: usize| {
        let mut sum = 0.0;
        while let Some(p) = joints[j].parent {
            sum += joints[j].offset.length();
            j = p;
        }
        sum
    };
    0.5 * (chain(feet[0]) + chain(feet[1]))
}

/// The unit that makes the leg from the root to `feet` human (see the module documentation);
/// when none does, the nearest one with `human` false. `None` for a leg of zero length.
pub fn guess_unit(skeleton: &Skeleton, feet: [usize; 2]) -> Option<UnitGuess> {
    let leg = leg_length(skeleton, feet);
    if !(leg > 0.0 && leg.is_finite()) {
        return None;
    }
    let miss = |u: &LengthUnit| (leg * u.metres / LEG_LENGTH_M).ln().abs();
    let unit = *UNITS.iter().min_by(|a, b| miss(a).total_cmp(&miss(b)))?;
    Some(UnitGuess { unit, leg_length: leg, human: miss(&unit) <= LEG_TOLERANCE.ln() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_are_far_enough_apart_for_one_to_fit() {
        for w in UNITS.windows(2) {
            assert!(w[0].metres / w[1].metres > LEG_TOLERANCE * LEG_TOLERANCE, "{} / {}", w[0].name, w[1].name);
        }
    }

    #[test]
    fn names_match_without_prefixes_case_or_separators() {
        for (name, side) in [
            ("LeftFoot", 'l'),
            ("mixamorig:RightFoot", 'r'),
            ("Armature|foot_l", 'l'),
            ("L_Ankle", 'l'),
            ("Foot.R", 'r'),
            ("right ankle", 'r'),
        ] {
            assert_eq!(side_and_part(&key(name)).map(|s| s.0), Some(side), "{name}");
        }
        for name in ["LeftFootIndex", "Hips", "LeftToeBase", "Flat"] {
            assert_eq!(side_and_part(&key(name)), None, "{name}");
        }
        assert_eq!(base_name("a:b|c:LeftFoot"), "LeftFoot");
    }
}
