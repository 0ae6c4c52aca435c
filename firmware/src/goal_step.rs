//! How far the board lets a joint's goal move in one bus cycle when the goal comes from the host
//! at run time rather than from a checked table: a streamed setpoint (`Controller::setpoint`) and
//! the torque bias after a stiffness change while walking (`Controller::set_stiffness`). The bound
//! is what the servo itself can move in one cycle: its no-load speed
//! ([`dynamixel::ServoModel::no_load_speed_rpm`], the one owner of the servo's constants) times the
//! cycle period, in ticks, rounded down, at least 1 tick. A goal further away is approached by at
//! most that much per cycle (rate-limited), never jumped to.

use dynamixel::ServoModel;

/// The largest goal change per bus cycle, ticks: no-load speed x cycle period, rounded down, at
/// least 1. E.g. an MX-28 (55 rev/min) at 100 Hz: 55 x 4096 / 60 / 100 = 37.55 -> 37 ticks.
pub fn max_step_ticks(model: ServoModel, cycle_hz: u16) -> i32 {
    let ticks_per_s = model.no_load_speed_rpm() * model.ticks_per_rev() as f32 / 60.0;
    let step = ticks_per_s / f32::from(cycle_hz.max(1));
    // `as` truncates toward zero: rounding down for a positive step.
    (step as i32).max(1)
}

/// One cycle's goal on the way from `from` to `to`, moving at most `step` ticks (`step` >= 1).
/// Returns the goal and whether the bound cut the move short.
pub fn toward(from: i32, to: i32, step: i32) -> (i32, bool) {
    let step = step.max(1);
    let d = to - from;
    if d.abs() <= step {
        (to, false)
    } else {
        (from + step * d.signum(), true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_is_the_no_load_speed_times_the_cycle_by_hand() {
        // MX-28: 55 rev/min = 5.7596 rad/s; x 0.01 s = 0.057596 rad; x 4096 / 2 pi = 651.90
        // ticks/rad -> 37.55 ticks -> 37.
        assert_eq!(max_step_ticks(ServoModel::Mx28, 100), 37);
        // MX-64: 63 rev/min = 6.5973 rad/s; x 0.01 s x 651.90 = 43.008 -> 43.
        assert_eq!(max_step_ticks(ServoModel::Mx64, 100), 43);
        // MX-28 at 200 Hz: half a 100 Hz step, 18.77 -> 18; at 50 Hz: 75.09 -> 75.
        assert_eq!(max_step_ticks(ServoModel::Mx28, 200), 18);
        assert_eq!(max_step_ticks(ServoModel::Mx28, 50), 75);
        // 1 kHz on an MX-28: 3.75 -> 3. Absurdly fast cycles still move: at least 1 tick.
        assert_eq!(max_step_ticks(ServoModel::Mx28, 1000), 3);
        assert_eq!(max_step_ticks(ServoModel::Mx28, 60_000), 1);
    }

    #[test]
    fn toward_moves_at_most_the_step_and_says_when_it_cut() {
        assert_eq!(toward(2000, 2010, 37), (2010, false));
        assert_eq!(toward(2000, 2037, 37), (2037, false));
        assert_eq!(toward(2000, 2038, 37), (2037, true));
        assert_eq!(toward(2000, 1000, 37), (1963, true));
        assert_eq!(toward(2000, 2000, 37), (2000, false));
        assert_eq!(toward(2000, 2005, 0), (2001, true));
    }
}
