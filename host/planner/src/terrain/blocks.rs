//! [`Blocks`]: uneven ground of square blocks with seeded random heights (and optional gaps), as
//! FlyGym's blocks and gapped terrains. The height of a cell is a pure function of the seed and
//! the cell's index (SplitMix64 of both), so any consumer (the MJCF export, a drawing, a test)
//! computes the same field without sharing state, on any machine.

/// Where the blocks lie, m (world frame at the robot's start, REP-103): the robot starts near
/// the origin facing +x. Outside this rectangle, and in a gap, the floor is [`Blocks::floor_m`].
pub const FIELD_X_M: (f64, f64) = (-0.6, 2.4);
/// Sideways extent of the field, m.
pub const FIELD_Y_M: (f64, f64) = (-0.6, 0.6);
/// Depth of a gap below the lowest block top (0 m), m: deeper than any step height of table 1
/// (0.05-0.09 m) would still catch a leg, so a foot stepping into a gap finds no support.
pub const GAP_DEPTH_M: f64 = 0.1;

/// A field of blocks: tops at heights uniform in [0, `max_height_m`], `size_m` square cells,
/// each cell a gap with probability `gaps`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Blocks {
    pub seed: u64,
    pub max_height_m: f64,
    pub size_m: f64,
    /// Fraction of cells left out, in [0, 1).
    pub gaps: f64,
}

/// One cell of the field: its centre and top.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    pub centre_xy_m: [f64; 2],
    /// Height of the block's top, m; `None` for a gap.
    pub top_m: Option<f64>,
}

/// SplitMix64's output function (Steele, Lea and Flood 2014; the generator behind Java's
/// `SplittableRandom` and the seeding of xoshiro): a bijective 64-bit mixer.
pub fn splitmix64(state: u64) -> u64 {
    let mut z = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform number in [0, 1) from 53 bits of `x`.
fn unit(x: u64) -> f64 {
    (x >> 11) as f64 / (1u64 << 53) as f64
}

impl Blocks {
    /// Defaults for a bare `blocks`: seed 0, tops up to 10 mm, 50 mm cells, no gaps. ESTIMATE:
    /// chosen against the robot's table-1 step heights (50-90 mm) and its 5 mm feet, so the
    /// ground is uneven under every foot yet a step clears it.
    pub const DEFAULT: Blocks = Blocks {
        seed: 0,
        max_height_m: 0.01,
        size_m: 0.05,
        gaps: 0.0,
    };

    /// Cells along x and y.
    pub fn cells_xy(&self) -> (usize, usize) {
        let n = |(lo, hi): (f64, f64)| ((hi - lo) / self.size_m).ceil() as usize;
        (n(FIELD_X_M), n(FIELD_Y_M))
    }

    /// The cell at grid index (`i` along x, `j` along y).
    pub fn cell(&self, i: usize, j: usize) -> Cell {
        let key = splitmix64(self.seed ^ splitmix64(((i as u64) << 32) | j as u64));
        let gap = self.gaps > 0.0 && unit(splitmix64(key)) < self.gaps;
        Cell {
            centre_xy_m: [
                FIELD_X_M.0 + (i as f64 + 0.5) * self.size_m,
                FIELD_Y_M.0 + (j as f64 + 0.5) * self.size_m,
            ],
            top_m: (!gap).then(|| unit(key) * self.max_height_m),
        }
    }

    /// Every cell, x-major.
    pub fn cells(&self) -> Vec<Cell> {
        let (nx, ny) = self.cells_xy();
        (0..nx)
            .flat_map(|i| (0..ny).map(move |j| (i, j)))
            .map(|(i, j)| self.cell(i, j))
            .collect()
    }

    /// Height of the floor below the blocks (in gaps and outside the field), m.
    pub fn floor_m(&self) -> f64 {
        -GAP_DEPTH_M
    }

    /// The ground's height at world (`x`, `y`), m.
    pub fn height_at(&self, x: f64, y: f64) -> f64 {
        let (nx, ny) = self.cells_xy();
        let fi = ((x - FIELD_X_M.0) / self.size_m).floor();
        let fj = ((y - FIELD_Y_M.0) / self.size_m).floor();
        if fi < 0.0 || fj < 0.0 || fi >= nx as f64 || fj >= ny as f64 {
            return self.floor_m();
        }
        self.cell(fi as usize, fj as usize)
            .top_m
            .unwrap_or(self.floor_m())
    }

    /// Distance from (`x`, `y`) to the nearest cell edge, m (a foot this close may rest on an
    /// edge rather than a top).
    pub fn edge_distance(&self, x: f64, y: f64) -> f64 {
        let d = |v: f64, lo: f64| {
            let r = (v - lo).rem_euclid(self.size_m);
            r.min(self.size_m - r)
        };
        d(x, FIELD_X_M.0).min(d(y, FIELD_Y_M.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_the_reference_sequence() {
        // The reference generator's first outputs from state 1234567 (the test vector of
        // Vigna's splitmix64.c, as in numpy's and Rust rand_core's ports): each output is the
        // mixer applied to the state advanced by the golden gamma.
        let gamma = 0x9E37_79B9_7F4A_7C15u64;
        let s0 = 1_234_567u64;
        assert_eq!(splitmix64(s0), 6_457_827_717_110_365_317);
        assert_eq!(
            splitmix64(s0.wrapping_add(gamma)),
            3_203_168_211_198_807_973
        );
    }

    #[test]
    fn heights_lie_in_range_and_depend_on_the_seed() {
        let a = Blocks::DEFAULT;
        let b = Blocks { seed: 1, ..a };
        let tops: Vec<f64> = a.cells().iter().map(|c| c.top_m.unwrap()).collect();
        assert!(tops.iter().all(|&h| (0.0..0.01).contains(&h)));
        // Uniform on [0, 10 mm]: the mean of ~1400 cells is 5 mm within a few standard errors
        // (sigma = 10 mm / sqrt(12 n) = 0.08 mm).
        let mean = tops.iter().sum::<f64>() / tops.len() as f64;
        assert!((mean - 0.005).abs() < 0.0004, "mean {mean}");
        assert_eq!(a.cells(), Blocks::DEFAULT.cells());
        assert_ne!(a.cells(), b.cells());
    }

    #[test]
    fn gaps_take_their_fraction_and_drop_to_the_floor() {
        let g = Blocks {
            gaps: 0.25,
            ..Blocks::DEFAULT
        };
        let cells = g.cells();
        let gaps = cells.iter().filter(|c| c.top_m.is_none()).count() as f64 / cells.len() as f64;
        // Binomial: sigma = sqrt(0.25 * 0.75 / 1440) = 0.011.
        assert!((gaps - 0.25).abs() < 0.04, "gap fraction {gaps}");
        let c = cells.iter().find(|c| c.top_m.is_none()).unwrap();
        assert_eq!(
            g.height_at(c.centre_xy_m[0], c.centre_xy_m[1]),
            -GAP_DEPTH_M
        );
    }

    #[test]
    fn height_at_reads_the_cell_under_the_point() {
        let b = Blocks::DEFAULT;
        let c = b.cell(3, 5);
        // Cell (3, 5) spans x in [-0.6 + 0.15, -0.6 + 0.2), y in [-0.6 + 0.25, -0.6 + 0.3).
        assert!((c.centre_xy_m[0] - (-0.425)).abs() < 1e-12);
        assert!((c.centre_xy_m[1] - (-0.325)).abs() < 1e-12);
        assert_eq!(b.height_at(-0.449, -0.349), c.top_m.unwrap());
        assert_eq!(b.height_at(10.0, 0.0), -GAP_DEPTH_M);
        // x: 0.155 m into the field is 5 mm past a cell edge; y: 0.27 m is 20 mm past one.
        assert!((b.edge_distance(-0.445, -0.33) - 0.005).abs() < 1e-12);
    }
}
