//! The servo bench (`board::bench`) against a virtual chain served on a pseudo-terminal, as
//! `dbot dxl` uses it on real servos: scan, read, write, setup, and errors that name the field.

use board::bench::{BaudChoice, Bench, BenchError, SetupRequest, Target};
use board::bus::pty::PtyServer;
use dynamixel::ServoModel;
use dynamixel::sim::VirtualChain;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A chain served on a pty in a thread; stopped when dropped.
struct Served {
    _dir: tempfile::TempDir,
    link: String,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Served {
    fn start(servos: &[(u8, ServoModel)], baud: u32) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("bus");
        let mut chain = VirtualChain::new(servos, baud).unwrap();
        // Replies at once: the e-manual default of 250 (500 us) only slows the test.
        chain.set_return_delay_all(0);
        let mut server = PtyServer::open(chain, baud, &link).unwrap();
        let stop = Arc::new(AtomicBool::new(false));
        let s = stop.clone();
        let thread = std::thread::spawn(move || server.serve(&s, |_| {}).unwrap());
        Self {
            link: link.to_string_lossy().into_owned(),
            _dir: dir,
            stop,
            thread: Some(thread),
        }
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            t.join().unwrap();
        }
    }
}

// Generous: every absent ID of a scan costs one slack, and a loaded machine can deschedule the
// server thread for a long time: 200 ms was once too little (a loaded run of the suite while a
// venv was being copied beside it: the scan missed servo 3).
const SLACK_US: u32 = 1_000_000;
// Where only silence is expected a stall cannot fake an answer: a short slack keeps it quick.
const SILENT_SLACK_US: u32 = 20_000;

#[test]
fn scan_finds_exactly_the_chain_with_its_e_manual_model_numbers() {
    let bus = Served::start(&[(1, ServoModel::Mx28), (3, ServoModel::Mx64)], 1_000_000);
    let mut bench = Bench::new(&bus.link, BaudChoice::Rate(1_000_000), SLACK_US);
    let scan = bench.scan(4, |_| {}).unwrap();
    assert_eq!(scan.baud, 1_000_000);
    let ids: Vec<(u8, u16)> = scan.found.iter().map(|f| (f.id, f.model_number)).collect();
    // e-manual: MX-28(2.0) is model number 30, MX-64(2.0) is 311.
    assert_eq!(ids, vec![(1, 30), (3, 311)]);
    assert_eq!(scan.found[1].model, Some(ServoModel::Mx64));
}

#[test]
fn auto_scan_finds_servos_at_1_mbit_after_trying_the_factory_rate() {
    let bus = Served::start(&[(2, ServoModel::Mx28)], 1_000_000);
    let mut bench = Bench::new(&bus.link, BaudChoice::Auto, SLACK_US);
    let scan = bench.scan(2, |_| {}).unwrap();
    assert_eq!((scan.baud, scan.found.len()), (1_000_000, 1));
    assert_eq!(bench.baud(), Some(1_000_000));
}

#[test]
fn read_write_and_errors_that_name_the_field() {
    let bus = Served::start(&[(2, ServoModel::Mx28)], 1_000_000);
    let mut bench = Bench::new(&bus.link, BaudChoice::Rate(1_000_000), SLACK_US);
    // Model Number (address 0, 2 bytes) of an MX-28(2.0): 30, by the e-manual.
    let r = bench.read(2, Target::Field("Model Number")).unwrap();
    assert_eq!((r.field.addr, r.bytes.clone()), (0, vec![30, 0]));
    // The Return Delay Time this test set, by address.
    let r = bench.read(2, Target::Addr { addr: 9, len: 1 }).unwrap();
    assert_eq!(r.unsigned(), Some(0));

    bench
        .write(2, Target::Field("goal_position"), 1234)
        .unwrap();
    let r = bench.read(2, Target::Field("Goal Position")).unwrap();
    assert_eq!((r.unsigned(), r.signed()), (Some(1234), Some(1234)));
    // Two's complement: Homing Offset (EEPROM, torque is off) -5 reads back as 2^32 - 5.
    bench.write(2, Target::Field("Homing Offset"), -5).unwrap();
    let r = bench.read(2, Target::Addr { addr: 20, len: 4 }).unwrap();
    assert_eq!((r.unsigned(), r.signed()), (Some((1 << 32) - 5), Some(-5)));

    let e = bench.read(2, Target::Field("Goal Positon")).unwrap_err();
    assert!(matches!(e, BenchError::UnknownField { .. }), "{e}");
    assert!(
        e.to_string()
            .starts_with("field \"Goal Positon\": no such control table field"),
        "{e}"
    );
    let e = bench.write(2, Target::Field("LED"), 300).unwrap_err();
    assert_eq!(
        e.to_string(),
        "value for LED: 300 does not fit in 1 byte(s) (-128..=255)"
    );
    let e = bench.read(9, Target::Field("LED")).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("ID 9") && text.contains(&bus.link), "{text}");
}

#[test]
fn setup_changes_id_and_baud_and_the_servo_answers_only_there() {
    let bus = Served::start(&[(1, ServoModel::Mx28)], 57_600);
    let mut bench = Bench::new(&bus.link, BaudChoice::Rate(57_600), SLACK_US);
    let req = SetupRequest {
        new_id: Some(8),
        new_baud: Some(1_000_000),
        return_delay_us: Some(0),
    };
    let done = bench.setup(1, req).unwrap();
    assert_eq!((done.id, done.baud, done.model_number), (8, 1_000_000, 30));
    // The port is opened exclusively: one bench at a time.
    drop(bench);

    let mut at_new = Bench::new(&bus.link, BaudChoice::Rate(1_000_000), SLACK_US);
    let ids: Vec<u8> = at_new
        .scan(9, |_| {})
        .unwrap()
        .found
        .iter()
        .map(|f| f.id)
        .collect();
    assert_eq!(ids, vec![8]);
    drop(at_new);
    let mut at_old = Bench::new(&bus.link, BaudChoice::Rate(57_600), SILENT_SLACK_US);
    let e = at_old.scan(9, |_| {}).unwrap_err();
    assert!(
        matches!(
            e,
            BenchError::NoneAtRate {
                next: 1_000_000,
                ..
            }
        ),
        "{e}"
    );

    drop(at_old);
    // Checked before the port is opened.
    let mut at_new = Bench::new(&bus.link, BaudChoice::Rate(1_000_000), SLACK_US);
    let e = at_new
        .setup(
            8,
            SetupRequest {
                return_delay_us: Some(3),
                ..SetupRequest::default()
            },
        )
        .unwrap_err();
    assert!(e.to_string().starts_with("return delay 3 us"), "{e}");
}
