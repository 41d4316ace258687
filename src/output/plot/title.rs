//! A figure's title, centred, with its glyphs where the font puts them.
//!
//! plotters 0.3.7 draws a bitmap glyph from the pen position without the glyph's left side
//! bearing (`style/font/ab_glyph.rs`: the outline's `px_bounds().min.x` is dropped), so the
//! gap after a glyph with a wide bearing grows by the difference of the two bearings:
//! "Constraint" came out as "Constrain t" at 26 px ('n' has a 2.4 px bearing, 't' 0.7 px).
//! On a bitmap the title is therefore drawn one glyph at a time, each at its pen position
//! plus its own bearing (advances and kerning from ab_glyph, as plotters measures them), so
//! the ink lands where the font places it. An SVG title is one text element: the viewer
//! lays it out.

use ab_glyph::{Font, FontRef, ScaleFont};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::font::{FONT, FONT_BYTES};

/// The x offset (px, from the start of the text) of each glyph's ink, and the text's width.
pub(super) fn glyph_offsets(text: &str, size: f32) -> (Vec<(char, f32)>, f32) {
    let Ok(font) = FontRef::try_from_slice(FONT_BYTES) else {
        return (vec![], 0.0);
    };
    let font = font.as_scaled(size);
    let mut pen = 0.0_f32;
    let mut previous = None;
    let mut out = Vec::with_capacity(text.len());
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = previous {
            pen += font.kern(p, id);
        }
        out.push((c, pen + font.h_side_bearing(id)));
        pen += font.h_advance(id);
        previous = Some(id);
    }
    (out, pen)
}

/// Draws `text` at `size` px centred across `area`, its top `top` px from the area's top;
/// glyph by glyph on a bitmap (`bitmap`), as one element otherwise.
pub(super) fn draw_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    size: u32,
    top: i32,
    bitmap: bool,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (width, _) = area.dim_in_pixel();
    let centre = width as i32 / 2;
    let font = (FONT, size).into_font();
    if !bitmap {
        let style = TextStyle::from(font).pos(Pos::new(HPos::Center, VPos::Top));
        return area.draw(&Text::new(text, (centre, top), style));
    }
    let (glyphs, total) = glyph_offsets(text, size as f32);
    let left = centre as f32 - total / 2.0;
    for (c, x) in glyphs.into_iter().filter(|(c, _)| !c.is_whitespace()) {
        let at = ((left + x).round() as i32, top);
        area.draw(&Text::new(c.to_string(), at, font.clone()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::glyph_offsets;

    #[test]
    fn each_glyph_starts_at_its_pen_position_plus_its_bearing() {
        // DejaVu Sans, 2048 units to the em: 'n' advance 1298, bearing 186; 't' bearing 55.
        // ab_glyph scales so that ascent - descent (1901 + 483 units) is the size in px.
        let em = 26.0 / 2384.0;
        let (glyphs, width) = glyph_offsets("nt", 26.0);
        assert_eq!(glyphs.len(), 2);
        let close = |a: f32, b: f32| (a - b).abs() < 0.05;
        assert!(close(glyphs[0].1, 186.0 * em), "{glyphs:?}");
        assert!(close(glyphs[1].1, (1298.0 + 55.0) * em), "{glyphs:?}");
        assert!(width > glyphs[1].1);
    }
}
