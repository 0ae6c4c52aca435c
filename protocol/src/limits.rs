//! What the hardware can do: the one place for the limits of the board's run-time settings (bus
//! baud, bus cycle rate, servo stiffness). The host's flags and setup file and the firmware's
//! `SetBus` / `SetStiffness` handling all check against these, so they cannot disagree.

use dynamixel::ServoModel;

/// Bauds the Dynamixel MX (2.0 firmware) servos support: the rates of the Baud Rate register
/// (address 8), e-manual. `dynamixel::control_table::BAUD_RATES` is the register table; a
/// firmware test checks that both list the same rates.
pub const MX_BAUDS: [u32; 8] = [
    9_600, 57_600, 115_200, 1_000_000, 2_000_000, 3_000_000, 4_000_000, 4_500_000,
];

/// Bus cycle rates the firmware's bus loop accepts, Hz (below 50 Hz the gait's 10 ms slices are
/// not met; above 1000 Hz the loop's own work does not fit).
pub const CYCLE_HZ: core::ops::RangeInclusive<u16> = 50..=1000;

/// The board's host-loss rule (the image's `Config::host_timeout_cycles`): an endless run stops at
/// the end of its step after this many bus cycles without a frame from the host, 10 s at the
/// default 100 Hz. Long enough for any pause a working host makes (`dbot run` asks for the status
/// every 100 ms; a USB re-plug takes about 1 s), short enough that a killed host leaves the robot
/// walking for at most 10 s and one step. Finite runs finish their steps whatever the host does.
pub const HOST_TIMEOUT_CYCLES: u32 = 1000;

/// Servos on the robot: the bus carries at least their goals and replies every cycle.
pub const ROBOT_SERVOS: usize = 22;

/// Bits on the wire per byte (start, 8 data, stop).
pub const BITS_PER_BYTE: u32 = 10;

/// Bytes one walking bus cycle puts on the wire for `servos` servos: a Sync Write of 4-byte goals
/// (14 + 5 n: header 7, instruction 1, address 2, length 2, CRC 2, per servo ID + 4 data), a Sync
/// Read request (14 + n) and n status packets of 10 data bytes (21 each: header 7, instruction
/// and error 2, data 10, CRC 2). 622 bytes for the robot's 22 servos (docs/performance.md).
/// Return Delay Time 0 and no byte stuffing are assumed: the real cycle is a little longer.
pub const fn cycle_bytes(servos: usize) -> u32 {
    (14 + 5 * servos + 14 + servos + 21 * servos) as u32
}

/// Highest bus cycle rate (Hz, rounded down) whose cycles fit the wire at `baud` with `servos`
/// servos: baud / (10 bits x [`cycle_bytes`]). 160 Hz at 1 Mbit/s for 22 servos.
pub const fn wire_limit_hz(baud: u32, servos: usize) -> u32 {
    baud / (BITS_PER_BYTE * cycle_bytes(servos))
}

/// Servo stiffness for the torque bias, in its fixed-point unit (mN m / rad), largest accepted:
/// the strongest servo's stall torque (MX-64, 6.0 N m at 12 V, e-manual) over one encoder tick
/// (2 pi / 4096 rad): 6000 x 4096 / (2 pi) = 3 911 391. A stiffer spring would bias the goal by
/// less than one tick even at stall: the bias could not act. 0 means "bias off" and is allowed on
/// the board; a value given in N m/rad must not round to 0 by accident ([`stiffness_units`]).
pub const MAX_STIFFNESS_UNITS: u32 = 3_911_391;

/// The stiffness (mN m/rad, inclusive) the Position P Gain register of `servo` holds, on every
/// path to it: the board's `SetStiffness` (firmware) and a step table's joint record (its parse,
/// `crate::gait`), and the host's rule (`board::rules::stiffness`) from the same numbers. The
/// firmware writes the P gain nearest the stiffness (`dynamixel::units::p_gain_for_stiffness`,
/// ESTIMATE per unit: MX-28 0.0144, MX-64 0.0345 N m/rad) clamped to 1 ..= 16383; the torque
/// bias divides by the stiffness itself. Outside this range the clamp would give the servo
/// another stiffness than the one the bias divides by (at 1 mN m/rad on an MX-28 the bias asks
/// 500 rad of a 0.5 N m joint: full speed into its limit). The range is that of the values in
/// N m/rad the host accepts (P gain nearest 1 ..= 16383) rounded to mN m/rad: MX-28 7 ..= 235 708,
/// MX-64 17 ..= 565 699 (hand computed: half a unit, 7.19 and 17.26, and 16383.5 units, 235 707.6
/// and 565 698.2, with the unit (1/128) / 885 x stall torque x 4096 / 2 pi).
pub fn p_gain_stiffness_units(servo: ServoModel) -> core::ops::RangeInclusive<u32> {
    let unit_mnm = f64::from(servo.stiffness_per_p_gain()) * 1000.0;
    // Every mN m/rad value that some N m/rad with P gain nearest 1 ..= 16383 rounds to.
    let least = unit_mnm * 0.5;
    let most = unit_mnm * (f64::from(dynamixel::units::P_GAIN_MAX) + 0.5);
    // `floor`/`ceil` need std: the values are positive, so truncation and +1 do.
    let least = least as u32; // rounds least down: least - 0.5 <= x < least + 0.5 rounds to it
    let most = most as u32 + 1;
    least.max(1)..=most.min(MAX_STIFFNESS_UNITS)
}

/// Whether `units` (mN m/rad) is a stiffness the P gain of `servo` holds
/// ([`p_gain_stiffness_units`]); 0 is the board's "bias off" and is checked by the caller.
pub fn p_gain_holds(servo: ServoModel, units: u32) -> bool {
    p_gain_stiffness_units(servo).contains(&units)
}

/// Why a setting is outside what the hardware can do. The messages say the limit.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
// Closed on purpose: the firmware maps each variant to a protocol setting, exhaustively.
pub enum LimitError {
    /// Not one of [`MX_BAUDS`].
    Baud { baud: u32 },
    /// Outside [`CYCLE_HZ`].
    CycleRate { hz: u16 },
    /// More cycles per second than the wire carries at this baud.
    Wire {
        hz: u16,
        baud: u32,
        servos: u16,
        limit_hz: u32,
    },
    /// Not finite, not positive, rounds to 0 mN m/rad, or above [`MAX_STIFFNESS_UNITS`] (N m/rad).
    Stiffness { nm_per_rad: f64 },
}

impl core::fmt::Display for LimitError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Self::Baud { baud } => write!(
                f,
                "baud {baud} is not a rate the MX servos support (9600, 57600, 115200, 1000000, \
                 2000000, 3000000, 4000000, 4500000 bit/s)"
            ),
            Self::CycleRate { hz } => write!(
                f,
                "rate {hz} Hz is outside {} ..= {} Hz",
                CYCLE_HZ.start(),
                CYCLE_HZ.end()
            ),
            Self::Wire {
                hz,
                baud,
                servos,
                limit_hz,
            } => write!(
                f,
                "rate {hz} Hz does not fit the wire at {baud} bit/s: {servos} servos need {} bytes \
                 per cycle, so at most {limit_hz} Hz",
                cycle_bytes(servos as usize)
            ),
            Self::Stiffness { nm_per_rad } => write!(
                f,
                "stiffness {nm_per_rad} N m/rad is outside what a servo can hold: it must be at \
                 least 0.0005 (smaller rounds to 0 mN m/rad, which switches the torque bias off) \
                 and at most {} N m/rad (the MX-64's stall torque over one encoder tick)",
                MAX_STIFFNESS_UNITS as f64 / 1000.0
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for LimitError {}

/// Checks a bus setting: the baud is an MX baud, the rate is in [`CYCLE_HZ`] and its cycles for
/// `servos` servos fit the wire at that baud.
pub fn check_bus(baud: u32, hz: u16, servos: usize) -> Result<(), LimitError> {
    if !MX_BAUDS.contains(&baud) {
        return Err(LimitError::Baud { baud });
    }
    if !CYCLE_HZ.contains(&hz) {
        return Err(LimitError::CycleRate { hz });
    }
    let limit_hz = wire_limit_hz(baud, servos);
    if u32::from(hz) > limit_hz {
        return Err(LimitError::Wire {
            hz,
            baud,
            servos: servos as u16,
            limit_hz,
        });
    }
    Ok(())
}

/// A stiffness in N m/rad as the board's unit (mN m/rad, rounded to nearest), refused when not
/// finite, not positive, rounding to 0 or above [`MAX_STIFFNESS_UNITS`].
pub fn stiffness_units(nm_per_rad: f64) -> Result<u32, LimitError> {
    let units = nm_per_rad * crate::units::STIFFNESS_PER_NM_RAD;
    // `round` needs std; adding 0.5 and truncating is the same for the positive values kept.
    if !(units.is_finite() && units >= 0.5 && units < MAX_STIFFNESS_UNITS as f64 + 0.5) {
        return Err(LimitError::Stiffness { nm_per_rad });
    }
    Ok((units + 0.5) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_p_gain_holds_the_hand_computed_stiffness_range() {
        // MX-28: (1/128)/885 x 2.5 N m x 4096/(2 pi) = 14.3869 mN m/rad per P unit; half of it
        // 7.19, 16383.5 of it 235 707.6. MX-64 (6.0 N m): 34.5285, 17.26 and 565 698.2.
        assert_eq!(p_gain_stiffness_units(ServoModel::Mx28), 7..=235_708);
        assert_eq!(p_gain_stiffness_units(ServoModel::Mx64), 17..=565_699);
        // The case: 1 mN m/rad, which P gain 1 (14.4 mN m/rad) cannot give.
        assert!(!p_gain_holds(ServoModel::Mx28, 1));
        assert!(!p_gain_holds(ServoModel::Mx28, MAX_STIFFNESS_UNITS));
        assert!(p_gain_holds(ServoModel::Mx28, 12_230));
    }

    #[test]
    fn the_wire_limit_is_the_hand_computed_one() {
        // docs/performance.md: 622 bytes per cycle for 22 servos, baud / 6220.
        assert_eq!(cycle_bytes(22), 622);
        assert_eq!(wire_limit_hz(1_000_000, 22), 160); // 160.77
        assert_eq!(wire_limit_hz(4_000_000, 22), 643); // 643.09
        assert_eq!(wire_limit_hz(57_600, 22), 9); // 9.26
        assert!(check_bus(1_000_000, 160, 22).is_ok());
        let e = check_bus(1_000_000, 161, 22).unwrap_err();
        assert!(e.to_string().contains("at most 160 Hz"));
        assert!(matches!(
            check_bus(4_500_000, 1001, 22),
            Err(LimitError::CycleRate { .. })
        ));
        assert!(matches!(
            check_bus(57_600, 1000, 22),
            Err(LimitError::Wire { limit_hz: 9, .. })
        ));
        assert!(matches!(
            check_bus(57_600, 100, 22),
            Err(LimitError::Wire { limit_hz: 9, .. })
        ));
        assert_eq!(
            check_bus(12_345, 100, 22),
            Err(LimitError::Baud { baud: 12_345 })
        );
    }

    #[test]
    fn stiffness_that_rounds_to_zero_or_exceeds_the_servo_is_refused() {
        // 6 N m / (2 pi / 4096 rad) = 3911.39 N m/rad.
        let max = 6.0 * 4096.0 / (2.0 * core::f64::consts::PI);
        assert!((f64::from(MAX_STIFFNESS_UNITS) / 1000.0 - max).abs() < 1e-3);
        assert_eq!(stiffness_units(8.4), Ok(8400));
        assert_eq!(stiffness_units(0.0005), Ok(1));
        for bad in [
            1e-9,
            0.0004,
            0.0,
            -1.0,
            3912.0,
            1e6,
            f64::NAN,
            f64::INFINITY,
        ] {
            assert!(stiffness_units(bad).is_err(), "{bad}");
        }
    }
}
