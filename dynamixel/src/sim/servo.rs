//! One virtual MX(2.0) servo: control table memory with the e-manual's access rules, the motor
//! model of [`super::physics`], and the faults a test can switch on.

use super::physics::{self, MotorInput, MotorState};
use super::thermal::{self, Thermal};
use crate::control_table::{self as ct, Field, hardware_error};
use crate::instruction::StatusError;
use crate::model::ServoModel;
use crate::units::{self, RAD_PER_TICK, RAD_S_PER_VELOCITY_UNIT};

/// Size of the modelled control table (through Present Temperature at 146; indirect addressing
/// is not modelled).
pub const TABLE_SIZE: usize = 147;
/// Start of the RAM area; below it is EEPROM, writable only with torque off.
const RAM_START: u16 = 64;

/// Power-on values of the control table (e-manual) that both models share, EEPROM (factory
/// defaults; the firmware version an arbitrary one for the simulation) and RAM (torque off, default
/// gains, 12.0 V and 36 degC present). Not here: Model Number and Current Limit, which depend on the
/// model, and Goal Position, which starts at the present position.
const DEFAULTS: [(Field, u32); 23] = [
    (ct::FIRMWARE_VERSION, 41),
    (ct::ID, 1),
    (ct::BAUD_RATE, 1),
    (ct::RETURN_DELAY_TIME, 250),
    (ct::OPERATING_MODE, 3),
    (ct::PROTOCOL_TYPE, 2),
    (ct::MOVING_THRESHOLD, 10),
    (ct::TEMPERATURE_LIMIT, 80),
    (ct::MAX_VOLTAGE_LIMIT, 160),
    (ct::MIN_VOLTAGE_LIMIT, 95),
    (ct::PWM_LIMIT, 885),
    (ct::ACCELERATION_LIMIT, 32767),
    (ct::VELOCITY_LIMIT, 1023),
    (ct::MAX_POSITION_LIMIT, 4095),
    (ct::MIN_POSITION_LIMIT, 0),
    (ct::SHUTDOWN, 0x34),
    (ct::STATUS_RETURN_LEVEL, 2),
    (ct::VELOCITY_I_GAIN, 1920),
    (ct::VELOCITY_P_GAIN, 100),
    (ct::POSITION_P_GAIN, 850),
    (ct::GOAL_PWM, 885),
    (ct::PRESENT_INPUT_VOLTAGE, 120),
    (ct::PRESENT_TEMPERATURE, 36),
];

/// Faults a test can inject into one servo.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Faults {
    /// Executes instructions but never replies.
    pub no_reply: bool,
    /// Replies with the CRC's low byte inverted.
    pub corrupt_crc: bool,
    /// The next this many replies have the CRC's low byte inverted (counts down per reply; a
    /// short glitch rather than a broken servo).
    pub corrupt_next: u32,
    /// Replies this many microseconds later than its Return Delay Time says.
    pub late_reply_us: u32,
    /// The output does not move (jammed gear): position stays, the motor stalls.
    pub stuck: bool,
}

impl Faults {
    /// No fault: the servo behaves.
    pub const NONE: Self = Self {
        no_reply: false,
        corrupt_crc: false,
        corrupt_next: 0,
        late_reply_us: 0,
        stuck: false,
    };
    /// A servo that executes instructions but never replies.
    pub const SILENT: Self = Self {
        no_reply: true,
        ..Self::NONE
    };
    /// A servo whose every reply has a bad CRC.
    pub const BAD_CRC: Self = Self {
        corrupt_crc: true,
        ..Self::NONE
    };
    /// A servo with a jammed gear: it answers, but its output does not move.
    pub const JAMMED: Self = Self {
        stuck: true,
        ..Self::NONE
    };

    /// A glitch: the next `n` replies have a bad CRC, then the servo is well again.
    pub const fn corrupting_next(n: u32) -> Self {
        Self {
            corrupt_next: n,
            ..Self::NONE
        }
    }

    /// A servo that replies `us` microseconds after its Return Delay Time.
    pub const fn late_by_us(us: u32) -> Self {
        Self {
            late_reply_us: us,
            ..Self::NONE
        }
    }
}

/// A virtual servo.
#[derive(Debug, Clone, PartialEq)]
pub struct VirtualServo {
    model: ServoModel,
    mem: [u8; TABLE_SIZE],
    motor: MotorState,
    /// External load torque at the output in N m (positive toward increasing ticks), e.g. the
    /// planner's modelled joint torque with its sign flipped.
    pub external_torque_nm: f64,
    pub faults: Faults,
    /// The output is moved by an external plant (a rigid-body simulation) that sets the motor
    /// state with [`Self::set_motor_state`]; [`Self::step`] then leaves it alone.
    pub external_plant: bool,
    /// The thermal body behind Present Temperature (ESTIMATE, [`super::thermal`]); a test raises
    /// `r_th_k_per_w` to make one servo heat fast.
    pub thermal: Thermal,
    /// Winding temperature, degC (Present Temperature is its rounded value).
    temperature_c: f64,
}

impl VirtualServo {
    /// A servo with factory defaults except `id` and `baud_code`, resting at `position` ticks.
    pub fn new(id: u8, model: ServoModel, baud_code: u8, position: i32) -> Self {
        let mut s = Self {
            model,
            mem: [0; TABLE_SIZE],
            motor: MotorState {
                angle_rad: position as f64 * RAD_PER_TICK as f64,
                ..Default::default()
            },
            external_torque_nm: 0.0,
            faults: Faults::default(),
            external_plant: false,
            thermal: Thermal::MX,
            temperature_c: Thermal::MX.ambient_c,
        };
        s.factory_defaults();
        s.put(ct::ID, id as u32);
        s.put(ct::BAUD_RATE, baud_code as u32);
        s.reset_ram();
        s.refresh_present();
        s
    }

    fn factory_defaults(&mut self) {
        self.mem = [0; TABLE_SIZE];
        self.put(ct::MODEL_NUMBER, self.model.number() as u32);
        for (f, v) in DEFAULTS.into_iter().filter(|d| d.0.addr < RAM_START) {
            self.put(f, v);
        }
        // Current Limit exists only where register 126 is a current (MX-64).
        if self.model.reports_current() {
            self.put(ct::CURRENT_LIMIT, 1941);
        }
    }

    /// RAM at power-on / after Reboot: torque off, gains default, goal = present position.
    fn reset_ram(&mut self) {
        self.mem[RAM_START as usize..].fill(0);
        for (f, v) in DEFAULTS.into_iter().filter(|d| d.0.addr >= RAM_START) {
            self.put(f, v);
        }
        self.put(ct::GOAL_POSITION, self.position_ticks() as u32);
    }

    pub fn model(&self) -> ServoModel {
        self.model
    }

    pub fn id(&self) -> u8 {
        self.mem[ct::ID.addr as usize]
    }

    /// A field's value (little endian, zero-extended).
    pub fn get(&self, f: Field) -> u32 {
        let a = f.addr as usize;
        self.mem[a..a + f.size as usize]
            .iter()
            .rev()
            .fold(0, |acc, &b| (acc << 8) | b as u32)
    }

    /// Sets a field directly, bypassing the access rules (test setup).
    pub fn put(&mut self, f: Field, value: u32) {
        let a = f.addr as usize;
        self.mem[a..a + f.size as usize].copy_from_slice(&value.to_le_bytes()[..f.size as usize]);
    }

    pub fn torque_enabled(&self) -> bool {
        self.get(ct::TORQUE_ENABLE) != 0
    }

    pub fn hardware_error(&self) -> u8 {
        self.get(ct::HARDWARE_ERROR_STATUS) as u8
    }

    /// Return Delay Time in microseconds (register x 2 us) plus an injected lateness.
    pub fn reply_delay_us(&self) -> u32 {
        self.get(ct::RETURN_DELAY_TIME) * ct::RETURN_DELAY_UNIT_US + self.faults.late_reply_us
    }

    pub fn baud(&self) -> Option<u32> {
        ct::baud_from_code(self.get(ct::BAUD_RATE) as u8)
    }

    /// Present position in ticks (nearest).
    pub fn position_ticks(&self) -> i32 {
        (self.motor.angle_rad / RAD_PER_TICK as f64).round() as i32
    }

    pub fn motor(&self) -> &MotorState {
        &self.motor
    }

    /// The status error byte's Alert bit: set while a hardware error is latched.
    pub fn alert(&self) -> u8 {
        if self.hardware_error() != 0 {
            StatusError::ALERT
        } else {
            0
        }
    }

    /// Latches an overload: torque off, Hardware Error Status bit 5, Alert until Reboot.
    pub fn trigger_overload(&mut self) {
        let e = self.hardware_error() | hardware_error::OVERLOAD;
        self.put(ct::HARDWARE_ERROR_STATUS, e as u32);
        self.put(ct::TORQUE_ENABLE, 0);
    }

    /// Reboot: RAM back to power-on values, which clears the hardware error and the torque.
    pub fn reboot(&mut self) {
        self.reset_ram();
        self.refresh_present();
        // Still hot after a reboot: the temperature is the winding's, not a RAM default.
        self.refresh_health(None);
    }

    /// The motor state from an external plant (angle from tick 0, velocity and output torque toward
    /// increasing ticks, duty); the Present registers follow at once.
    pub fn set_motor_state(&mut self, state: MotorState) {
        self.motor = state;
        self.refresh_present();
    }

    /// Advances the motor by `dt_s` seconds and updates the Present registers (nothing moves
    /// under an external plant: the plant sets the state).
    pub fn step(&mut self, dt_s: f64) {
        if self.external_plant {
            return;
        }
        let input = MotorInput {
            model: self.model,
            torque_on: self.torque_enabled(),
            goal_ticks: self.get(ct::GOAL_POSITION) as i32,
            p_gain: self.get(ct::POSITION_P_GAIN) as u16,
            external_nm: self.external_torque_nm,
            stuck: self.faults.stuck,
        };
        physics::step(&mut self.motor, &input, dt_s);
        self.refresh_present();
    }

    /// Motor current at the present output torque, A (ESTIMATE, [`thermal::motor_current_a`]).
    pub fn motor_current_a(&self) -> f64 {
        thermal::motor_current_a(self.model, self.motor.torque_nm)
    }

    /// Winding temperature, degC.
    pub fn temperature_c(&self) -> f64 {
        self.temperature_c
    }

    /// Sets the winding temperature (test setup); Present Temperature follows at once.
    pub fn set_temperature_c(&mut self, t_c: f64) {
        self.temperature_c = t_c;
        self.refresh_health(None);
    }

    /// Heats the winding for `dt_s` seconds at the present motor current and sets Present Input
    /// Voltage to `volts` (the chain's supply at the servos). Past the Temperature Limit the servo
    /// latches the overheating error and, if its Shutdown register has that bit, drops torque.
    pub fn heat(&mut self, dt_s: f64, volts: f64) {
        self.heat_decayed(self.thermal.decay(dt_s), volts);
    }

    /// [`Self::heat`] with the step's [`Thermal::decay`] given.
    pub(crate) fn heat_decayed(&mut self, decay: f64, volts: f64) {
        let i = self.motor_current_a();
        self.temperature_c = self
            .thermal
            .step_c_decayed(self.model, self.temperature_c, i, decay);
        self.refresh_health(Some(volts));
    }

    fn refresh_health(&mut self, volts: Option<f64>) {
        let t = self.temperature_c.round().clamp(0.0, 255.0) as u32;
        self.put(ct::PRESENT_TEMPERATURE, t);
        if let Some(v) = volts {
            let dv = (v * 10.0).round().clamp(0.0, 65535.0) as u32;
            self.put(ct::PRESENT_INPUT_VOLTAGE, dv);
        }
        if t > self.get(ct::TEMPERATURE_LIMIT) {
            let e = self.hardware_error() | hardware_error::OVERHEATING;
            self.put(ct::HARDWARE_ERROR_STATUS, e as u32);
            if self.get(ct::SHUTDOWN) as u8 & hardware_error::OVERHEATING != 0 {
                self.put(ct::TORQUE_ENABLE, 0);
            }
        }
    }

    fn refresh_present(&mut self) {
        let m = self.motor;
        self.put(ct::PRESENT_POSITION, self.position_ticks() as u32);
        let vel = (m.velocity_rad_s / RAD_S_PER_VELOCITY_UNIT as f64).round() as i32;
        self.put(ct::PRESENT_VELOCITY, vel as u32);
        let load = units::torque_to_load(self.model, m.torque_nm as f32);
        self.put(ct::PRESENT_LOAD_OR_CURRENT, load as u16 as u32);
        self.put(
            ct::PRESENT_PWM,
            ((m.duty * 885.0).round() as i16) as u16 as u32,
        );
        let moving = (m.velocity_rad_s.abs() / RAD_S_PER_VELOCITY_UNIT as f64)
            > self.get(ct::MOVING_THRESHOLD) as f64;
        self.put(ct::MOVING, moving as u32);
    }

    /// Reads `len` bytes at `addr`, or the error number the servo would answer.
    pub fn read(&self, addr: u16, len: u16) -> Result<&[u8], u8> {
        let (a, l) = (addr as usize, len as usize);
        if l == 0 || a + l > TABLE_SIZE {
            return Err(StatusError::DATA_RANGE);
        }
        Ok(&self.mem[a..a + l])
    }

    /// Writes `data` at `addr` with the e-manual's rules: read-only fields and EEPROM with torque
    /// on are Access errors, out-of-range values Data Range, goals outside the position limits
    /// Data Limit. Nothing is written on error.
    pub fn write(&mut self, addr: u16, data: &[u8]) -> Result<(), u8> {
        let (a, l) = (addr as usize, data.len());
        if l == 0 || a + l > TABLE_SIZE {
            return Err(StatusError::DATA_RANGE);
        }
        let mut next = self.mem;
        next[a..a + l].copy_from_slice(data);
        // The fields the write touches: `FIELDS` is in address order without overlaps, so they
        // are one run found by bisection (a sync write reaches every servo every bus cycle,
        // and walking all fifty fields for each was most of the write's time).
        let first = ct::FIELDS.partition_point(|f| (f.addr + f.size as u16) as usize <= a);
        for f in ct::FIELDS[first..]
            .iter()
            .take_while(|f| (f.addr as usize) < a + l)
        {
            if !f.writable || (f.eeprom && self.torque_enabled()) {
                return Err(StatusError::ACCESS);
            }
        }
        let val = |f: Field| {
            let s = f.addr as usize;
            next[s..s + f.size as usize]
                .iter()
                .rev()
                .fold(0u32, |acc, &b| (acc << 8) | b as u32)
        };
        let touches = |f: Field| (f.addr as usize) < a + l && a < (f.addr + f.size as u16) as usize;
        if touches(ct::ID) && val(ct::ID) > crate::instruction::MAX_ID as u32 {
            return Err(StatusError::DATA_RANGE);
        }
        if touches(ct::BAUD_RATE) && ct::baud_from_code(val(ct::BAUD_RATE) as u8).is_none() {
            return Err(StatusError::DATA_RANGE);
        }
        if touches(ct::TORQUE_ENABLE) && val(ct::TORQUE_ENABLE) > 1 {
            return Err(StatusError::DATA_RANGE);
        }
        if touches(ct::TORQUE_ENABLE) && val(ct::TORQUE_ENABLE) == 1 && self.hardware_error() != 0 {
            // A latched hardware error keeps the torque off until Reboot.
            return Err(StatusError::RESULT_FAIL);
        }
        if touches(ct::GOAL_POSITION) {
            let g = val(ct::GOAL_POSITION) as i32;
            let (min, max) = (
                val(ct::MIN_POSITION_LIMIT) as i32,
                val(ct::MAX_POSITION_LIMIT) as i32,
            );
            if g < min || g > max {
                return Err(StatusError::DATA_LIMIT);
            }
        }
        self.mem = next;
        Ok(())
    }
}
