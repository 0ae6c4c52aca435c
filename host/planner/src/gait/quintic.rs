//! Quintic polynomials through given position, velocity and acceleration at both ends.

/// `p(t)` on `[0, duration]` with prescribed value, slope and curvature at both ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quintic {
    c: [f64; 6],
    duration: f64,
}

impl Quintic {
    /// Through `(p0, v0, a0)` at t = 0 and `(p1, v1, a1)` at t = `duration` (> 0).
    pub fn new(p0: f64, v0: f64, a0: f64, p1: f64, v1: f64, a1: f64, duration: f64) -> Quintic {
        let t = duration;
        let (v0s, v1s, a0s, a1s) = (v0 * t, v1 * t, a0 * t * t, a1 * t * t);
        let d = p1 - p0;
        Quintic {
            c: [
                p0,
                v0s,
                0.5 * a0s,
                10.0 * d - 6.0 * v0s - 4.0 * v1s - 1.5 * a0s + 0.5 * a1s,
                -15.0 * d + 8.0 * v0s + 7.0 * v1s + 1.5 * a0s - a1s,
                6.0 * d - 3.0 * v0s - 3.0 * v1s - 0.5 * a0s + 0.5 * a1s,
            ],
            duration,
        }
    }

    /// Position, velocity and acceleration at time `t`.
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        let s = t / self.duration;
        let c = &self.c;
        let p = c[0] + s * (c[1] + s * (c[2] + s * (c[3] + s * (c[4] + s * c[5]))));
        let dp = c[1] + s * (2.0 * c[2] + s * (3.0 * c[3] + s * (4.0 * c[4] + s * 5.0 * c[5])));
        let ddp = 2.0 * c[2] + s * (6.0 * c[3] + s * (12.0 * c[4] + s * 20.0 * c[5]));
        (p, dp / self.duration, ddp / (self.duration * self.duration))
    }
}
