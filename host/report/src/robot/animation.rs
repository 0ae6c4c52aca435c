//! An animation of stick figures as a GIF: every frame drawn with plotters into an RGB buffer
//! (three views, a caption and the legend), mapped to one fixed palette (the figure's colours,
//! their blends with white for anti-aliased text, and a grey ramp) and encoded with the `gif`
//! crate. A fixed palette keeps the colours exact and the file the same for the same frames.

use std::collections::HashMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use nalgebra::Point3;
use plotters::prelude::*;

use super::figure::{FigureError, StickFigure};
use super::view::{FOOT, GROUND, JOINT, THORAX};
use super::views::{Bounds, Ground, ViewLayout, draw_legend, draw_views};
use crate::style::colour;

/// One frame: the robot and the line shown above it (e.g. "phase 0.25, t = 0.350 s").
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub figure: StickFigure,
    pub caption: String,
}

/// Size of every frame, pixels.
pub const FRAME_SIZE: (u32, u32) = (1200, 420);
/// Height of the legend strip under the views, pixels.
pub(super) const LEGEND_H: u32 = 36;

/// Writes `frames` as a looping GIF to `path`, each shown `delay_ms` (rounded to the GIF's
/// 10 ms unit (nearest), at least 20 ms: browsers slow faster frames down). Every frame shows the same region
/// (the bounds of all frames), so the robot moves and the axes stay.
pub fn write_gif(
    path: &Path,
    frames: &[Frame],
    ground: &Ground,
    delay_ms: u32,
) -> Result<(), FigureError> {
    let bounds = Bounds::around(frames.iter().map(|f| &f.figure), ground);
    encode(path, frames, ground, delay_ms, |_| bounds).map(|_| ())
}

/// Writes `frames` as [`write_gif`] does, but seen by a camera that follows the robot: frame `i`
/// is centred on `centres[i]` (e.g. the thorax) at one scale for the whole animation
/// ([`Bounds::following`]), so a long walk keeps the robot large and the axes move under it.
/// Returns where each frame's views put the world.
pub fn write_gif_following(
    path: &Path,
    frames: &[Frame],
    centres: &[Point3<f64>],
    ground: &Ground,
    delay_ms: u32,
) -> Result<Vec<Vec<ViewLayout>>, FigureError> {
    if centres.len() != frames.len() {
        return Err(FigureError::Draw {
            path: path.display().to_string(),
            reason: format!(
                "{} frames but {} camera centres",
                frames.len(),
                centres.len()
            ),
        });
    }
    let figures: Vec<&StickFigure> = frames.iter().map(|f| &f.figure).collect();
    let bounds = Bounds::following(&figures, centres, ground);
    encode(path, frames, ground, delay_ms, |i| bounds[i])
}

fn encode(
    path: &Path,
    frames: &[Frame],
    ground: &Ground,
    delay_ms: u32,
    bounds_of: impl Fn(usize) -> Bounds,
) -> Result<Vec<Vec<ViewLayout>>, FigureError> {
    let err = |reason: String| FigureError::Draw {
        path: path.display().to_string(),
        reason,
    };
    let mut layouts = Vec::with_capacity(frames.len());
    let (w, h) = FRAME_SIZE;
    let palette = palette();
    let flat: Vec<u8> = palette.iter().flatten().copied().collect();
    let file = File::create(path).map_err(|e| err(e.to_string()))?;
    let mut enc = gif::Encoder::new(BufWriter::new(file), w as u16, h as u16, &flat)
        .map_err(|e| err(e.to_string()))?;
    enc.set_repeat(gif::Repeat::Infinite)
        .map_err(|e| err(e.to_string()))?;
    let mut cache: HashMap<[u8; 3], u8> = HashMap::new();
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    for (i, f) in frames.iter().enumerate() {
        {
            let root = crate::Bitmap::with_buffer(&mut rgb, (w, h)).into_drawing_area();
            root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
            let (views, legend) = root.split_vertically(h - LEGEND_H);
            layouts.push(
                draw_views(&views, &f.figure, ground, &bounds_of(i), &f.caption).map_err(err)?,
            );
            draw_legend(&legend).map_err(err)?;
            root.present().map_err(|e| err(e.to_string()))?;
        }
        // Most pixels repeat their left neighbour (background, lines): look up only changes.
        let mut last = ([255u8; 3], nearest(&palette, [255; 3]));
        let indices: Vec<u8> = rgb
            .chunks_exact(3)
            .map(|p| {
                let c = [p[0], p[1], p[2]];
                if c != last.0 {
                    last = (c, *cache.entry(c).or_insert_with(|| nearest(&palette, c)));
                }
                last.1
            })
            .collect();
        let frame = gif::Frame {
            width: w as u16,
            height: h as u16,
            delay: (delay_ms.saturating_add(5) / 10).max(2) as u16,
            buffer: std::borrow::Cow::Owned(indices),
            ..gif::Frame::default()
        };
        enc.write_frame(&frame).map_err(|e| err(e.to_string()))?;
    }
    Ok(layouts)
}

/// White, a 32-step grey ramp, and every colour of the drawing blended with white in quarters.
pub(super) fn palette() -> Vec<[u8; 3]> {
    let mut p: Vec<[u8; 3]> = (0..32u16)
        .map(|k| {
            let g = (k * 255 / 31) as u8;
            [g, g, g]
        })
        .collect();
    let base = [THORAX, GROUND, FOOT, JOINT, colour(0), colour(1)]
        .into_iter()
        .chain((2..8).map(colour));
    for RGBColor(r, g, b) in base {
        for q in 1..=4u16 {
            let mix = |c: u8| (255 - (255 - u16::from(c)) * q / 4) as u8;
            p.push([mix(r), mix(g), mix(b)]);
        }
    }
    p.dedup();
    p.truncate(256);
    p
}

fn nearest(palette: &[[u8; 3]], c: [u8; 3]) -> u8 {
    let d = |p: &[u8; 3]| {
        (0..3)
            .map(|i| (i32::from(p[i]) - i32::from(c[i])).pow(2))
            .sum::<i32>()
    };
    palette
        .iter()
        .enumerate()
        .min_by_key(|(_, p)| d(p))
        .map_or(0, |(i, _)| i as u8)
}
