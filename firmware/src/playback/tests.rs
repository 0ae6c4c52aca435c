//! Gait clock, interpolation, direction, scaling, step counting and the ramp, against hand-computed
//! values.

use super::*;

/// A gait given by its samples: `angle_urad[slice][joint]`, `torque_mnm[slice][joint]`.
struct Samples<const JOINTS: usize, const SLICES: usize> {
    period_us: u32,
    angle_urad: [[i32; JOINTS]; SLICES],
    torque_mnm: [[i32; JOINTS]; SLICES],
}

impl<const JOINTS: usize, const SLICES: usize> Gait for Samples<JOINTS, SLICES> {
    fn joints(&self) -> usize {
        JOINTS
    }
    fn slices(&self) -> usize {
        SLICES
    }
    fn period_us(&self) -> u32 {
        self.period_us
    }
    fn angle_urad(&self, slice: usize, joint: usize) -> i32 {
        self.angle_urad[slice][joint]
    }
    fn torque_mnm(&self, slice: usize, joint: usize) -> i32 {
        self.torque_mnm[slice][joint]
    }
}

/// `per_slice` x i at slice i of 10, for one joint.
const fn ten_slices(per_slice: i32) -> [[i32; 1]; 10] {
    let mut v = [[0]; 10];
    let mut i = 0;
    while i < 10 {
        v[i][0] = i as i32 * per_slice;
        i += 1;
    }
    v
}

/// Joint 0's angle at slice i is i x 1000 urad, its torque i x 10 mN m; 10 slices over 1 s.
const LINE: Samples<1, 10> = Samples {
    period_us: 1_000_000,
    angle_urad: ten_slices(1000),
    torque_mnm: ten_slices(10),
};

fn angle_at(clock: &PlayClock) -> i32 {
    let s = clock.sample(10);
    lerp(
        LINE.angle_urad(s.slice, 0),
        LINE.angle_urad(s.next, 0),
        s.frac,
    )
}

#[test]
fn forward_interpolates_between_slices_and_wraps_to_the_first() {
    let mut c = PlayClock::new(1_000_000, Direction::Forward, None);
    assert_eq!(angle_at(&c), 0);
    c.advance(250_000);
    // 0.25 s = 2.5 slices: halfway between 2000 and 3000.
    assert_eq!(
        c.sample(10),
        Sample {
            slice: 2,
            next: 3,
            frac: 32768
        }
    );
    assert_eq!(angle_at(&c), 2500);
    c.advance(700_000);
    // 0.95 s: halfway from slice 9 (9000) back to slice 0 (0).
    assert_eq!(
        c.sample(10),
        Sample {
            slice: 9,
            next: 0,
            frac: 32768
        }
    );
    assert_eq!(angle_at(&c), 4500);
    let a = c.advance(100_000);
    assert_eq!(
        a,
        Advance {
            steps_ended: 1,
            finished: false
        }
    );
    assert_eq!(c.phase_us(), 50_000);
    assert_eq!(angle_at(&c), 500);
}

#[test]
fn backward_runs_from_the_end_of_the_step_to_its_start() {
    let mut c = PlayClock::new(1_000_000, Direction::Backward, None);
    assert_eq!(angle_at(&c), 0);
    c.advance(250_000);
    assert_eq!(c.phase_us(), 750_000);
    assert_eq!(angle_at(&c), 7500);
    c.advance(500_000);
    assert_eq!(angle_at(&c), 2500);
    // Each sample is earlier in the step than the one before.
    let mut last = c.phase_us();
    for _ in 0..20 {
        c.advance(10_000);
        assert!(c.phase_us() < last);
        last = c.phase_us();
    }
    assert_eq!(c.advance(50_000).steps_ended, 1);
}

#[test]
fn scaling_stretches_the_period_and_keeps_the_phase_when_changed() {
    let mut c = PlayClock::new(1_000_000, Direction::Forward, None);
    c.set_scale(2000);
    c.advance(500_000);
    // Twice as slow: 0.5 s of wall time is 0.25 s of the table.
    assert_eq!(c.phase_us(), 250_000);
    c.set_scale(500);
    c.advance(100_000);
    assert_eq!(c.phase_us(), 450_000);
    // Thirds do not drift: 3000 advances of 1 us at 3x slower make exactly 1000 table us.
    let mut c = PlayClock::new(1_000_000, Direction::Forward, None);
    c.set_scale(3000);
    for _ in 0..3000 {
        c.advance(1);
    }
    assert_eq!(c.phase_us(), 1000);
}

#[test]
fn a_number_of_steps_ends_exactly_at_the_step_boundary() {
    let mut c = PlayClock::new(1_000_000, Direction::Forward, Some(3));
    let mut ended = 0;
    let mut finished_at = None;
    for i in 1..=40 {
        let a = c.advance(90_000);
        ended += a.steps_ended;
        if a.finished && finished_at.is_none() {
            finished_at = Some(i);
        }
    }
    // 3 s / 90 ms: the 34th advance (3.06 s) crosses the third step end.
    assert_eq!(finished_at, Some(34));
    assert_eq!(ended, 3);
    assert_eq!(c.steps_done(), 3);
    // Resting at slice 0, and staying there.
    assert_eq!(c.phase_us(), 0);
    assert_eq!(
        c.advance(90_000),
        Advance {
            steps_ended: 0,
            finished: true
        }
    );
    assert_eq!(c.phase_us(), 0);
}

#[test]
fn goals_bias_and_clamp_every_joint() {
    // Two slices over 1 ms. Joint 0: 0 then pi/2; joint 1: 3 rad at both slices (past its
    // limit); both joints' torque 0 then 1.68 N m.
    let two = Samples {
        period_us: 1000,
        angle_urad: [[0, 3_000_000], [1_570_796, 3_000_000]],
        torque_mnm: [[0, 0], [1680, 1680]],
    };
    let cal = |joint: usize| JointCal {
        id: joint as u8 + 1,
        model: protocol::ServoModel::Mx28,
        calibration: protocol::Calibration::new(
            protocol::ServoModel::Mx28,
            2048,
            if joint == 0 {
                protocol::Sign::Positive
            } else {
                protocol::Sign::Negative
            },
        ),
        min_ticks: 1000,
        max_ticks: 3500,
        leg: None,
    };
    let cals = [cal(0), cal(1)];
    let mut out = [0; 2];
    let mut cut = [false; 2];
    let s = Sample {
        slice: 0,
        next: 1,
        frac: 32768,
    };
    let clamped = goals(&two, s, &cals, &[8400, 8400], &mut out, &mut cut);
    // Joint 0 halfway: pi/4 + 0.84 N m / 8.4 N m/rad = 0.785398 + 0.1 rad = 0.885398 rad
    // x 4096 / 2 pi = 577.19 ticks -> 577.
    assert_eq!(out[0], 2048 + 577);
    // Joint 1: 2048 - (3 + 0.1) x 651.9 = 27 ticks, below the 1000 limit.
    assert_eq!(out[1], 1000);
    assert_eq!(clamped, 1);
    assert_eq!(cut, [false, true]);
    // Stiffness set to 0 at run time switches the bias off: pi/4 = 512 ticks.
    goals(&two, s, &cals, &[0, 0], &mut out, &mut cut);
    assert_eq!(out[0], 2048 + 512);
}

#[test]
fn the_ramp_moves_every_joint_in_a_straight_line_at_the_speed_limit() {
    let mut r = Ramp::new(&[0, 100, 500], &[1000, 100, 0], 1000, 200_000);
    // The longest way is 1000 ticks at 1000 ticks/s.
    assert_eq!(r.duration_us(), 1_000_000);
    let mut out = [0; 3];
    r.goals(&mut out);
    assert_eq!(out, [0, 100, 500]);
    assert!(!r.advance(500_000));
    r.goals(&mut out);
    assert_eq!(out, [500, 100, 250]);
    assert!(r.advance(600_000));
    r.goals(&mut out);
    assert_eq!(out, [1000, 100, 0]);
    // Short ways still take the minimum time.
    assert_eq!(Ramp::new(&[0], &[10], 1000, 200_000).duration_us(), 200_000);
}

#[test]
fn the_ramp_moves_one_part_at_a_time_lifted_and_the_rest_straight() {
    // Joint 0 in part 0 (150 ticks, lifted 25), joint 1 in part 1 (-150, lifted -25), joint 2
    // straight over both (600). A lifted joint goes across in the first three quarters of its part
    // and up in the first quarter, down in the last: at 1000 ticks/s its part lasts
    // (4/3 x 150 + 4 x 25) / 1000 = 0.3 s, and the straight joint's 600 ticks fit in the 0.6 s.
    let groups = [RampGroup::Part(0), RampGroup::Part(1), RampGroup::Whole];
    let (from, to, lift) = ([0, 0, 0], [150, -150, 600], [25, -25, 0]);
    let mut r = Ramp::stepping(&from, &to, &lift, &groups, 1000, 100_000);
    assert_eq!(r.duration_us(), 600_000);
    let mut out = [0; 3];
    let mut at = |r: &mut Ramp, dt| {
        let arrived = r.advance(dt);
        r.goals(&mut out);
        (out, arrived)
    };
    // Half way through part 0: joint 0 two thirds across (100) and up (+25); joint 1 waits.
    assert_eq!(at(&mut r, 150_000), ([125, 0, 150], false));
    // 0.9 of part 0: across, and down to 4 x 0.1 of the lift.
    assert_eq!(at(&mut r, 120_000), ([160, 0, 270], false));
    assert_eq!(at(&mut r, 30_000), ([150, 0, 300], false));
    // A quarter of part 1: a third across (-50) and up (-25).
    assert_eq!(at(&mut r, 75_000), ([150, -75, 375], false));
    assert_eq!(at(&mut r, 225_000), ([150, -150, 600], true));
    // No goal moves faster than the speed: 1 tick per millisecond, give or take the rounding.
    let mut r = Ramp::stepping(&from, &to, &lift, &groups, 1000, 100_000);
    let mut last = [0; 3];
    for _ in 0..600 {
        r.advance(1000);
        let mut now = [0; 3];
        r.goals(&mut now);
        for (a, b) in now.iter().zip(&last) {
            assert!((a - b).abs() <= 2, "{now:?} after {last:?}");
        }
        last = now;
    }
    // Without parts it is the straight ramp.
    let straight = Ramp::stepping(&[0], &[10], &[], &[], 1000, 200_000);
    assert_eq!(straight.duration_us(), 200_000);
    // Each part as long as its own joints need: part 0 4/3 x 75 ticks, 0.1 s, part 1 0.3 s; the
    // straight joint's 200 ticks fit in their 0.4 s.
    let unlifted = |to: &[i32; 3]| Ramp::stepping(&[0; 3], to, &[0; 3], &groups, 1000, 100_000);
    assert_eq!(unlifted(&[75, 225, 200]).duration_us(), 400_000);
    // A straight joint that needs longer stretches both parts alike: 800 ticks, 0.8 s.
    let mut r = unlifted(&[75, 225, 800]);
    assert_eq!(r.duration_us(), 800_000);
    let mut out = [0; 3];
    r.advance(200_000);
    r.goals(&mut out);
    assert_eq!(out, [75, 0, 200]);
}

/// Eight slices of four joints with stance flags: LF (joint 0) and LM (no joint here) stand in
/// slices 0-3, RH (joint 1) in 4-7, LH (joint 2) always; joint 3 is no leg's.
struct Legged {
    angle_urad: [[i32; 4]; 8],
}

impl Gait for Legged {
    fn joints(&self) -> usize {
        4
    }
    fn slices(&self) -> usize {
        8
    }
    fn period_us(&self) -> u32 {
        800_000
    }
    fn angle_urad(&self, slice: usize, joint: usize) -> i32 {
        self.angle_urad[slice][joint]
    }
    fn torque_mnm(&self, _: usize, _: usize) -> i32 {
        0
    }
    fn stance(&self, slice: usize) -> u8 {
        let lf_lm = u8::from(slice < 4) * 0b11;
        let rh = u8::from(slice >= 4) << 5;
        lf_lm | rh | 1 << 2
    }
}

#[test]
fn each_swinging_leg_gets_its_pairs_part_and_an_eighth_of_its_swings_rise() {
    let mut angle_urad = [[0; 4]; 8];
    // LF swings in slices 4-7: lift-off after slice 3, touch-down at slice 0, its middle slice 5.
    angle_urad[5][0] = 800_000;
    // RH swings in 0-3: lift-off after slice 7 (0.1 rad), middle slice 1 (0.6), touch-down 4 (0.3).
    angle_urad[7][1] = 100_000;
    angle_urad[1][1] = 600_000;
    angle_urad[4][1] = 300_000;
    angle_urad[5][2] = 500_000;
    angle_urad[5][3] = 500_000;
    let gait = Legged { angle_urad };
    let cal = |leg| JointCal {
        id: 1,
        model: protocol::ServoModel::Mx28,
        calibration: protocol::Calibration::new(
            protocol::ServoModel::Mx28,
            2048,
            protocol::Sign::Positive,
        ),
        min_ticks: 0,
        max_ticks: 4095,
        leg,
    };
    let cals = [cal(Some(0)), cal(Some(5)), cal(Some(2)), cal(None)];
    let (mut lift, mut group) = ([9; 4], [RampGroup::Part(9); 4]);
    start_lifts(&gait, &cals, &mut lift, &mut group);
    // Ticks by hand (4096 per turn, zero at 2048): 0.8 rad = 521.5 -> 2570, so the rise above the
    // line 2048-2048 is 522, an eighth 65; RH: 0.1 rad 2113, 0.3 rad 2244, 0.6 rad 2439, the
    // line's middle 2178, the rise 261, an eighth 32. LH never swings, joint 3 has no leg.
    assert_eq!(lift, [65, 32, 0, 0]);
    // The pairs LM RM, LH RF, RH LF in turn, counting those with a leg that swings: LM's pair
    // is part 0 (LM swings, though no joint here is its), LH's pair has none, RH and LF part 1.
    let part1 = RampGroup::Part(1);
    assert_eq!(group, [part1, part1, RampGroup::Whole, RampGroup::Whole]);
}
