//! The bitmap backend every plot draws on: plotters' `BitMapBackend` with its text drawn here, and
//! the PNG written here.
//!
//! Why: plotters 0.3.7 draws `ab_glyph` text at the pen position without each glyph's left side
//! bearing (it places the glyph's pixel box, not its origin), so narrow glyphs slide left into
//! their neighbours ("CTr" reads "C Tr" with the r under the T's bar). Here every glyph is placed
//! at its origin, sub-pixel, with the font's kerning; anchors, rotation and the vertical placement
//! are plotters' own, so layouts stay as plotters measures them. Only DejaVu Sans is registered
//! (see [`super::style`]), so every family is drawn with it.
//!
//! The PNG of [`Bitmap::new`] is written here with the `png` crate, byte for byte as plotters'
//! image encoder (`image` 0.24.9, plotters' `bitmap_encoder` feature) wrote it: the same encoder
//! settings (RGB, 8 bits, fast compression, adaptive filter). That encoder brought `image` and its
//! JPEG decoder into the demo's build (about 17 s of CPU) to write PNGs only.

use std::fs::File;
use std::io::{BufWriter, ErrorKind};
use std::path::Path;

use ab_glyph::{Font, FontRef, ScaleFont, point};
use plotters::backend::BitMapBackend;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};
use plotters_bitmap::BitMapBackendError;

/// An RGB image (3 bytes a pixel, rows top to bottom) drawn by plotters' `BitMapBackend`, whose
/// text keeps the glyphs' side bearings: a PNG file or a buffer of the caller's.
pub struct Bitmap<'a> {
    size: (u32, u32),
    pixels: Pixels<'a>,
}

enum Pixels<'a> {
    /// Written to `path` as PNG on `present`, and on drop unless presented since the last
    /// drawing (as plotters' `BitMapBackend::new`; an error there is lost).
    File {
        path: &'a Path,
        rgb: Vec<u8>,
        saved: bool,
    },
    Buffer(&'a mut [u8]),
}

impl std::fmt::Debug for Bitmap<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Bitmap {:?}", self.size)
    }
}

impl<'a> Bitmap<'a> {
    /// An image written to `path` as PNG on `present`; `path` must end in `.png` (any case; another
    /// name is refused there, and no file is written).
    pub fn new<P: AsRef<Path> + ?Sized>(path: &'a P, (w, h): (u32, u32)) -> Self {
        Self {
            size: (w, h),
            pixels: Pixels::File {
                path: path.as_ref(),
                rgb: vec![0; 3 * w as usize * h as usize],
                saved: false,
            },
        }
    }

    /// An image in `buf` (RGB, 3 bytes a pixel, rows top to bottom).
    pub fn with_buffer(buf: &'a mut [u8], size: (u32, u32)) -> Self {
        // A buffer too small for `size` panics, as it does in plotters.
        drop(BitMapBackend::with_buffer(buf, size));
        Self {
            size,
            pixels: Pixels::Buffer(buf),
        }
    }

    /// Plotters' backend over the pixels, for one drawing call (it holds nothing between calls).
    fn backend(&mut self) -> BitMapBackend<'_> {
        let buf = match &mut self.pixels {
            Pixels::File { rgb, .. } => rgb.as_mut_slice(),
            Pixels::Buffer(buf) => buf,
        };
        BitMapBackend::with_buffer(buf, self.size)
    }
}

impl Drop for Bitmap<'_> {
    fn drop(&mut self) {
        if let Pixels::File { saved: false, .. } = self.pixels {
            let _ = self.present();
        }
    }
}

/// Writes `rgb` to `path` as `image` 0.24.9 saves an RGB buffer to a `.png` path (`save_buffer`:
/// a `BufWriter` on the created file, `PngEncoder::new`: `CompressionType::Fast` and
/// `FilterType::Adaptive`, its defaults), so the file is the same byte for byte.
fn write_png(path: &Path, (w, h): (u32, u32), rgb: &[u8]) -> std::io::Result<()> {
    let png = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !png {
        return Err(std::io::Error::new(
            ErrorKind::InvalidInput,
            format!(
                "{}: plots are written as PNG, to a .png name",
                path.display()
            ),
        ));
    }
    let io = |e: png::EncodingError| match e {
        png::EncodingError::IoError(e) => e,
        e => std::io::Error::other(e),
    };
    let mut encoder = png::Encoder::new(BufWriter::new(File::create(path)?), w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(png::FilterType::Sub);
    encoder.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
    let mut writer = encoder.write_header().map_err(io)?;
    writer.write_image_data(rgb).map_err(io)?;
    // The end chunk and the flush, whose errors `image` lost.
    writer.finish().map_err(io)
}

type Result<E> = std::result::Result<(), DrawingErrorKind<E>>;

impl DrawingBackend for Bitmap<'_> {
    type ErrorType = BitMapBackendError;

    fn get_size(&self) -> (u32, u32) {
        self.size
    }
    fn ensure_prepared(&mut self) -> Result<Self::ErrorType> {
        if let Pixels::File { saved, .. } = &mut self.pixels {
            *saved = false;
        }
        Ok(())
    }
    fn present(&mut self) -> Result<Self::ErrorType> {
        let size = self.size;
        if let Pixels::File { path, rgb, saved } = &mut self.pixels {
            write_png(path, size, rgb)
                .map_err(|e| DrawingErrorKind::DrawingError(BitMapBackendError::IOError(e)))?;
            *saved = true;
        }
        Ok(())
    }
    fn draw_pixel(&mut self, p: BackendCoord, c: BackendColor) -> Result<Self::ErrorType> {
        self.backend().draw_pixel(p, c)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<Self::ErrorType> {
        self.backend().draw_line(from, to, style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        ul: BackendCoord,
        br: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<Self::ErrorType> {
        self.backend().draw_rect(ul, br, style, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<Self::ErrorType> {
        self.backend().draw_path(path, style)
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        centre: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<Self::ErrorType> {
        self.backend().draw_circle(centre, radius, style, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<Self::ErrorType> {
        self.backend().fill_polygon(vert, style)
    }
    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        (w, h): (u32, u32),
        src: &[u8],
    ) -> Result<Self::ErrorType> {
        self.backend().blit_bitmap(pos, (w, h), src)
    }

    fn draw_text<T: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        pos: BackendCoord,
    ) -> Result<Self::ErrorType> {
        let colour = style.color();
        if colour.alpha == 0.0 {
            return Ok(());
        }
        // Anchor offsets from plotters' own layout box (as its default `draw_text`).
        let ((min_x, min_y), (max_x, max_y)) = style
            .layout_box(text)
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let (width, height) = (max_x - min_x, max_y - min_y);
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let trans = style.transform();
        let (w, h) = self.get_size();
        let size = style.size() as f32;
        let font = FontRef::try_from_slice(dejavu::sans::regular())
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let scaled = font.as_scaled(size);
        // One backend over the pixels for the whole text, not one per pixel drawn.
        let mut backend = self.backend();
        let mut pen = 0.0f32;
        let mut prev = None;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = prev {
                pen += scaled.kern(p, id);
            }
            prev = Some(id);
            // Baseline at half the size below the top, where plotters puts it.
            let glyph = id.with_scale_and_position(size, point(pen, size / 2.0));
            pen += scaled.h_advance(id);
            let Some(outline) = font.outline_glyph(glyph) else {
                continue;
            };
            let b = outline.px_bounds();
            let (gx, gy) = (b.min.x as i32, b.min.y as i32);
            let mut result = Ok(());
            outline.draw(|x, y, coverage| {
                if result.is_err() || coverage <= 0.0 {
                    return;
                }
                let (x, y) =
                    trans.transform(gx + x as i32 + dx - min_x, gy + y as i32 + dy - min_y);
                let (x, y) = (pos.0 + x, pos.1 + y);
                if x >= 0 && y >= 0 && (x as u32) < w && (y as u32) < h {
                    let c = BackendColor {
                        alpha: colour.alpha * f64::from(coverage.min(1.0)),
                        rgb: colour.rgb,
                    };
                    result = backend.draw_pixel((x, y), c);
                }
            });
            result?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;

    fn draw<DB: DrawingBackend>(root: DrawingArea<DB, plotters::coord::Shift>) {
        crate::style::register_font();
        root.fill(&WHITE).unwrap();
        root.draw(&Circle::new((30, 20), 12, RED.filled())).unwrap();
        root.draw(&Text::new("CTr", (5, 5), ("sans-serif", 14)))
            .unwrap();
        root.present().unwrap();
    }

    fn decode(path: &Path) -> (png::OutputInfo, Vec<u8>) {
        let mut rd = png::Decoder::new(File::open(path).unwrap())
            .read_info()
            .unwrap();
        let mut rgb = vec![0; rd.output_buffer_size()];
        let info = rd.next_frame(&mut rgb).unwrap();
        (info, rgb)
    }

    #[test]
    fn the_png_holds_the_pixels_drawn() {
        let size = (64, 40);
        let mut rgb = vec![0; 3 * 64 * 40];
        draw(Bitmap::with_buffer(&mut rgb, size).into_drawing_area());
        let d = tempfile::tempdir().unwrap();
        let path = d.path().join("p.PNG");
        draw(Bitmap::new(&path, size).into_drawing_area());
        let (info, png) = decode(&path);
        assert_eq!((info.width, info.height), size);
        assert_eq!(
            (info.color_type, info.bit_depth),
            (png::ColorType::Rgb, png::BitDepth::Eight)
        );
        assert_eq!(png, rgb);
    }

    #[test]
    fn a_bitmap_dropped_unpresented_is_still_written() {
        let d = tempfile::tempdir().unwrap();
        let path = d.path().join("p.png");
        let root = Bitmap::new(&path, (8, 4)).into_drawing_area();
        root.fill(&BLUE).unwrap();
        drop(root);
        let (_, rgb) = decode(&path);
        assert_eq!(&rgb[..3], &[0, 0, 255]);
    }

    #[test]
    fn a_failed_write_is_an_error_and_only_a_png_name_is_written() {
        let d = tempfile::tempdir().unwrap();
        let missing = d.path().join("no-such-folder/p.png");
        let root = Bitmap::new(&missing, (8, 4)).into_drawing_area();
        root.fill(&WHITE).unwrap();
        let e = root.present().unwrap_err().to_string();
        assert!(e.contains("NotFound"), "{e}");
        for name in ["p.jpg", "p"] {
            let path = d.path().join(name);
            let root = Bitmap::new(&path, (8, 4)).into_drawing_area();
            let e = root.present().unwrap_err().to_string();
            assert!(e.contains(&path.display().to_string()), "{e}");
            assert!(!path.exists(), "{name}");
        }
    }
}
