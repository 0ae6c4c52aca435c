//! The plots' text keeps each glyph's left side bearing (issue 20: "CTr" was badly kerned because
//! plotters' ab_glyph drawing puts a glyph's pixel box at the pen, dropping the bearing).

use ab_glyph::{Font, FontRef, ScaleFont};
use plotters::prelude::*;
use report::Bitmap;
use report::style::register_font;

/// Leftmost and rightmost columns with ink of `text` drawn at x = 100 on a white image.
fn ink(text: &str, size: f64) -> (i32, i32) {
    register_font();
    let (w, h) = (400u32, 120u32);
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = Bitmap::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.draw(&Text::new(text, (100, 20), ("sans-serif", size)))
            .unwrap();
        root.present().unwrap();
    }
    let cols: Vec<i32> = (0..w as i32)
        .filter(|&x| (0..h as usize).any(|y| rgb[3 * (y * w as usize + x as usize)] < 128))
        .collect();
    (cols[0], *cols.last().unwrap())
}

#[test]
fn glyphs_start_at_their_side_bearing() {
    let font = FontRef::try_from_slice(dejavu::sans::regular()).unwrap();
    let size = 60.0f32;
    let f = font.as_scaled(size);
    for c in ['r', 'C', 'j'] {
        let lsb = f.h_side_bearing(f.glyph_id(c));
        let (left, _) = ink(&c.to_string(), f64::from(size));
        assert!(
            (f64::from(left) - (100.0 + f64::from(lsb))).abs() <= 1.0,
            "{c}: ink starts at {left}, the pen is at 100 and the bearing is {lsb} px"
        );
    }
    // "CTr": the r's ink starts where its origin (after C and T's advances and the pair kerning)
    // plus its bearing puts it.
    let (ids, mut pen) = (['C', 'T', 'r'].map(|c| f.glyph_id(c)), 0.0f32);
    pen += f.h_advance(ids[0]) + f.kern(ids[0], ids[1]);
    pen += f.h_advance(ids[1]) + f.kern(ids[1], ids[2]);
    // The outline's exact right edge; the last column counted as ink is at least half covered.
    let r_right = pen + font.outline(ids[2]).unwrap().bounds.max.x * f.h_scale_factor() - 0.5;
    let (_, right) = ink("CTr", f64::from(size));
    assert!(
        (f64::from(right) - (100.0 + f64::from(r_right))).abs() <= 1.0,
        "CTr ends at {right}, expected {}",
        100.0 + r_right
    );
}
