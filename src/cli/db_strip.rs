//! `strider db strip`: a side-view strip (seed 002 Fig. 6) of one clip of a database, every
//! N-th frame, each pose in its own ground frame (root above the origin, facing right), with
//! its frame number under it, written as a PNG.

use std::path::PathBuf;

use anyhow::{Context, anyhow};
use clap::Args;

use crate::anim::Ground;
use crate::files::write_atomic;
use crate::load::{Outcome, builtin_database, load_database};
use crate::render::png::parse_size;
use crate::render::png::{PngPainter, encode};
use crate::render::poses::{StripPose, draw_strip, strip_pose};

/// `strider db strip` options.
#[derive(Debug, Args)]
pub struct StripArgs {
    /// Database directory (default: built-in).
    pub dir: Option<PathBuf>,
    /// Name of the clip to draw.
    #[arg(long)]
    pub clip: String,
    /// PNG file to write.
    #[arg(long)]
    pub out: PathBuf,
    /// Draw every N-th frame (the last frame of the range is always drawn).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    pub every: u32,
    /// First frame drawn.
    #[arg(long, default_value_t = 0)]
    pub first: usize,
    /// Last frame drawn (default: the clip's last).
    #[arg(long)]
    pub last: Option<usize>,
    /// Image size WIDTHxHEIGHT in pixels (default: 110 pixels per pose, 300 high).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
}

/// The frames drawn for a clip of `frames` frames: `0, every, 2·every, …` and the last one.
pub fn strip_frames(frames: usize, every: usize) -> Vec<usize> {
    if frames == 0 {
        return Vec::new();
    }
    let mut v: Vec<usize> = (0..frames).step_by(every.max(1)).collect();
    if v.last() != Some(&(frames - 1)) {
        v.push(frames - 1);
    }
    v
}

/// `strider db strip …`.
pub fn run(a: StripArgs) -> Outcome {
    let db = match &a.dir {
        Some(d) => load_database(d)?,
        None => builtin_database()?,
    };
    let clip = db.clips.iter().find(|c| c.name == a.clip).ok_or_else(|| {
        let names: Vec<&str> = db.clips.iter().map(|c| c.name.as_str()).collect();
        anyhow!("no clip named '{}'; the clips are: {}", a.clip, names.join(", "))
    })?;
    let last = a.last.unwrap_or(usize::MAX).min(clip.frames.len() - 1);
    if a.first > last {
        return Err(anyhow!("--first {} is after the last frame drawn ({last})", a.first).into());
    }
    let poses: Vec<StripPose> = strip_frames(last + 1 - a.first, a.every as usize)
        .into_iter()
        .map(|f| f + a.first)
        .map(|f| {
            let mut pose = clip.frames[f].clone();
            Ground::of(&pose, db.forward_offset).transform_pose(&mut pose, true);
            strip_pose(&db.skeleton, &pose, &db.feet, f.to_string())
        })
        .collect();
    let (w, h) = a.size.unwrap_or(((110 * poses.len() as u32).clamp(200, 8192), 300));
    let mut painter = PngPainter::new(w, h);
    draw_strip(&poses, &mut painter);
    let png = encode(painter.pixmap()).map_err(|e| anyhow!("cannot encode PNG: {e}"))?;
    write_atomic(&a.out, &png).with_context(|| format!("cannot write {}", a.out.display()))?;
    crate::files::outln!(
        "{} poses of '{}' ({} frames) written to {}",
        poses.len(),
        clip.name,
        clip.frames.len(),
        a.out.display()
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_nth_frame_and_the_last() {
        assert_eq!(strip_frames(11, 5), vec![0, 5, 10]);
        assert_eq!(strip_frames(12, 5), vec![0, 5, 10, 11]);
        assert_eq!(strip_frames(1, 3), vec![0]);
        assert!(strip_frames(0, 3).is_empty());
    }
}
