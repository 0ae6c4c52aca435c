//! Stuck-servo detection: a joint whose goal moves while its output does not.
//!
//! A plain following error |present - goal| cannot tell a jam from normal walking: the goal is the
//! planned angle plus the torque bias (torque / stiffness), which a loaded servo does not reach by
//! design, and every position-controlled servo lags its goal (about 35 ms for an MX-28 at P = 850,
//! dynamixel::sim::physics). So the rule looks at *ranges* over a window instead of differences:
//!
//! > over a window of `window` samples, the goal moved over more than `goal_range` ticks, the
//! > planned angle (the goal without the torque bias) did too, and the present position moved over
//! > at most `present_range` ticks.
//!
//! Requiring the planned angle to move as well means a change of load alone (a joint held still in
//! stance while the torque on it shifts moves only the bias part of the goal) never fires; requiring
//! the goal to move means a robot lifted off the ground (no load, the servo follows the goal, not
//! the planned angle) never fires on a bias that cancels the planned motion either.
//!
//! Windows are consecutive blocks of `window` samples per joint (a sample = one bus cycle that
//! wrote the goal with torque on and got a usable reply from that servo); the rule is checked at the
//! end of each block, which then starts anew. A jam is thus reported within `2 * window - 1`
//! samples, and the detector needs six numbers per joint instead of a history of the last `window`
//! samples. Anything that is not such a sample (torque off, a state that does not drive goals) resets
//! every window: see [`StuckDetector::reset`].

use super::SafeReason;

/// Thresholds of the rule (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StuckLimits {
    /// Samples per window (0 switches detection off).
    pub window: u16,
    /// The goal and the planned angle must each move over more than this, ticks.
    pub goal_range: u16,
    /// The present position moved over at most this, ticks.
    pub present_range: u16,
}

impl Default for StuckLimits {
    /// 50 samples (0.5 s at the default 100 Hz), 40 ticks (3.5 deg), 2 ticks (0.18 deg).
    ///
    /// - 0.5 s is about 14 time constants of the servo's position loop: a servo that is not stuck
    ///   has long followed a goal that moved 40 ticks (a saturated MX-28 still turns at its no-load
    ///   speed, about 37 ticks per 10 ms cycle), so its present position moves over tens of ticks,
    ///   not 2.
    /// - 40 ticks is above the bias swing of a joint held still while its load changes (0.3 N m on
    ///   8.4 N m/rad is 0.036 rad = 23 ticks in the test gaits), and well below the swing of the
    ///   joints that walk (the tripod's joints move 0.3 to 1 rad per step: 200 to 650 ticks), so a
    ///   jammed walking joint is caught while a nearly still one is simply not checked.
    /// - 2 ticks: a real MX reads its encoder to within a tick or two only when it is not moving;
    ///   a jammed output still shows that +-1 tick of noise.
    fn default() -> Self {
        Self {
            window: 50,
            goal_range: 40,
            present_range: 2,
        }
    }
}

/// Range (min, max) of one signal within the current window.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Span {
    min: i32,
    max: i32,
}

impl Span {
    const EMPTY: Span = Span {
        min: i32::MAX,
        max: i32::MIN,
    };

    fn add(&mut self, v: i32) {
        self.min = self.min.min(v);
        self.max = self.max.max(v);
    }

    fn range(&self) -> i32 {
        self.max.saturating_sub(self.min).max(0)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Window {
    samples: u16,
    goal: Span,
    planned: Span,
    present: Span,
}

impl Window {
    const EMPTY: Window = Window {
        samples: 0,
        goal: Span::EMPTY,
        planned: Span::EMPTY,
        present: Span::EMPTY,
    };
}

/// The rule of the module doc for `N` joints.
#[derive(Debug, Clone)]
pub struct StuckDetector<const N: usize> {
    limits: StuckLimits,
    windows: [Window; N],
}

impl<const N: usize> StuckDetector<N> {
    pub fn new(limits: StuckLimits) -> Self {
        Self {
            limits,
            windows: [Window::EMPTY; N],
        }
    }

    pub fn limits(&self) -> StuckLimits {
        self.limits
    }

    /// One sample of the servo of `joint` (bus `id`), all in ticks: the goal written this cycle, the
    /// planned angle it came from (the goal without the torque bias) and the present position read.
    /// Returns the fault when a window ends that meets the rule.
    pub fn record(
        &mut self,
        joint: usize,
        id: u8,
        goal: i32,
        planned: i32,
        present: i32,
    ) -> Option<SafeReason> {
        let l = self.limits;
        if l.window == 0 {
            return None;
        }
        let w = self.windows.get_mut(joint)?;
        w.samples += 1;
        w.goal.add(goal);
        w.planned.add(planned);
        w.present.add(present);
        if w.samples < l.window {
            return None;
        }
        let done = *w;
        *w = Window::EMPTY;
        let limit = i32::from(l.goal_range);
        let stuck = done.goal.range() > limit
            && done.planned.range() > limit
            && done.present.range() <= i32::from(l.present_range);
        stuck.then(|| SafeReason::ServoStuck {
            joint: joint as u8,
            id,
            goal_range: done.goal.range().min(i32::from(u16::MAX)) as u16,
            present_range: done.present.range() as u16,
        })
    }

    /// Starts every window anew: torque went off, or goals are not driven (a sample is only
    /// meaningful while the servo is meant to follow).
    pub fn reset(&mut self) {
        self.windows = [Window::EMPTY; N];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Small numbers so every window can be checked by eye: 5 samples, goal over more than 4
    /// ticks, present over at most 1.
    const L: StuckLimits = StuckLimits {
        window: 5,
        goal_range: 4,
        present_range: 1,
    };

    fn stuck(goal_range: u16, present_range: u16) -> Option<SafeReason> {
        Some(SafeReason::ServoStuck {
            joint: 2,
            id: 3,
            goal_range,
            present_range,
        })
    }

    /// Feeds (goal, planned, present) samples to joint 2 (ID 3); the sample numbers (1-based) at
    /// which the detector fired and what it said.
    fn feed(d: &mut StuckDetector<4>, samples: &[(i32, i32, i32)]) -> Vec<(usize, SafeReason)> {
        samples
            .iter()
            .enumerate()
            .filter_map(|(i, &(g, p, x))| d.record(2, 3, g, p, x).map(|r| (i + 1, r)))
            .collect()
    }

    #[test]
    fn a_goal_that_moves_while_the_output_holds_fires_at_the_end_of_the_window() {
        let mut d = StuckDetector::<4>::new(L);
        // Goal 100..108 (range 8 > 4), planned the same minus a bias of 3, present 500/501 (range 1).
        let s = [
            (100, 97, 500),
            (102, 99, 500),
            (104, 101, 501),
            (106, 103, 500),
            (108, 105, 500),
        ];
        assert_eq!(feed(&mut d, &s), vec![(5, stuck(8, 1).unwrap())]);
    }

    #[test]
    fn a_jam_in_the_middle_of_a_window_is_reported_at_the_end_of_the_next_one() {
        let mut d = StuckDetector::<4>::new(L);
        // Samples 1-2 follow (present moves 10 ticks), then the output jams at 520 while the goal
        // goes on: window 1 (samples 1-5) has a present range of 10, window 2 (6-10) of 0.
        let s: Vec<(i32, i32, i32)> = (0..10)
            .map(|k| (500 + 10 * k, 500 + 10 * k, 500 + 10 * k.min(2)))
            .collect();
        assert_eq!(feed(&mut d, &s), vec![(10, stuck(40, 0).unwrap())]);
    }

    #[test]
    fn a_load_change_alone_or_a_bias_that_cancels_the_plan_never_fires() {
        let mut d = StuckDetector::<4>::new(L);
        // Planned angle still, the goal moves by the bias only (load shifting in stance).
        let load: Vec<_> = (0..20).map(|k| (100 + 3 * k, 100, 300)).collect();
        assert_eq!(feed(&mut d, &load), vec![]);
        // Goal still, the planned angle moves (a bias that cancels it): an unloaded servo holds.
        let cancel: Vec<_> = (0..20).map(|k| (100, 100 + 3 * k, 300)).collect();
        assert_eq!(feed(&mut d, &cancel), vec![]);
    }

    #[test]
    fn thresholds_are_exclusive_for_the_goal_and_inclusive_for_the_present() {
        let mut d = StuckDetector::<4>::new(L);
        // Goal range exactly 4: not more than 4.
        let s: Vec<_> = (0..5).map(|k| (100 + k, 100 + k, 300)).collect();
        assert_eq!(feed(&mut d, &s), vec![]);
        // Present range 2 (> 1): it moved.
        let s: Vec<_> = (0..5)
            .map(|k| (100 + 2 * k, 100 + 2 * k, 300 + k % 3))
            .collect();
        assert_eq!(feed(&mut d, &s), vec![]);
        // Goal range 5, present range 1: fires.
        let s: Vec<_> = (0..5)
            .map(|k| (100 + k + k / 4, 100 + k + k / 4, 300 + k % 2))
            .collect();
        assert_eq!(feed(&mut d, &s), vec![(5, stuck(5, 1).unwrap())]);
    }

    #[test]
    fn a_reset_starts_the_window_again_and_joints_are_independent() {
        let mut d = StuckDetector::<4>::new(L);
        let jam = |k: i32| (100 + 5 * k, 100 + 5 * k, 300);
        assert_eq!(feed(&mut d, &[jam(0), jam(1), jam(2)]), vec![]);
        d.reset();
        // Two more samples would have ended the old window; after the reset it takes five.
        assert_eq!(feed(&mut d, &[jam(3), jam(4)]), vec![]);
        // Another joint's samples do not count toward joint 2's window.
        for k in 0..5 {
            assert_eq!(d.record(1, 2, 1000 + 50 * k, 1000 + 50 * k, 0), {
                if k == 4 {
                    Some(SafeReason::ServoStuck {
                        joint: 1,
                        id: 2,
                        goal_range: 200,
                        present_range: 0,
                    })
                } else {
                    None
                }
            });
        }
        assert_eq!(
            feed(&mut d, &[jam(5), jam(6), jam(7)]),
            vec![(3, stuck(20, 0).unwrap())]
        );
        // Out-of-range joints are ignored rather than panicking; window 0 switches it off.
        assert_eq!(d.record(9, 1, 0, 0, 0), None);
        let mut off = StuckDetector::<4>::new(StuckLimits { window: 0, ..L });
        assert_eq!(
            feed(&mut off, &(0..20).map(jam).collect::<Vec<_>>()),
            vec![]
        );
    }
}
