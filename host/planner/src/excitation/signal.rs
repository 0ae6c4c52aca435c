//! The signals an excitation is made of, as functions of time: a ramp at a set speed (a servo's
//! step, as fast as the excitation allows) and a linear chirp with tapered ends.

use std::f64::consts::PI;

/// A move from `from` to `to` (rad) starting at `start_s`, at `speed` rad/s: `from` before,
/// `to` after `start_s + |to - from| / speed`, a straight line between.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ramp {
    pub from: f64,
    pub to: f64,
    pub start_s: f64,
    pub speed: f64,
}

impl Ramp {
    /// Time the move takes, s.
    pub fn duration_s(&self) -> f64 {
        (self.to - self.from).abs() / self.speed
    }

    /// The angle at `t_s`.
    pub fn at(&self, t_s: f64) -> f64 {
        let d = self.duration_s();
        if d <= 0.0 || t_s >= self.start_s + d {
            return self.to;
        }
        if t_s <= self.start_s {
            return self.from;
        }
        self.from + (self.to - self.from) * (t_s - self.start_s) / d
    }
}

/// A linear chirp about `centre` (rad): `centre + w(t) amplitude sin(2 pi (f0 t + (f1 - f0)
/// t^2 / (2 T)))` for `0 <= t <= T` (t from `start_s`), its frequency sweeping from `f0_hz` to
/// `f1_hz` linearly, `w` a raised-cosine taper over `taper_s` at each end (1 between). The taper
/// changes no sign, so the zero crossings are the sine's: 2 per cycle, at the times the phase
/// passes a multiple of pi.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chirp {
    pub centre: f64,
    pub amplitude_rad: f64,
    pub f0_hz: f64,
    pub f1_hz: f64,
    pub start_s: f64,
    pub duration_s: f64,
    pub taper_s: f64,
}

impl Chirp {
    /// Cycles of the sine over the chirp: `(f0 + f1) T / 2`.
    pub fn cycles(&self) -> f64 {
        0.5 * (self.f0_hz + self.f1_hz) * self.duration_s
    }

    /// The sine's phase (cycles) at `t` s after the start.
    pub fn phase_cycles(&self, t: f64) -> f64 {
        self.f0_hz * t + (self.f1_hz - self.f0_hz) * t * t / (2.0 * self.duration_s)
    }

    /// The instantaneous frequency (Hz) at `t` s after the start.
    pub fn frequency_hz(&self, t: f64) -> f64 {
        self.f0_hz + (self.f1_hz - self.f0_hz) * t / self.duration_s
    }

    /// Largest amplitude (rad) whose chirp stays at or under `speed` rad/s everywhere: the
    /// sine's speed `2 pi f1 A` plus the taper's `pi A / (2 taper)` bound the derivative of
    /// `w A sin`.
    pub fn amplitude_for_speed(speed: f64, f1_hz: f64, taper_s: f64) -> f64 {
        speed / (2.0 * PI * f1_hz + PI / (2.0 * taper_s))
    }

    fn taper(&self, t: f64) -> f64 {
        let edge = t.min(self.duration_s - t);
        if edge >= self.taper_s {
            1.0
        } else {
            0.5 * (1.0 - (PI * edge.max(0.0) / self.taper_s).cos())
        }
    }

    /// The angle at `t_s` (`centre` outside the chirp).
    pub fn at(&self, t_s: f64) -> f64 {
        let t = t_s - self.start_s;
        if !(0.0..=self.duration_s).contains(&t) {
            return self.centre;
        }
        self.centre + self.taper(t) * self.amplitude_rad * (2.0 * PI * self.phase_cycles(t)).sin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ramp_moves_at_its_speed_and_holds_its_ends() {
        let r = Ramp {
            from: 0.2,
            to: -0.1,
            start_s: 1.0,
            speed: 1.5,
        };
        assert!((r.duration_s() - 0.2).abs() < 1e-15);
        assert_eq!(r.at(0.5), 0.2);
        assert_eq!(r.at(2.0), -0.1);
        // Half way in time, half way in angle.
        assert!((r.at(1.1) - 0.05).abs() < 1e-12);
    }

    #[test]
    fn the_chirps_amplitude_bound_is_its_peak_speed() {
        // Finite differences of a tapered chirp at the bound stay under the speed; 10 % more
        // amplitude than the bound at f1 with the taper's slope is not guaranteed to.
        let (speed, f1, taper) = (2.0, 2.0, 0.5);
        let a = Chirp::amplitude_for_speed(speed, f1, taper);
        assert!((a - 2.0 / (4.0 * PI + PI)).abs() < 1e-12);
        let c = Chirp {
            centre: 0.3,
            amplitude_rad: a,
            f0_hz: 0.1,
            f1_hz: f1,
            start_s: 0.0,
            duration_s: 20.0,
            taper_s: taper,
        };
        let h = 1e-4;
        let peak = (0..200_000)
            .map(|k| {
                let t = k as f64 * h;
                ((c.at(t + h) - c.at(t)) / h).abs()
            })
            .fold(0.0, f64::max);
        assert!(peak <= speed, "{peak}");
        // The plain sine's own peak near f1 comes close: the bound is not loose by much.
        assert!(peak > 0.75 * speed, "{peak}");
        assert_eq!(c.at(0.0), 0.3);
        assert!((c.at(20.0) - 0.3).abs() < 1e-12);
    }
}
