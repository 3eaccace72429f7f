//! Pixel comparison of two RGBA images and the diff picture of a failed comparison.
//!
//! Pure functions over 8-bit straight-alpha RGBA buffers (4 bytes per pixel, rows top to
//! bottom): no IO, no allocation beyond the diff picture. Identical buffers are recognised by
//! a plain byte comparison, so checking a frame that did not change costs one `memcmp`.

use std::borrow::Cow;

use tiny_skia::Pixmap;

/// When two pictures count as equal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// Largest difference of any channel (0–255) for a pixel to count as unchanged.
    pub channel: u8,
    /// Largest share of changed pixels (0–1) for the picture to count as matching.
    pub changed_share: f64,
}

impl Tolerance {
    /// Bit-identical pictures only.
    pub const EXACT: Tolerance = Tolerance { channel: 0, changed_share: 0.0 };

    /// Pixels whose channels all differ by at most `channel` count as unchanged; every other
    /// pixel must be unchanged.
    pub const fn channel(channel: u8) -> Tolerance {
        Tolerance { channel, changed_share: 0.0 }
    }
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance::EXACT
    }
}

/// What differs between two pictures of the same size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelDiff {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Pixels with a channel differing by more than the tolerance's `channel`.
    pub changed: u64,
    /// Largest difference of any channel over the picture (0–255).
    pub largest: u8,
    /// The first pixel (in reading order) with the largest difference, `(x, y)`; `None` when
    /// the pictures are identical.
    pub largest_at: Option<(u32, u32)>,
    /// Bounding box `(x_min, y_min, x_max, y_max)` (inclusive) of the changed pixels.
    pub changed_box: Option<(u32, u32, u32, u32)>,
}

impl PixelDiff {
    /// No difference at all, `width`×`height`.
    pub fn identical(width: u32, height: u32) -> PixelDiff {
        PixelDiff { width, height, changed: 0, largest: 0, largest_at: None, changed_box: None }
    }

    /// Pixels in the picture.
    pub fn total(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }

    /// Share of changed pixels, 0–1.
    pub fn changed_share(&self) -> f64 {
        self.changed as f64 / self.total().max(1) as f64
    }

    /// True when the pictures match within `tolerance` (its `channel` must be the one the
    /// difference was measured with).
    pub fn within(&self, tolerance: &Tolerance) -> bool {
        self.changed == 0 || self.changed_share() <= tolerance.changed_share
    }
}

/// Compares `expected` with `actual`, both `width`×`height` straight RGBA. A pixel is changed
/// when any channel differs by more than `channel`.
///
/// # Panics
/// When a buffer is not `width * height * 4` bytes long.
pub fn compare(expected: &[u8], actual: &[u8], width: u32, height: u32, channel: u8) -> PixelDiff {
    let len = width as usize * height as usize * 4;
    assert!(expected.len() == len && actual.len() == len, "buffers must hold width × height RGBA pixels");
    let mut d = PixelDiff::identical(width, height);
    if expected == actual {
        return d;
    }
    let w = width.max(1) as usize;
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for (i, (e, a)) in expected.chunks_exact(4).zip(actual.chunks_exact(4)).enumerate() {
        if e == a {
            continue;
        }
        let delta = e.iter().zip(a).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0);
        let (x, y) = ((i % w) as u32, (i / w) as u32);
        if delta > d.largest {
            d.largest = delta;
            d.largest_at = Some((x, y));
        }
        if delta > channel {
            d.changed += 1;
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
    }
    if d.changed > 0 {
        d.changed_box = Some((x0, y0, x1, y1));
    }
    d
}

/// Colour of a changed pixel in a diff picture.
pub const CHANGED: [u8; 4] = [255, 0, 0, 255];

/// The diff picture of `actual` (straight RGBA, `actual.len() / 4` pixels): every pixel that
/// differs from `expected` by more than `channel` (or that `expected` lacks) in red, every
/// other pixel a faded copy of `actual`.
pub fn diff_image(actual: &[u8], expected: &[u8], channel: u8) -> Vec<u8> {
    let fade = |c: u8| 255 - (255 - c) / 4;
    let mut out = Vec::with_capacity(actual.len());
    for (i, a) in actual.chunks_exact(4).enumerate() {
        let changed =
            expected.get(i * 4..i * 4 + 4).is_none_or(|e| e.iter().zip(a).any(|(x, y)| x.abs_diff(*y) > channel));
        if changed {
            out.extend_from_slice(&CHANGED);
        } else {
            out.extend_from_slice(&[fade(a[0]), fade(a[1]), fade(a[2]), 255]);
        }
    }
    out
}

/// The straight-alpha RGBA bytes of `pixmap` (borrowed when every pixel is opaque, where
/// premultiplied and straight alpha agree).
pub fn straight_rgba(pixmap: &Pixmap) -> Cow<'_, [u8]> {
    let data = pixmap.data();
    if data.chunks_exact(4).all(|p| p[3] == 255) {
        return Cow::Borrowed(data);
    }
    Cow::Owned(
        pixmap
            .pixels()
            .iter()
            .flat_map(|p| {
                let c = p.demultiply();
                [c.red(), c.green(), c.blue(), c.alpha()]
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn picture(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
        (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).flat_map(|(x, y)| f(x, y)).collect()
    }

    #[test]
    fn identical_pictures_have_no_difference() {
        let a = picture(5, 4, |x, y| [x as u8, y as u8, 7, 255]);
        let d = compare(&a, &a, 5, 4, 0);
        assert_eq!(d, PixelDiff::identical(5, 4));
        assert!(d.within(&Tolerance::EXACT));
    }

    #[test]
    fn changes_are_counted_located_and_boxed() {
        let a = picture(6, 5, |_, _| [200, 200, 200, 255]);
        let b = picture(6, 5, |x, y| match (x, y) {
            (1, 1) => [200, 203, 200, 255],
            (4, 3) => [90, 200, 200, 255],
            (2, 4) => [200, 200, 150, 255],
            _ => [200, 200, 200, 255],
        });
        let d = compare(&a, &b, 6, 5, 0);
        assert_eq!(d.changed, 3);
        assert_eq!((d.largest, d.largest_at), (110, Some((4, 3))));
        assert_eq!(d.changed_box, Some((1, 1, 4, 4)));
        let loose = compare(&a, &b, 6, 5, 3);
        assert_eq!(loose.changed, 2);
        assert_eq!(loose.changed_box, Some((2, 3, 4, 4)));
        assert!(!d.within(&Tolerance::EXACT));
        assert!(d.within(&Tolerance { channel: 0, changed_share: 0.1 }));
    }

    #[test]
    fn diff_marks_changed_pixels_over_a_faded_copy() {
        let a = picture(2, 1, |_, _| [0, 0, 0, 255]);
        let b = picture(2, 1, |x, _| if x == 1 { [9, 0, 0, 255] } else { [0, 0, 0, 255] });
        let d = diff_image(&b, &a, 0);
        assert_eq!(d, vec![192, 192, 192, 255, 255, 0, 0, 255]);
        assert_eq!(diff_image(&b, &[], 0), [CHANGED, CHANGED].concat());
    }
}
