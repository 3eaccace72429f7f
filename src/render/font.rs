//! A tiny built-in 5×7 bitmap font for labels and titles.
//!
//! Each printable ASCII character (32..=126) has one glyph made of seven row
//! masks; bit 4 of a row is the leftmost column and bit 0 the rightmost.
//! Glyphs are drawn as solid `scale`×`scale` blocks per set bit, so text is
//! crisp at any integer scale. Characters outside the table are drawn as a
//! hollow box. The descending letters `g`, `p`, `q` and `y` are drawn two
//! rows lower, so they extend [`DESCENT`] units below the cell. Drawing is clipped to the pixmap and never panics.

use tiny_skia::{Color, Pixmap, PremultipliedColorU8};

/// Glyph width in font units (columns).
pub const GLYPH_WIDTH: u32 = 5;
/// Glyph height in font units (rows).
pub const GLYPH_HEIGHT: u32 = 7;
/// Font units that descending letters (`g`, `p`, `q`, `y`) reach below
/// the seven-row cell; callers should leave this much room under a line.
pub const DESCENT: u32 = 2;
/// Letters whose glyph is drawn `DESCENT` rows lower than the others.
const DESCENDERS: &str = "gpqy";
/// Horizontal advance per character in font units (glyph plus one column gap).
pub const ADVANCE: u32 = GLYPH_WIDTH + 1;

/// Glyph used for characters that have no entry in [`GLYPHS`].
const UNKNOWN: [u8; 7] = [0b11111, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b11111];

/// Row masks for ASCII 32 (space) through 126 (`~`), in code-point order.
#[rustfmt::skip]
pub const GLYPHS: [[u8; 7]; 95] = [
    [0, 0, 0, 0, 0, 0, 0],                                              // ' '
    [0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00000, 0b00100],    // '!'
    [0b01010, 0b01010, 0b01010, 0, 0, 0, 0],                            // '"'
    [0b01010, 0b01010, 0b11111, 0b01010, 0b11111, 0b01010, 0b01010],    // '#'
    [0b00100, 0b01111, 0b10100, 0b01110, 0b00101, 0b11110, 0b00100],    // '$'
    [0b11000, 0b11001, 0b00010, 0b00100, 0b01000, 0b10011, 0b00011],    // '%'
    [0b01100, 0b10010, 0b10100, 0b01000, 0b10101, 0b10010, 0b01101],    // '&'
    [0b00100, 0b00100, 0b01000, 0, 0, 0, 0],                            // '\''
    [0b00010, 0b00100, 0b01000, 0b01000, 0b01000, 0b00100, 0b00010],    // '('
    [0b01000, 0b00100, 0b00010, 0b00010, 0b00010, 0b00100, 0b01000],    // ')'
    [0, 0b00100, 0b10101, 0b01110, 0b10101, 0b00100, 0],                // '*'
    [0, 0b00100, 0b00100, 0b11111, 0b00100, 0b00100, 0],                // '+'
    [0, 0, 0, 0, 0b01100, 0b00100, 0b01000],                            // ','
    [0, 0, 0, 0b11111, 0, 0, 0],                                        // '-'
    [0, 0, 0, 0, 0, 0b01100, 0b01100],                                  // '.'
    [0, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0],                // '/'
    [0b01110, 0b10001, 0b10011, 0b10101, 0b11001, 0b10001, 0b01110],    // '0'
    [0b00100, 0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110],    // '1'
    [0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b01000, 0b11111],    // '2'
    [0b11111, 0b00010, 0b00100, 0b00010, 0b00001, 0b10001, 0b01110],    // '3'
    [0b00010, 0b00110, 0b01010, 0b10010, 0b11111, 0b00010, 0b00010],    // '4'
    [0b11111, 0b10000, 0b11110, 0b00001, 0b00001, 0b10001, 0b01110],    // '5'
    [0b00110, 0b01000, 0b10000, 0b11110, 0b10001, 0b10001, 0b01110],    // '6'
    [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b01000, 0b01000],    // '7'
    [0b01110, 0b10001, 0b10001, 0b01110, 0b10001, 0b10001, 0b01110],    // '8'
    [0b01110, 0b10001, 0b10001, 0b01111, 0b00001, 0b00010, 0b01100],    // '9'
    [0, 0b01100, 0b01100, 0, 0b01100, 0b01100, 0],                      // ':'
    [0, 0b01100, 0b01100, 0, 0b01100, 0b00100, 0b01000],                // ';'
    [0b00010, 0b00100, 0b01000, 0b10000, 0b01000, 0b00100, 0b00010],    // '<'
    [0, 0, 0b11111, 0, 0b11111, 0, 0],                                  // '='
    [0b01000, 0b00100, 0b00010, 0b00001, 0b00010, 0b00100, 0b01000],    // '>'
    [0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0, 0b00100],          // '?'
    [0b01110, 0b10001, 0b00001, 0b01101, 0b10101, 0b10101, 0b01110],    // '@'
    [0b01110, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001],    // 'A'
    [0b11110, 0b10001, 0b10001, 0b11110, 0b10001, 0b10001, 0b11110],    // 'B'
    [0b01110, 0b10001, 0b10000, 0b10000, 0b10000, 0b10001, 0b01110],    // 'C'
    [0b11100, 0b10010, 0b10001, 0b10001, 0b10001, 0b10010, 0b11100],    // 'D'
    [0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b11111],    // 'E'
    [0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b10000],    // 'F'
    [0b01110, 0b10001, 0b10000, 0b10111, 0b10001, 0b10001, 0b01111],    // 'G'
    [0b10001, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001],    // 'H'
    [0b01110, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110],    // 'I'
    [0b00111, 0b00010, 0b00010, 0b00010, 0b00010, 0b10010, 0b01100],    // 'J'
    [0b10001, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010, 0b10001],    // 'K'
    [0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b11111],    // 'L'
    [0b10001, 0b11011, 0b10101, 0b10101, 0b10001, 0b10001, 0b10001],    // 'M'
    [0b10001, 0b10001, 0b11001, 0b10101, 0b10011, 0b10001, 0b10001],    // 'N'
    [0b01110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110],    // 'O'
    [0b11110, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000, 0b10000],    // 'P'
    [0b01110, 0b10001, 0b10001, 0b10001, 0b10101, 0b10010, 0b01101],    // 'Q'
    [0b11110, 0b10001, 0b10001, 0b11110, 0b10100, 0b10010, 0b10001],    // 'R'
    [0b01111, 0b10000, 0b10000, 0b01110, 0b00001, 0b00001, 0b11110],    // 'S'
    [0b11111, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100],    // 'T'
    [0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110],    // 'U'
    [0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100],    // 'V'
    [0b10001, 0b10001, 0b10001, 0b10101, 0b10101, 0b10101, 0b01010],    // 'W'
    [0b10001, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001, 0b10001],    // 'X'
    [0b10001, 0b10001, 0b10001, 0b01010, 0b00100, 0b00100, 0b00100],    // 'Y'
    [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b11111],    // 'Z'
    [0b01110, 0b01000, 0b01000, 0b01000, 0b01000, 0b01000, 0b01110],    // '['
    [0, 0b10000, 0b01000, 0b00100, 0b00010, 0b00001, 0],                // '\\'
    [0b01110, 0b00010, 0b00010, 0b00010, 0b00010, 0b00010, 0b01110],    // ']'
    [0b00100, 0b01010, 0b10001, 0, 0, 0, 0],                            // '^'
    [0, 0, 0, 0, 0, 0, 0b11111],                                        // '_'
    [0b01000, 0b00100, 0b00010, 0, 0, 0, 0],                            // '`'
    [0, 0, 0b01110, 0b00001, 0b01111, 0b10001, 0b01111],                // 'a'
    [0b10000, 0b10000, 0b10110, 0b11001, 0b10001, 0b10001, 0b11110],    // 'b'
    [0, 0, 0b01110, 0b10000, 0b10000, 0b10001, 0b01110],                // 'c'
    [0b00001, 0b00001, 0b01101, 0b10011, 0b10001, 0b10001, 0b01111],    // 'd'
    [0, 0, 0b01110, 0b10001, 0b11111, 0b10000, 0b01110],                // 'e'
    [0b00110, 0b01001, 0b01000, 0b11100, 0b01000, 0b01000, 0b01000],    // 'f'
    [0b01111, 0b10001, 0b10001, 0b10011, 0b01101, 0b00001, 0b01110],    // 'g'
    [0b10000, 0b10000, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001],    // 'h'
    [0b00100, 0, 0b01100, 0b00100, 0b00100, 0b00100, 0b01110],          // 'i'
    [0b00010, 0, 0b00110, 0b00010, 0b00010, 0b10010, 0b01100],          // 'j'
    [0b10000, 0b10000, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010],    // 'k'
    [0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110],    // 'l'
    [0, 0, 0b11010, 0b10101, 0b10101, 0b10001, 0b10001],                // 'm'
    [0, 0, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001],                // 'n'
    [0, 0, 0b01110, 0b10001, 0b10001, 0b10001, 0b01110],                // 'o'
    [0b10110, 0b11001, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000],    // 'p'
    [0b01101, 0b10011, 0b10001, 0b10001, 0b01111, 0b00001, 0b00001],    // 'q'
    [0, 0, 0b10110, 0b11001, 0b10000, 0b10000, 0b10000],                // 'r'
    [0, 0, 0b01110, 0b10000, 0b01110, 0b00001, 0b11110],                // 's'
    [0b01000, 0b01000, 0b11100, 0b01000, 0b01000, 0b01001, 0b00110],    // 't'
    [0, 0, 0b10001, 0b10001, 0b10001, 0b10011, 0b01101],                // 'u'
    [0, 0, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100],                // 'v'
    [0, 0, 0b10001, 0b10001, 0b10101, 0b10101, 0b01010],                // 'w'
    [0, 0, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001],                // 'x'
    [0b10001, 0b10001, 0b10001, 0b10011, 0b01101, 0b00001, 0b01110],    // 'y'
    [0, 0, 0b11111, 0b00010, 0b00100, 0b01000, 0b11111],                // 'z'
    [0b00010, 0b00100, 0b00100, 0b01000, 0b00100, 0b00100, 0b00010],    // '{'
    [0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100],    // '|'
    [0b01000, 0b00100, 0b00100, 0b00010, 0b00100, 0b00100, 0b01000],    // '}'
    [0, 0, 0b01000, 0b10101, 0b00010, 0, 0],                            // '~'
];

/// Returns the row masks for `c`, or a hollow box for unsupported characters.
pub fn glyph(c: char) -> &'static [u8; 7] {
    let code = c as u32;
    if (32..=126).contains(&code) { &GLYPHS[(code - 32) as usize] } else { &UNKNOWN }
}

/// Width in pixels of `text` rendered at `scale` (0 is treated as 1).
///
/// Every character advances by six font units; the trailing gap after the
/// last character is not counted. The empty string has width 0.
pub fn text_width(text: &str, scale: u32) -> u32 {
    let scale = scale.max(1);
    let n = u32::try_from(text.chars().count()).unwrap_or(u32::MAX);
    if n == 0 { 0 } else { n.saturating_mul(ADVANCE).saturating_sub(1).saturating_mul(scale) }
}

/// Height in pixels of one line of text at `scale` (0 is treated as 1),
/// excluding the [`DESCENT`] of descending letters.
pub fn text_height(scale: u32) -> u32 {
    GLYPH_HEIGHT * scale.max(1)
}

/// Draws `text` with its top-left corner at (`x`, `y`).
///
/// Each font unit becomes a `scale`×`scale` block (0 is treated as 1) in
/// `color`, blended source-over. Parts falling outside the pixmap are
/// silently clipped.
pub fn draw_text(pixmap: &mut Pixmap, x: i32, y: i32, text: &str, scale: u32, color: Color) {
    let s = i64::from(scale.max(1));
    let src = color.premultiply().to_color_u8();
    let (w, h) = (i64::from(pixmap.width()), i64::from(pixmap.height()));
    let mut pen_x = i64::from(x);
    let top = i64::from(y);
    for c in text.chars() {
        if pen_x >= w {
            break;
        }
        let rows = glyph(c);
        let drop = if DESCENDERS.contains(c) { i64::from(DESCENT) * s } else { 0 };
        for (r, &mask) in rows.iter().enumerate() {
            for col in 0..GLYPH_WIDTH {
                if mask & (1 << (GLYPH_WIDTH - 1 - col)) != 0 {
                    let bx = pen_x + i64::from(col) * s;
                    let by = top + drop + r as i64 * s;
                    fill_block(pixmap, bx, by, s, s, src, w, h);
                }
            }
        }
        pen_x += i64::from(ADVANCE) * s;
    }
}

/// Blends a solid block into the pixmap, clipped to its bounds.
#[allow(clippy::too_many_arguments)]
fn fill_block(pixmap: &mut Pixmap, x: i64, y: i64, bw: i64, bh: i64, src: PremultipliedColorU8, w: i64, h: i64) {
    let x0 = x.max(0);
    let y0 = y.max(0);
    let x1 = (x + bw).min(w);
    let y1 = (y + bh).min(h);
    if x0 >= x1 || y0 >= y1 {
        return;
    }
    let pixels = pixmap.pixels_mut();
    for py in y0..y1 {
        let row = (py * w) as usize;
        for px in x0..x1 {
            let p = &mut pixels[row + px as usize];
            *p = blend(src, *p);
        }
    }
}

/// Source-over blending of premultiplied colours.
fn blend(src: PremultipliedColorU8, dst: PremultipliedColorU8) -> PremultipliedColorU8 {
    let sa = u32::from(src.alpha());
    if sa == 255 {
        return src;
    }
    let inv = 255 - sa;
    let mix = |s: u8, d: u8| -> u8 {
        let v = u32::from(s) + (u32::from(d) * inv + 127) / 255;
        v.min(255) as u8
    };
    let a = mix(src.alpha(), dst.alpha());
    let r = mix(src.red(), dst.red()).min(a);
    let g = mix(src.green(), dst.green()).min(a);
    let b = mix(src.blue(), dst.blue()).min(a);
    PremultipliedColorU8::from_rgba(r, g, b, a).unwrap_or(dst)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glyph_table_covers_printable_ascii() {
        assert_eq!(GLYPHS.len(), 95);
        assert_eq!(glyph(' '), &[0; 7]);
        assert_eq!(glyph('~'), &GLYPHS[94]);
        assert_eq!(glyph('é'), &UNKNOWN);
        // Every visible character has at least one set bit and fits in 5 columns.
        for (i, g) in GLYPHS.iter().enumerate() {
            assert!(g.iter().all(|&row| row < 32), "glyph {i} too wide");
            if i > 0 {
                assert!(g.iter().any(|&row| row != 0), "glyph {i} is blank");
            }
        }
    }

    #[test]
    fn text_width_counts_characters() {
        assert_eq!(text_width("", 3), 0);
        assert_eq!(text_width("A", 1), 5);
        assert_eq!(text_width("AB", 1), 11);
        assert_eq!(text_width("0.5", 2), 34);
        assert_eq!(text_width("µ", 1), 5);
        assert_eq!(text_width("x", 0), 5);
    }

    #[test]
    fn draw_text_clips_and_colours() {
        let mut pm = Pixmap::new(20, 10).expect("non-zero size");
        pm.fill(Color::WHITE);
        let red = Color::from_rgba8(200, 0, 0, 255);
        draw_text(&mut pm, -3, -2, "Hi?é", 2, red);
        draw_text(&mut pm, i32::MAX - 1, i32::MIN, "x", u32::MAX, red);
        draw_text(&mut pm, 15, 5, "WWW", 1, red);
        let hit = pm.pixels().iter().any(|p| p.red() == 200 && p.green() == 0 && p.blue() == 0);
        assert!(hit);
    }
}
