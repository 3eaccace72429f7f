//! Animated GIFs of drawn frames (`strider render --gif`), through the `image` crate's GIF
//! encoder: each frame is quantised to its own palette of 256 colours (NeuQuant, as the `gif`
//! crate does; exact when a frame has no more colours) and shown for its own time; the
//! animation loops. Like the rest of the module, nothing here touches the file system: the
//! bytes come back to the caller.

use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};
use tiny_skia::Pixmap;

/// Quantiser speed of the encoder, 1 (best, slowest) to 30: 10 keeps a 100-frame 800 × 800
/// animation within seconds with no visible loss on strider's flat colours.
const QUANTISER_SPEED: i32 = 10;

/// The animation of `frames` (each a picture of at most 65,535 pixels a side and how long it
/// shows, milliseconds; GIF keeps hundredths of a second), looping forever. Frames are taken
/// one at a time, so a caller can draw them as they are encoded.
pub fn encode_gif(frames: impl IntoIterator<Item = (Pixmap, u32)>) -> Result<Vec<u8>, String> {
    let fail = |e: image::ImageError| format!("GIF encoding failed: {e}");
    let mut bytes = Vec::new();
    {
        let mut encoder = GifEncoder::new_with_speed(&mut bytes, QUANTISER_SPEED);
        encoder.set_repeat(Repeat::Infinite).map_err(fail)?;
        for (pixmap, delay_ms) in frames {
            let pixels: Vec<u8> = pixmap
                .pixels()
                .iter()
                .flat_map(|p| {
                    let c = p.demultiply();
                    [c.red(), c.green(), c.blue(), c.alpha()]
                })
                .collect();
            let image = RgbaImage::from_raw(pixmap.width(), pixmap.height(), pixels)
                .ok_or_else(|| "GIF encoding failed: a frame's size and pixels disagree".to_string())?;
            encoder
                .encode_frame(Frame::from_parts(image, 0, 0, Delay::from_numer_denom_ms(delay_ms, 1)))
                .map_err(fail)?;
        }
        // The encoder writes the file's trailer when it is dropped.
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_become_a_looping_animation() {
        let frames = [0u8, 128, 255].map(|shade| {
            let mut p = Pixmap::new(20, 10).unwrap();
            p.fill(tiny_skia::Color::from_rgba8(shade, 255 - shade, 40, 255));
            (p, 250)
        });
        let bytes = encode_gif(frames).unwrap();
        assert_eq!(&bytes[..6], b"GIF89a");
        let decoder = image::codecs::gif::GifDecoder::new(std::io::Cursor::new(&bytes)).unwrap();
        let frames = image::AnimationDecoder::into_frames(decoder).collect_frames().unwrap();
        assert_eq!(frames.len(), 3);
        assert_eq!(frames[1].delay().numer_denom_ms(), (250, 1));
        assert_eq!(frames[2].buffer().get_pixel(3, 3).0, [255, 0, 40, 255]);
    }
}
