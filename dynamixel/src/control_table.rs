//! MX-28(2.0) and MX-64(2.0) control tables (Protocol 2.0 firmware) as typed constants.
//! Addresses, sizes and defaults from the ROBOTIS e-manual (see ../shared/reference/dynamixel.md).

/// One control table field: address and size in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Field {
    pub name: &'static str,
    pub addr: u16,
    pub size: u8,
    /// EEPROM fields can be written only with Torque Enable off.
    pub eeprom: bool,
    pub writable: bool,
}

const fn ee(name: &'static str, addr: u16, size: u8) -> Field {
    Field {
        name,
        addr,
        size,
        eeprom: true,
        writable: true,
    }
}
const fn ee_ro(name: &'static str, addr: u16, size: u8) -> Field {
    Field {
        name,
        addr,
        size,
        eeprom: true,
        writable: false,
    }
}
const fn ram(name: &'static str, addr: u16, size: u8) -> Field {
    Field {
        name,
        addr,
        size,
        eeprom: false,
        writable: true,
    }
}
const fn ram_ro(name: &'static str, addr: u16, size: u8) -> Field {
    Field {
        name,
        addr,
        size,
        eeprom: false,
        writable: false,
    }
}

pub const MODEL_NUMBER: Field = ee_ro("Model Number", 0, 2);
pub const MODEL_INFORMATION: Field = ee_ro("Model Information", 2, 4);
pub const FIRMWARE_VERSION: Field = ee_ro("Firmware Version", 6, 1);
pub const ID: Field = ee("ID", 7, 1);
pub const BAUD_RATE: Field = ee("Baud Rate", 8, 1);
pub const RETURN_DELAY_TIME: Field = ee("Return Delay Time", 9, 1);
pub const DRIVE_MODE: Field = ee("Drive Mode", 10, 1);
pub const OPERATING_MODE: Field = ee("Operating Mode", 11, 1);
pub const SECONDARY_ID: Field = ee("Secondary ID", 12, 1);
pub const PROTOCOL_TYPE: Field = ee("Protocol Type", 13, 1);
pub const HOMING_OFFSET: Field = ee("Homing Offset", 20, 4);
pub const MOVING_THRESHOLD: Field = ee("Moving Threshold", 24, 4);
pub const TEMPERATURE_LIMIT: Field = ee("Temperature Limit", 31, 1);
pub const MAX_VOLTAGE_LIMIT: Field = ee("Max Voltage Limit", 32, 2);
pub const MIN_VOLTAGE_LIMIT: Field = ee("Min Voltage Limit", 34, 2);
pub const PWM_LIMIT: Field = ee("PWM Limit", 36, 2);
/// MX-64(2.0) only (MX-28 has no current sensing).
pub const CURRENT_LIMIT: Field = ee("Current Limit", 38, 2);
pub const ACCELERATION_LIMIT: Field = ee("Acceleration Limit", 40, 4);
pub const VELOCITY_LIMIT: Field = ee("Velocity Limit", 44, 4);
pub const MAX_POSITION_LIMIT: Field = ee("Max Position Limit", 48, 4);
pub const MIN_POSITION_LIMIT: Field = ee("Min Position Limit", 52, 4);
pub const SHUTDOWN: Field = ee("Shutdown", 63, 1);
pub const TORQUE_ENABLE: Field = ram("Torque Enable", 64, 1);
pub const LED: Field = ram("LED", 65, 1);
pub const STATUS_RETURN_LEVEL: Field = ram("Status Return Level", 68, 1);
pub const REGISTERED_INSTRUCTION: Field = ram_ro("Registered Instruction", 69, 1);
pub const HARDWARE_ERROR_STATUS: Field = ram_ro("Hardware Error Status", 70, 1);
pub const VELOCITY_I_GAIN: Field = ram("Velocity I Gain", 76, 2);
pub const VELOCITY_P_GAIN: Field = ram("Velocity P Gain", 78, 2);
pub const POSITION_D_GAIN: Field = ram("Position D Gain", 80, 2);
pub const POSITION_I_GAIN: Field = ram("Position I Gain", 82, 2);
pub const POSITION_P_GAIN: Field = ram("Position P Gain", 84, 2);
pub const BUS_WATCHDOG: Field = ram("Bus Watchdog", 98, 1);
pub const GOAL_PWM: Field = ram("Goal PWM", 100, 2);
/// MX-64(2.0) only.
pub const GOAL_CURRENT: Field = ram("Goal Current", 102, 2);
pub const GOAL_VELOCITY: Field = ram("Goal Velocity", 104, 4);
pub const PROFILE_ACCELERATION: Field = ram("Profile Acceleration", 108, 4);
pub const PROFILE_VELOCITY: Field = ram("Profile Velocity", 112, 4);
pub const GOAL_POSITION: Field = ram("Goal Position", 116, 4);
pub const REALTIME_TICK: Field = ram_ro("Realtime Tick", 120, 2);
pub const MOVING: Field = ram_ro("Moving", 122, 1);
pub const MOVING_STATUS: Field = ram_ro("Moving Status", 123, 1);
pub const PRESENT_PWM: Field = ram_ro("Present PWM", 124, 2);
/// Present Load on the MX-28(2.0) (0.1 % of maximum), Present Current on the MX-64(2.0).
pub const PRESENT_LOAD_OR_CURRENT: Field = ram_ro("Present Load/Current", 126, 2);
pub const PRESENT_VELOCITY: Field = ram_ro("Present Velocity", 128, 4);
pub const PRESENT_POSITION: Field = ram_ro("Present Position", 132, 4);
pub const VELOCITY_TRAJECTORY: Field = ram_ro("Velocity Trajectory", 136, 4);
pub const POSITION_TRAJECTORY: Field = ram_ro("Position Trajectory", 140, 4);
pub const PRESENT_INPUT_VOLTAGE: Field = ram_ro("Present Input Voltage", 144, 2);
pub const PRESENT_TEMPERATURE: Field = ram_ro("Present Temperature", 146, 1);

/// Every field above, in address order (for `dbot dxl read` by name and the virtual servo).
pub const FIELDS: &[Field] = &[
    MODEL_NUMBER,
    MODEL_INFORMATION,
    FIRMWARE_VERSION,
    ID,
    BAUD_RATE,
    RETURN_DELAY_TIME,
    DRIVE_MODE,
    OPERATING_MODE,
    SECONDARY_ID,
    PROTOCOL_TYPE,
    HOMING_OFFSET,
    MOVING_THRESHOLD,
    TEMPERATURE_LIMIT,
    MAX_VOLTAGE_LIMIT,
    MIN_VOLTAGE_LIMIT,
    PWM_LIMIT,
    CURRENT_LIMIT,
    ACCELERATION_LIMIT,
    VELOCITY_LIMIT,
    MAX_POSITION_LIMIT,
    MIN_POSITION_LIMIT,
    SHUTDOWN,
    TORQUE_ENABLE,
    LED,
    STATUS_RETURN_LEVEL,
    REGISTERED_INSTRUCTION,
    HARDWARE_ERROR_STATUS,
    VELOCITY_I_GAIN,
    VELOCITY_P_GAIN,
    POSITION_D_GAIN,
    POSITION_I_GAIN,
    POSITION_P_GAIN,
    BUS_WATCHDOG,
    GOAL_PWM,
    GOAL_CURRENT,
    GOAL_VELOCITY,
    PROFILE_ACCELERATION,
    PROFILE_VELOCITY,
    GOAL_POSITION,
    REALTIME_TICK,
    MOVING,
    MOVING_STATUS,
    PRESENT_PWM,
    PRESENT_LOAD_OR_CURRENT,
    PRESENT_VELOCITY,
    PRESENT_POSITION,
    VELOCITY_TRAJECTORY,
    POSITION_TRAJECTORY,
    PRESENT_INPUT_VOLTAGE,
    PRESENT_TEMPERATURE,
];

/// A field by its e-manual name, case-insensitive, spaces or underscores.
pub fn field_by_name(name: &str) -> Option<Field> {
    FIELDS.iter().copied().find(|f| {
        f.name.len() == name.len()
            && f.name.bytes().zip(name.bytes()).all(|(a, b)| {
                let b = if b == b'_' { b' ' } else { b };
                a.eq_ignore_ascii_case(&b)
            })
    })
}

/// First address of the 10 bytes one Sync Read per cycle gets: load/current, velocity, position.
pub const FEEDBACK_ADDR: u16 = 126;
/// Length of that block.
pub const FEEDBACK_LEN: u16 = 10;

/// Hardware Error Status bits.
pub mod hardware_error {
    pub const INPUT_VOLTAGE: u8 = 1 << 0;
    pub const OVERHEATING: u8 = 1 << 2;
    pub const ENCODER: u8 = 1 << 3;
    pub const ELECTRICAL_SHOCK: u8 = 1 << 4;
    pub const OVERLOAD: u8 = 1 << 5;
}

/// Baud Rate register values and their rates in bit/s.
pub const BAUD_RATES: [(u8, u32); 8] = [
    (0, 9_600),
    (1, 57_600),
    (2, 115_200),
    (3, 1_000_000),
    (4, 2_000_000),
    (5, 3_000_000),
    (6, 4_000_000),
    (7, 4_500_000),
];

/// The Baud Rate register value for a rate in bit/s.
pub fn baud_code(baud: u32) -> Option<u8> {
    BAUD_RATES.iter().find(|(_, b)| *b == baud).map(|(c, _)| *c)
}

/// The rate in bit/s of a Baud Rate register value.
pub fn baud_from_code(code: u8) -> Option<u32> {
    BAUD_RATES.iter().find(|(c, _)| *c == code).map(|(_, b)| *b)
}

/// Return Delay Time unit.
pub const RETURN_DELAY_UNIT_US: u32 = 2;
