//! The line `dbot run` ends with. The board's states and directions print as protocol words them
//! (`RunState::name`, `Direction::name`: never Rust debug text).

/// What a finished walk did, from the board's counters before and after it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkReport {
    /// Whole steps completed.
    pub steps: u32,
    /// Board time from the play command to standing, s.
    pub seconds: f64,
    /// Bus cycles that missed their deadline during the walk.
    pub overruns: u32,
    /// Bus replies that timed out or failed their CRC during the walk.
    pub bus_errors: u32,
}

impl WalkReport {
    /// The closing line of `dbot run`.
    pub fn line(&self) -> String {
        let steps = match self.steps {
            1 => "1 step".to_owned(),
            n => format!("{n} steps"),
        };
        format!(
            "done: {steps} walked in {:.2} s (board clock); {} overrun(s), {} bus error(s), no fault; the robot stands",
            self.seconds, self.overruns, self.bus_errors
        )
    }
}

#[cfg(test)]
mod tests {
    use protocol::{Direction, RunState};

    use super::*;

    #[test]
    fn the_closing_line_names_steps_time_and_counters() {
        let r = WalkReport {
            steps: 10,
            seconds: 12.5,
            overruns: 0,
            bus_errors: 2,
        };
        assert_eq!(
            r.line(),
            "done: 10 steps walked in 12.50 s (board clock); 0 overrun(s), 2 bus error(s), no fault; the robot stands"
        );
        let one = WalkReport { steps: 1, ..r };
        assert!(
            one.line().starts_with("done: 1 step walked"),
            "{}",
            one.line()
        );
    }

    #[test]
    fn states_read_as_the_firmware_names_them() {
        let want = [
            (RunState::Idle, "Idle (torque off)"),
            (RunState::Standing, "Standing"),
            (RunState::Ramping, "Ramping (to the first slice)"),
            (RunState::Walking, "Walking"),
            (RunState::Stopping, "Stopping (at the end of the step)"),
            (RunState::Streaming, "Streaming"),
            (RunState::Fault, "Fault (torque off)"),
            (
                RunState::Boot,
                "Boot (finding the servos, reading the gait store)",
            ),
        ];
        for (s, name) in want {
            assert_eq!(s.name(), name);
        }
        assert_eq!(Direction::Backward.name(), "backward");
        assert_eq!(Direction::Forward.name(), "forward");
    }
}
