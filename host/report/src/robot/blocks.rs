//! Uneven ground (`planner::terrain::Blocks`) in the three views: from above, every block in the
//! plot as a square shaded by its height (light low, dark high); from the side and the front,
//! the field's silhouette (the highest top of each column, or row, of cells), as one would see
//! the blocks from far to the robot's right or in front of it. Gaps show the floor.

use plotters::prelude::*;

use planner::terrain::Blocks;

use super::view::{Chart, GROUND, View};

/// Shade of a top at `h` over the field's range: the ground colour, lighter for low blocks.
fn shade(b: &Blocks, h: f64) -> RGBColor {
    let f = if b.max_height_m > 0.0 {
        (h / b.max_height_m).clamp(0.0, 1.0)
    } else {
        1.0
    };
    let mix = |c: u8| (255.0 - (255.0 - f64::from(c)) * (0.25 + 0.75 * f)).round() as u8;
    RGBColor(mix(GROUND.0), mix(GROUND.1), mix(GROUND.2))
}

/// Draws `b` in `view` on `chart` (axes in mm).
pub(super) fn draw_blocks<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    view: View,
    b: &Blocks,
) -> Result<(), String> {
    let (xr, yr) = (chart.x_range(), chart.y_range());
    let mm = |m: f64| m * 1e3;
    let half = b.size_m / 2.0;
    let cells = b.cells();
    let e = |e: &dyn std::fmt::Display| e.to_string();
    match view {
        View::Top => {
            let squares = cells.iter().filter_map(|c| {
                let [x, y] = c.centre_xy_m;
                let (x0, x1, y0, y1) = (mm(x - half), mm(x + half), mm(y - half), mm(y + half));
                let seen = x1 > xr.start && x0 < xr.end && y1 > yr.start && y0 < yr.end;
                let top = c.top_m?;
                seen.then(|| Rectangle::new([(x0, y0), (x1, y1)], shade(b, top).filled()))
            });
            chart.draw_series(squares).map_err(|x| e(&x))?;
        }
        View::Side | View::Front => {
            let (nx, ny) = b.cells_xy();
            // Silhouette: the highest top over the cells that share a column (side) or row (front).
            let (n, along, lo) = match view {
                View::Side => (nx, ny, planner::terrain::FIELD_X_M.0),
                View::Top | View::Front => (ny, nx, planner::terrain::FIELD_Y_M.0),
            };
            let mut pts = Vec::with_capacity(2 * n);
            for k in 0..n {
                let top = (0..along)
                    .map(|m| match view {
                        View::Side => b.cell(k, m),
                        View::Top | View::Front => b.cell(m, k),
                    })
                    .map(|c| c.top_m.unwrap_or(b.floor_m()))
                    .fold(b.floor_m(), f64::max);
                let h0 = lo + k as f64 * b.size_m;
                pts.push((mm(h0), mm(top)));
                pts.push((mm(h0 + b.size_m), mm(top)));
            }
            let pts: Vec<(f64, f64)> = pts
                .into_iter()
                .map(|(h, v)| (h.clamp(xr.start, xr.end), v.clamp(yr.start, yr.end)))
                .collect();
            chart
                .draw_series(std::iter::once(PathElement::new(
                    pts,
                    GROUND.stroke_width(2),
                )))
                .map_err(|x| e(&x))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn higher_blocks_are_darker() {
        let b = Blocks::DEFAULT;
        let (low, high) = (shade(&b, 0.0), shade(&b, b.max_height_m));
        assert!(low.0 > high.0 && low.1 > high.1 && low.2 > high.2);
        // The highest block is the ground colour itself.
        assert_eq!(high, GROUND);
    }
}
