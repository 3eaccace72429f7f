//! A side view of the character (seed 002 Fig. 6; DESIGN.md §6): a strip of skeleton poses
//! seen from the character's left, each in its own ground frame (forward to the right, up),
//! one after another with the ground line and the feet's floor.

use glam::{DVec2, DVec3};

use super::scene::{Painter, Rgba};

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
    /// Caption under the figure.
    pub caption: String,
}

const LEFT: Rgba = Rgba::rgb(40, 110, 200);
const RIGHT: Rgba = Rgba::rgb(200, 70, 50);
const MIDDLE: Rgba = Rgba::rgb(40, 40, 40);
const GROUND: Rgba = Rgba::rgb(120, 120, 120);

/// Draws the poses side by side on `painter`, scaled to fit.
pub fn draw_strip(poses: &[StripPose], painter: &mut dyn Painter) {
    let (w, h) = painter.size();
    let n = poses.len().max(1) as f64;
    let slot_w = w / n;
    // Metres to pixels: fit a 2 m tall figure and each slot's 1.2 m width.
    let scale = ((h - 30.0) / 2.1).min(slot_w / 1.2).max(1.0);
    let ground_y = h - 22.0;
    painter.line(DVec2::new(0.0, ground_y), DVec2::new(w, ground_y), GROUND, 1.5);
    for (k, p) in poses.iter().enumerate() {
        let cx = slot_w * (k as f64 + 0.5);
        let px = |v: DVec3| DVec2::new(cx + v.x * scale, ground_y - v.z * scale);
        // Far (right) side first so the near (left) side is drawn on top.
        for side in [-1i8, 0, 1] {
            let color = match side {
                -1 => RIGHT,
                1 => LEFT,
                _ => MIDDLE,
            };
            for (i, parent) in p.parents.iter().enumerate() {
                if p.sides[i] != side {
                    continue;
                }
                if let Some(j) = parent {
                    painter.line(px(p.joints[*j]), px(p.joints[i]), color, 2.5);
                }
            }
            for &(i, tip) in &p.tips {
                if p.sides[i] == side {
                    painter.line(px(p.joints[i]), px(tip), color, 2.5);
                }
            }
        }
        for &j in &p.joints {
            painter.fill_circle(px(j), 2.5, MIDDLE);
        }
        let size = painter.text_size(&p.caption);
        painter.text(DVec2::new(cx - size.x / 2.0, h - 16.0), &p.caption, MIDDLE);
    }
}
