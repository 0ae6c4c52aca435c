//! The bring-up check (`dbot doctor`, Python `dbot.doctor()`): a freshly wired robot checked end
//! to end, each item passed or failed with what to do, in the order to fix them: the board (found,
//! its versions, its state), then every servo of the model file on the servo bus (answering at
//! the bus's rate with the right model, firmware, Return Delay Time, Operating Mode, position
//! limits, no hardware error; a silent one looked for at the other MX rates; two with each
//! other's models called swapped), the supply voltage (the servos' Present Input Voltage), then
//! the strain board's 36 channels.
//!
//! The servos' registers are read on a servo bus: a serial port (`bus`: a U2D2 on the robot's
//! bus, or `dbot sim-bus`'s link), or for the in-process robots (`virtual`, `physics`) their own
//! simulated wire, or for a board on a serial port without a `bus` the board's own bus, the reads
//! passed through it between its bus cycles (`ReadServo`, protocol version 9; a silent servo cannot
//! be looked for at other rates there, and the item says so).

pub mod servo_bus;
pub mod servos;
mod strain;

use planner::model::Model;

pub use servo_bus::{BoardBus, SerialBus, ServoBus, SimBus};
pub use servos::{Expected, check_servos, expected_servos};
pub use strain::{check_strain, check_strain_io};

/// How one item came out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Pass,
    Fail,
    /// Not checked: what it needs is not given (the detail says what).
    NotChecked,
}

impl Outcome {
    /// `PASS`, `FAIL` or `----`: the word each printed line starts with.
    pub const fn word(self) -> &'static str {
        match self {
            Self::Pass => "PASS",
            Self::Fail => "FAIL",
            Self::NotChecked => "----",
        }
    }
}

/// One item of the check.
#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    /// What was checked (`board`, `servo ID 3 (LF_CTr, MX-64)`, `supply voltage`, `strain board`).
    pub name: String,
    pub outcome: Outcome,
    /// What was found.
    pub detail: String,
    /// What to do (failed and unchecked items).
    pub fix: Option<String>,
}

impl Item {
    pub fn pass(name: &str, detail: String) -> Self {
        Self {
            name: name.to_owned(),
            outcome: Outcome::Pass,
            detail,
            fix: None,
        }
    }

    pub fn fail(name: &str, detail: String, fix: String) -> Self {
        Self {
            name: name.to_owned(),
            outcome: Outcome::Fail,
            detail,
            fix: Some(fix),
        }
    }

    pub fn not_checked(name: &str, fix: String) -> Self {
        Self {
            name: name.to_owned(),
            outcome: Outcome::NotChecked,
            detail: "not checked".to_owned(),
            fix: Some(fix),
        }
    }

    /// A failure listing several problems and their fixes (unnamed until [`Item::named`]).
    fn failed_with(problems: Vec<String>, fixes: Vec<String>) -> Self {
        Self::fail("", problems.join("; "), fixes.join("; "))
    }

    fn named(mut self, name: String) -> Self {
        self.name = name;
        self
    }

    pub fn passed(&self) -> bool {
        self.outcome == Outcome::Pass
    }
}

impl std::fmt::Display for Item {
    /// `FAIL  servo ID 3 (...): missing: ...` and, indented below, `fix: ...`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}  {}: {}", self.outcome.word(), self.name, self.detail)?;
        if let Some(fix) = &self.fix {
            write!(f, "\n      fix: {fix}")?;
        }
        Ok(())
    }
}

/// Every item, in the order they are best fixed.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Report {
    pub items: Vec<Item>,
}

impl Report {
    /// The failed items.
    pub fn failures(&self) -> impl Iterator<Item = &Item> {
        self.items.iter().filter(|i| i.outcome == Outcome::Fail)
    }

    /// Whether nothing failed.
    pub fn ok(&self) -> bool {
        self.failures().next().is_none()
    }

    /// The lines `dbot doctor` prints and `dbot.doctor()` prints: the items, then a summary.
    pub fn text(&self) -> String {
        let mut out: String = self.items.iter().map(|i| format!("{i}\n")).collect();
        let count = |o: Outcome| self.items.iter().filter(|i| i.outcome == o).count();
        out.push_str(&format!(
            "{} passed, {} failed, {} not checked",
            count(Outcome::Pass),
            count(Outcome::Fail),
            count(Outcome::NotChecked)
        ));
        if let Some(first) = self.failures().next() {
            out.push_str(&format!("; fix first: {}", first.name));
        }
        out.push('\n');
        out
    }
}

/// What to check.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Options {
    /// The board's port (a serial device, `virtual[:PATH]`, `physics[:SCENE]`); none: no board
    /// items, and the servos only on `bus`.
    pub port: Option<String>,
    /// A servo bus on a serial port (a U2D2 on the robot's bus, or `dbot sim-bus`'s link).
    pub bus: Option<String>,
    /// The rate the servos must answer at, bit/s; default the board's bus rate, without a board
    /// the firmware's default.
    pub baud: Option<u32>,
    /// The strain board's port (`virtual`, or a serial device); none: not checked.
    pub strain: Option<String>,
    /// Seconds of strain samples to read after calibration.
    pub strain_seconds: f64,
}

/// `e` and its sources, `: `-joined (the words the CLI's error chain prints).
fn chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut cur = e.source();
    while let Some(c) = cur {
        s.push_str(": ");
        s.push_str(&c.to_string());
        cur = c.source();
    }
    s
}

/// Runs every check of `options` against the servos `model` names.
pub fn run(model: &Model, options: &Options) -> Report {
    let mut items = Vec::new();
    let mut robot = None;
    let mut board_baud = None;
    if let Some(port) = &options.port {
        match physics::open(port) {
            Ok(mut r) => {
                board_baud = board_items(&mut r, &mut items);
                robot = Some(r);
            }
            Err(e) => items.push(Item::fail(
                "board",
                format!("cannot connect to {port}: {}", chain(&e)),
                "check the USB cable and that the board runs this firmware version (dbot devices \
                 lists boards; flash it: docs/hardware.md, Flashing)"
                    .to_owned(),
            )),
        }
    }
    let baud = options
        .baud
        .or(board_baud)
        .unwrap_or(firmware::controller::Config::default().baud);
    let expected = expected_servos(model);
    let wire = robot.as_ref().and_then(|r| r.transport().bus_wire());
    let mut bus: Option<Box<dyn ServoBus>> = match (&options.bus, wire) {
        (Some(path), _) => match SerialBus::open(path, baud) {
            Ok(b) => Some(Box::new(b)),
            Err(why) => {
                items.push(Item::fail(
                    "servo bus",
                    why,
                    "give the servo adapter's port (--bus, Python bus=): a U2D2 on the robot's \
                     bus, or the --link of dbot sim-bus"
                        .to_owned(),
                ));
                None
            }
        },
        (None, Some(wire)) => {
            let kind = robot
                .as_ref()
                .map_or("in-process", |r| r.transport().kind());
            let mut b = SimBus::new(&format!("the {kind} robot's bus"), wire, baud);
            b.set_baud(baud).expect("the simulated wire takes any rate");
            Some(Box::new(b))
        }
        (None, None) => match robot.as_mut() {
            // A board on a port: its reads passed through to its bus, at its rate.
            Some(r) => Some(Box::new(BoardBus::new(r, baud))),
            None => {
                items.push(Item::not_checked(
                    "servos",
                    "no board and no servo bus: give the board's port (--port) or a servo bus \
                     (--bus PORT, Python bus=): a U2D2 on the robot's bus"
                        .to_owned(),
                ));
                None
            }
        },
    };
    if let Some(bus) = bus.as_deref_mut() {
        items.push(Item::pass(
            "servo bus",
            format!(
                "{} at {baud} bit/s; {} servos in the model file",
                bus.name(),
                expected.len()
            ),
        ));
        items.extend(check_servos(bus, &expected));
    }
    // The bus may borrow the board, which is closed below.
    drop(bus);
    if let Some(strain) = &options.strain {
        items.push(check_strain(
            strain,
            options.port.as_deref(),
            options.strain_seconds,
        ));
    }
    if let Some(mut r) = robot {
        let port = r.port().to_owned();
        if let Err(e) = board::link::Transport::shutdown(r.transport_mut()) {
            items.push(Item::fail(
                "board",
                format!("closing {port}: {}", chain(&e)),
                "check the virtual robot's store file can be written".to_owned(),
            ));
        }
    }
    Report { items }
}

/// The board's items (found and its versions, its state); returns its bus rate.
fn board_items(robot: &mut physics::Robot, items: &mut Vec<Item>) -> Option<u32> {
    let info = robot.info().clone();
    let port = robot.port().to_owned();
    let v = info.firmware;
    items.push(Item::pass(
        "board",
        format!(
            "{} board on {port}: firmware {}.{}.{} (build {:08x}), protocol {}, step table format {}, {} gait slots",
            robot.transport().kind(),
            v.major,
            v.minor,
            v.patch,
            info.build_id,
            info.protocol_version,
            info.table_format_version,
            info.slots.len()
        ),
    ));
    match robot.status() {
        Ok(s) => items.push(match s.fault {
            Some(f) => Item::fail(
                "board state",
                format!("{}: {f}", s.state.name()),
                "fix the cause (dbot status says more), then leave the fault: dbot set \
                 --clear-fault"
                    .to_owned(),
            ),
            None => Item::pass("board state", format!("{}, no fault", s.state.name())),
        }),
        Err(e) => items.push(Item::fail(
            "board state",
            format!("reading its status: {}", chain(&e)),
            "check the USB cable; reset the board".to_owned(),
        )),
    }
    match robot.settings() {
        Ok(s) => {
            items.push(Item::pass(
                "board bus",
                format!("{} bit/s, {} Hz bus cycle", s.baud, s.cycle_hz),
            ));
            Some(s.baud)
        }
        Err(e) => {
            items.push(Item::fail(
                "board bus",
                format!("reading its settings: {}", chain(&e)),
                "check the USB cable; reset the board".to_owned(),
            ));
            None
        }
    }
}
