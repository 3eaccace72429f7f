//! A side view of the character (seed 002 Fig. 6; DESIGN.md §6): a strip of skeleton poses
//! seen from the character's left, each in its own ground frame (forward to the right, up),
//! one after another with the ground line and the feet's floor. Bones are lines (left side
//! blue, right side red, middle dark), the head a filled circle on a short neck, and each foot
//! a small outline from the heel to the toe tip.

use glam::{DVec2, DVec3};

use super::scene::{Painter, Rgba};
use crate::anim::{Pose, Skeleton};

/// One pose of the strip: joint positions in the character's ground frame (X forward, Z up),
/// the parent of each joint, and a caption.
#[derive(Debug, Clone, PartialEq)]
pub struct StripPose {
    /// Joint positions, metres.
    pub joints: Vec<DVec3>,
    /// Tips (end sites) as (joint, position), metres.
    pub tips: Vec<(usize, DVec3)>,
    /// Parent of each joint.
    pub parents: Vec<Option<usize>>,
    /// Which side each joint is on: -1 right, 0 middle, 1 left.
    pub sides: Vec<i8>,
    /// The head as (joint, top of the head): drawn as a circle around the segment from the
    /// joint (the base of the skull) to the top, instead of a line; `None` draws no head.
    pub head: Option<(usize, DVec3)>,
    /// Foot outlines as (side, points around the foot: ankle, toe tip, heel), metres.
    pub feet: Vec<(i8, Vec<DVec3>)>,
    /// Obstacles beside the figure, as rectangles (lowest corner, highest corner) in the
    /// strip's plane (horizontal, up), metres; drawn behind it.
    pub boxes: Vec<(DVec2, DVec2)>,
    /// Caption under the figure.
    pub caption: String,
}

const LEFT: Rgba = Rgba::rgb(40, 110, 200);
const RIGHT: Rgba = Rgba::rgb(200, 70, 50);
const MIDDLE: Rgba = Rgba::rgb(40, 40, 40);
const HEAD_FILL: Rgba = Rgba::rgb(235, 225, 205);
const GROUND: Rgba = Rgba::rgb(120, 120, 120);
const OBSTACLE: Rgba = Rgba::rgb(150, 159, 173);

/// Radius of the drawn head as a fraction of the head segment (base of the skull to the top).
const HEAD_RADIUS: f64 = 0.62;

/// Which side a joint is on, from its name: `Left…`/`left…` or `L` before a capital is the left
/// (1), the same for the right (-1), anything else the middle (0).
pub fn side_of(name: &str) -> i8 {
    let n = name.to_ascii_lowercase();
    let capital_after = |c: char| name.starts_with(c) && name.chars().nth(1).is_some_and(char::is_uppercase);
    if n.contains("left") || capital_after('L') {
        1
    } else if n.contains("right") || capital_after('R') {
        -1
    } else {
        0
    }
}

/// The strip pose of `pose` (in the world) seen in the ground frame of the pose itself
/// (`ground_pose`, usually the pose itself: root above the origin, facing +X). `feet` are the
/// foot (ankle) joints, whose outlines go from the ankle to the end site (toe tip) and back to
/// a heel point under the ankle; the head is the joint called `Head` (any case) with an end
/// site.
pub fn strip_pose(skeleton: &Skeleton, pose: &Pose, feet: &[usize], caption: String) -> StripPose {
    let mut globals = Vec::new();
    skeleton.globals(pose, &mut globals);
    let joints = skeleton.joints();
    let head = joints
        .iter()
        .position(|j| j.name.eq_ignore_ascii_case("head") && j.end_site.is_some())
        .map(|i| (i, skeleton.tip(&globals, i)));
    let outlines = feet
        .iter()
        .filter(|&&f| f < joints.len())
        .filter_map(|&f| {
            let e = joints[f].end_site?;
            let (ankle, q) = globals[f];
            // The heel under the ankle, a quarter of the foot's length behind it, on the sole.
            let heel = ankle + q * DVec3::new(-0.26 * e.x, 0.0, e.z);
            let heel_top = ankle + q * DVec3::new(-0.3 * e.x, 0.0, 0.5 * e.z);
            let instep = ankle + q * DVec3::new(0.35 * e.x, 0.0, 0.45 * e.z);
            Some((side_of(&joints[f].name), vec![ankle, instep, ankle + q * e, heel, heel_top]))
        })
        .collect();
    StripPose {
        joints: globals.iter().map(|g| g.0).collect(),
        tips: (0..joints.len())
            .filter(|&i| joints[i].end_site.is_some())
            .map(|i| (i, skeleton.tip(&globals, i)))
            .collect(),
        parents: joints.iter().map(|j| j.parent).collect(),
        sides: joints.iter().map(|j| side_of(&j.name)).collect(),
        head,
        feet: outlines,
        boxes: Vec::new(),
        caption,
    }
}

/// Draws the poses side by side on `painter`, scaled to fit.
pub fn draw_strip(poses: &[StripPose], painter: &mut dyn Painter) {
    let (w, h) = painter.size();
    let n = poses.len().max(1) as f64;
    let slot_w = w / n;
    // Metres to pixels: fit a 2 m tall figure and each slot's 1.2 m width.
    let scale = ((h - 30.0) / 2.1).min(slot_w / 1.2).max(1.0);
    let ground_y = h - 22.0;
    let width = (scale / 40.0).clamp(1.5, 4.0);
    painter.line(DVec2::new(0.0, ground_y), DVec2::new(w, ground_y), GROUND, 1.5);
    for (k, p) in poses.iter().enumerate() {
        let cx = slot_w * (k as f64 + 0.5);
        let px = |v: DVec3| DVec2::new(cx + v.x * scale, ground_y - v.z * scale);
        let head = p.head.map(|(i, _)| i);
        for &(lo, hi) in &p.boxes {
            let (a, b) = (px(DVec3::new(lo.x, 0.0, lo.y)), px(DVec3::new(hi.x, 0.0, hi.y)));
            let corners = [a, DVec2::new(b.x, a.y), b, DVec2::new(a.x, b.y)];
            painter.fill_polygon(&corners, OBSTACLE.with_alpha(110));
            painter.stroke_polygon(&corners, OBSTACLE, 0.5 * width);
        }
        // Far (right) side first so the near (left) side is drawn on top.
        for side in [-1i8, 0, 1] {
            let color = match side {
                -1 => RIGHT,
                1 => LEFT,
                _ => MIDDLE,
            };
            for (s, outline) in &p.feet {
                if *s == side && outline.len() > 2 {
                    let pts: Vec<DVec2> = outline.iter().map(|&v| px(v)).collect();
                    painter.fill_polygon(&pts, color.with_alpha(90));
                    painter.stroke_polygon(&pts, color, 0.6 * width);
                }
            }
            for (i, parent) in p.parents.iter().enumerate() {
                if p.sides[i] != side {
                    continue;
                }
                if let Some(j) = parent {
                    painter.line(px(p.joints[*j]), px(p.joints[i]), color, width);
                }
            }
            for &(i, tip) in &p.tips {
                if p.sides[i] == side && Some(i) != head {
                    painter.line(px(p.joints[i]), px(tip), color, width);
                }
            }
        }
        for &j in &p.joints {
            painter.fill_circle(px(j), 0.9 * width, MIDDLE);
        }
        if let Some((i, top)) = p.head {
            let base = p.joints[i];
            let r = HEAD_RADIUS * base.distance(top) * scale;
            // The skull sits a little ahead of the neck line, over the face.
            let up = (top - base).normalize_or_zero();
            let centre = px(base.lerp(top, 0.45)) + DVec2::new(up.z, up.x) * 0.12 * r;
            painter.fill_circle(centre, r, HEAD_FILL);
            painter.circle(centre, r, MIDDLE, 0.8 * width);
        }
        let size = painter.text_size(&p.caption);
        painter.text(DVec2::new(cx - size.x / 2.0, h - 16.0), &p.caption, MIDDLE);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::anim::actor;
    use crate::render::png::PngPainter;

    #[test]
    fn strip_pose_has_a_head_and_two_feet() {
        let s = actor::actor();
        let feet = [s.find(actor::LEFT_FOOT).unwrap(), s.find(actor::RIGHT_FOOT).unwrap()];
        let p = strip_pose(&s, &s.bind_pose(), &feet, "bind".into());
        let (head, top) = p.head.expect("a head");
        assert_eq!(head, s.find(actor::HEAD).unwrap());
        assert!((top.z - 1.75).abs() < 0.03, "top of the head at {}", top.z);
        assert_eq!(p.feet.len(), 2);
        assert_eq!((p.feet[0].0, p.feet[1].0), (1, -1));
        for (_, outline) in &p.feet {
            // Heel behind the ankle, toe ahead, both on the ground.
            let (ankle, toe, heel) = (outline[0], outline[2], outline[3]);
            assert!(toe.x > ankle.x + 0.15 && heel.x < ankle.x - 0.03);
            assert!(toe.z.abs() < 1e-9 && heel.z.abs() < 1e-9);
        }
        assert_eq!((side_of("LeftArm"), side_of("RHipJoint"), side_of("Head")), (1, -1, 0));
    }

    #[test]
    fn draws_the_head_as_a_filled_circle() {
        let s = actor::actor();
        let p = strip_pose(&s, &s.bind_pose(), &[], "x".into());
        let mut painter = PngPainter::new(200, 300);
        draw_strip(&[p], &mut painter);
        let pm = painter.pixmap();
        // The middle of the head is filled with the head colour.
        let scale = (300.0f64 - 30.0) / 2.1;
        let (x, y) = (100.0 + 0.012 * scale, 300.0 - 22.0 - 1.665 * scale);
        let c = pm.pixel(x as u32, y as u32).unwrap().demultiply();
        assert_eq!((c.red(), c.green(), c.blue()), (HEAD_FILL.r, HEAD_FILL.g, HEAD_FILL.b));
    }
}
