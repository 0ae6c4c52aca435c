//! Board bring-up on the RP2040 with embassy, and the seams of the firmware library on real
//! hardware: the gait store on the QSPI flash (written through embassy-rp's flash driver, read in
//! place through the XIP window), the half-duplex Dynamixel bus on UART0 with a direction pin
//! (pins from `firmware::pins`, the table docs/hardware.md shows), the
//! embassy-time clock, the USB CDC-ACM link, and the watchdog.
//!
//! Tasks: `bus_task` runs the fixed-rate bus loop and feeds the watchdog; `link_task` serves the host;
//! `usb_task` runs the USB device. The controller sits in a thread-mode mutex between the first two.

#[cfg(not(feature = "defmt"))]
compile_error!(
    "the image logs state changes and faults with defmt (src/device_log.rs): build it with the \
     firmware's default features, not --no-default-features"
);

use core::cell::RefCell;

use defmt::{info, unwrap, warn};
use defmt_rtt as _;
use dynamixel::master::{BusMaster, Clock, DirectionPin, MasterConfig};
use embassy_executor::Spawner;
use embassy_rp::bind_interrupts;
use embassy_rp::flash::{Blocking, Flash};
use embassy_rp::gpio::{Level, Output};
use embassy_rp::peripherals::{FLASH, UART0, USB};
use embassy_rp::uart::{self, BufferedInterruptHandler, BufferedUart};
use embassy_rp::usb::{self, Driver};
use embassy_rp::watchdog::{ResetReason, Watchdog};
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::ThreadModeRawMutex;
use embassy_time::{Duration, Instant, Timer};
use embassy_usb::UsbDevice;
use embassy_usb::class::cdc_acm::{CdcAcmClass, State};
use embedded_storage::nor_flash::{ErrorType, NorFlash, ReadNorFlash};
use firmware::bus_loop::{BusLoop, Shared};
use firmware::controller::{Config, Controller};
use firmware::link::{Link, LinkDown, serve};
use firmware::memory_map::{FLASH_BASE, FLASH_SIZE, GAIT_STORE_OFFSET, GAIT_STORE_SIZE};
use firmware::pins;
use firmware::store::{BOARD_SLOTS, FlashWindow};
use panic_probe as _;
use static_cell::StaticCell;

bind_interrupts!(struct Irqs {
    USBCTRL_IRQ => usb::InterruptHandler<USB>;
    UART0_IRQ => BufferedInterruptHandler<UART0>;
});

type UsbDriver = Driver<'static, USB>;
type Ctl = Controller<GaitFlash>;

/// The watchdog resets a firmware whose bus loop has not completed a cycle for this long (a cycle
/// is at most 20 ms; a sector erase during an upload stalls up to about 400 ms worst case).
const WATCHDOG_TIMEOUT: Duration = Duration::from_millis(1000);

/// The gait region of the QSPI flash: offset 0 = `GAIT_STORE_OFFSET` of the chip.
struct GaitFlash {
    flash: Flash<'static, FLASH, Blocking, { FLASH_SIZE as usize }>,
}

impl ErrorType for GaitFlash {
    type Error = embassy_rp::flash::Error;
}

impl ReadNorFlash for GaitFlash {
    const READ_SIZE: usize = 1;
    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
        self.flash.blocking_read(GAIT_STORE_OFFSET + offset, bytes)
    }
    fn capacity(&self) -> usize {
        GAIT_STORE_SIZE as usize
    }
}

impl NorFlash for GaitFlash {
    const WRITE_SIZE: usize = embassy_rp::flash::WRITE_SIZE;
    const ERASE_SIZE: usize = embassy_rp::flash::ERASE_SIZE;
    fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
        self.flash
            .blocking_erase(GAIT_STORE_OFFSET + from, GAIT_STORE_OFFSET + to)
    }
    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        self.flash.blocking_write(GAIT_STORE_OFFSET + offset, bytes)
    }
}

impl FlashWindow for GaitFlash {
    fn window(&self) -> &[u8] {
        // SAFETY: the gait region is mapped read-only by XIP for the whole run time and lies outside
        // the image (memory.x asserts it). Its bytes only change through `NorFlash::erase/write`,
        // which take `&mut self`, so no slice handed out here is alive while they change; embassy-rp
        // flushes the XIP cache after each program/erase.
        unsafe {
            core::slice::from_raw_parts(
                (FLASH_BASE + GAIT_STORE_OFFSET) as *const u8,
                GAIT_STORE_SIZE as usize,
            )
        }
    }
}

/// The controller between the bus and the link task (both in thread mode on core 0).
struct Board(Mutex<ThreadModeRawMutex, RefCell<Ctl>>);

impl Shared<Ctl> for Board {
    fn with<R>(&self, f: impl FnOnce(&mut Ctl) -> R) -> R {
        self.0.lock(|c| f(&mut c.borrow_mut()))
    }
}

/// embassy-time as the library's clock.
struct EmbassyClock;

impl Clock for EmbassyClock {
    fn now_us(&self) -> u64 {
        Instant::now().as_micros()
    }
    async fn wait_until(&self, deadline_us: u64) {
        Timer::at(Instant::from_micros(deadline_us)).await
    }
}

/// The tri-state buffer's direction pin (high = drive the bus).
struct Direction(Output<'static>);

impl DirectionPin for Direction {
    fn drive(&mut self) {
        self.0.set_high();
    }
    async fn release_after_tx(&mut self) {
        // `write` returned once the bytes were in the FIFO; BUSY stays set until the last stop bit
        // has left the shift register. Spin, never yield: a servo at Return Delay Time 0 answers
        // about 50 us after our last stop bit, and a task holding the executor past that would cost
        // its reply (seen in the emulator with telemetry every cycle). The spin is at most a FIFO of
        // 32 bytes: 320 us at 1 Mbaud, 80 us at 4 Mbaud.
        while embassy_rp::pac::UART0.uartfr().read().busy() {
            core::hint::spin_loop();
        }
        self.0.set_low();
    }
}

/// The bus UART as the bus master sees it: reads are async (the receive interrupt fills the ring
/// buffer); writes are blocking and go straight into the TX FIFO from the bus task, so that driving
/// the direction pin, sending a request and releasing the pin after its last stop bit happen in one
/// run of the bus task that no other task can interrupt.
///
/// A request leaves the pin as one unbroken run of characters: a servo takes a pause inside a
/// packet for its end, so a gap turns a Sync Write into a corrupt packet that no servo obeys.
/// BufferedUart's own write refills the FIFO from the UART interrupt, which fires when 4 characters
/// are left (10 us at 4 Mbaud); any other interrupt handler or critical section running at that
/// moment emptied the FIFO (seen in the emulator while streaming at 4 Mbaud). Here the bytes are
/// written with interrupts masked until the last one is in the FIFO: the masked time is the wire
/// time of all but the FIFO's 32 characters (a 22-servo Sync Write of 124 bytes: 0.92 ms at
/// 1 Mbaud, 0.23 ms at 4 Mbaud; 16 ms at 57600 baud), in which the link task could not run anyway;
/// interrupts (USB, timer) are served after it.
struct BusUart(BufferedUart);

impl embedded_io_async::ErrorType for BusUart {
    type Error = uart::Error;
}

impl embedded_io_async::Read for BusUart {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, uart::Error> {
        embedded_io_async::Read::read(&mut self.0, buf).await
    }
}

impl embedded_io_async::ReadReady for BusUart {
    fn read_ready(&mut self) -> Result<bool, uart::Error> {
        embedded_io_async::ReadReady::read_ready(&mut self.0)
    }
}

impl embedded_io_async::Write for BusUart {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, uart::Error> {
        // Nothing ever goes through the ring buffer of TX (the interrupt handler finds it empty and
        // leaves the FIFO alone), so the FIFO holds this request's bytes only.
        let regs = embassy_rp::pac::UART0;
        cortex_m::interrupt::free(|_| {
            for &byte in buf {
                while regs.uartfr().read().txff() {
                    core::hint::spin_loop();
                }
                regs.uartdr().write(|w| w.set_data(byte));
            }
        });
        Ok(buf.len())
    }
    async fn flush(&mut self) -> Result<(), uart::Error> {
        // Every byte is in the FIFO once `write` returns; `release_after_tx` waits for BUSY.
        Ok(())
    }
}

/// USB CDC-ACM as a byte stream for the link handler.
struct CdcStream {
    class: CdcAcmClass<'static, UsbDriver>,
    rx: [u8; 64],
    rx_len: usize,
    rx_pos: usize,
    /// The last packet written was full-size: the host needs a zero-length packet to see the end.
    zlp_due: bool,
}

impl embedded_io_async::ErrorType for CdcStream {
    type Error = LinkDown;
}

impl embedded_io_async::Read for CdcStream {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, LinkDown> {
        if self.rx_pos == self.rx_len {
            self.rx_len = self
                .class
                .read_packet(&mut self.rx)
                .await
                .map_err(|_| LinkDown)?;
            self.rx_pos = 0;
        }
        let n = buf.len().min(self.rx_len - self.rx_pos);
        buf[..n].copy_from_slice(&self.rx[self.rx_pos..self.rx_pos + n]);
        self.rx_pos += n;
        Ok(n)
    }
}

impl embedded_io_async::Write for CdcStream {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, LinkDown> {
        let max = usize::from(self.class.max_packet_size());
        let n = buf.len().min(max);
        self.class
            .write_packet(&buf[..n])
            .await
            .map_err(|_| LinkDown)?;
        self.zlp_due = n == max;
        Ok(n)
    }
    async fn flush(&mut self) -> Result<(), LinkDown> {
        if self.zlp_due {
            self.class.write_packet(&[]).await.map_err(|_| LinkDown)?;
            self.zlp_due = false;
        }
        Ok(())
    }
}

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let p = embassy_rp::init(Default::default());
    info!(
        "drosophibot firmware {} (protocol {}), gait store {=u32:#x}+{=u32:#x}",
        env!("CARGO_PKG_VERSION"),
        protocol::PROTOCOL_VERSION,
        GAIT_STORE_OFFSET,
        GAIT_STORE_SIZE
    );

    let mut watchdog = Watchdog::new(p.WATCHDOG);
    let after_watchdog = matches!(watchdog.reset_reason(), Some(ResetReason::TimedOut));
    watchdog.pause_on_debug(true);

    // Gait store and controller.
    let flash = GaitFlash {
        flash: Flash::new_blocking(p.FLASH),
    };
    // The host-loss rule is on in the image: a killed host does not leave the robot walking.
    let config = Config {
        host_timeout_cycles: protocol::limits::HOST_TIMEOUT_CYCLES,
        ..Config::default()
    };
    static BOARD: StaticCell<Board> = StaticCell::new();
    let mut controller = Controller::new(flash, BOARD_SLOTS, config);
    if after_watchdog {
        warn!("reset by the watchdog: staying safe until the host clears the fault");
        controller.watchdog_reset();
    }
    let board: &'static Board = BOARD.init(Board(Mutex::new(RefCell::new(controller))));

    // USB CDC-ACM link to the host.
    let driver = Driver::new(p.USB, Irqs);
    let mut usb_config = embassy_usb::Config::new(protocol::USB_VID, protocol::USB_PID);
    usb_config.manufacturer = Some("Drosophibot");
    usb_config.product = Some(protocol::USB_PRODUCT);
    usb_config.serial_number = Some("0001");
    usb_config.max_power = 100;
    usb_config.max_packet_size_0 = 64;
    static CONFIG_DESC: StaticCell<[u8; 256]> = StaticCell::new();
    static BOS_DESC: StaticCell<[u8; 256]> = StaticCell::new();
    static CONTROL_BUF: StaticCell<[u8; 64]> = StaticCell::new();
    static CDC_STATE: StaticCell<State> = StaticCell::new();
    let mut builder = embassy_usb::Builder::new(
        driver,
        usb_config,
        CONFIG_DESC.init([0; 256]),
        BOS_DESC.init([0; 256]),
        &mut [],
        CONTROL_BUF.init([0; 64]),
    );
    let class = CdcAcmClass::new(&mut builder, CDC_STATE.init(State::new()), 64);
    spawner.spawn(unwrap!(usb_task(builder.build())));
    spawner.spawn(unwrap!(link_task(class, board)));

    // Half-duplex Dynamixel bus: UART0, direction pin low = listen.
    static TX_BUF: StaticCell<[u8; 256]> = StaticCell::new();
    static RX_BUF: StaticCell<[u8; 1024]> = StaticCell::new();
    let mut uart_config = uart::Config::default();
    uart_config.baudrate = config.baud;
    // The pins are `firmware::pins` (the hardware page's table): change both together.
    const _: () = assert!(
        pins::BUS_UART == 0 && pins::BUS_TX.gpio == 0 && pins::BUS_RX.gpio == 1,
        "rp.rs takes UART0 on PIN_0/PIN_1: follow firmware::pins"
    );
    let uart = BufferedUart::new(
        p.UART0,
        p.PIN_0,
        p.PIN_1,
        Irqs,
        TX_BUF.init([0; 256]),
        RX_BUF.init([0; 1024]),
        uart_config,
    );
    const _: () = assert!(
        pins::BUS_DIRECTION.gpio == 2,
        "rp.rs takes PIN_2 as the direction pin: follow firmware::pins"
    );
    let direction = Direction(Output::new(p.PIN_2, Level::Low));
    info!("bus UART up at {} baud", config.baud);
    watchdog.start(WATCHDOG_TIMEOUT);
    spawner.spawn(unwrap!(bus_task(uart, direction, board, watchdog)));
}

#[embassy_executor::task]
async fn usb_task(mut usb: UsbDevice<'static, UsbDriver>) -> ! {
    usb.run().await
}

/// Host link: serves each connection until it drops, then waits for the next. The controller (and
/// a running gait) does not notice the drop.
#[embassy_executor::task]
async fn link_task(class: CdcAcmClass<'static, UsbDriver>, board: &'static Board) -> ! {
    let mut stream = CdcStream {
        class,
        rx: [0; 64],
        rx_len: 0,
        rx_pos: 0,
        zlp_due: false,
    };
    let mut link = Link::new();
    loop {
        stream.class.wait_connection().await;
        info!("host connected");
        stream.rx_len = 0;
        stream.rx_pos = 0;
        serve(&mut link, board, &mut stream, &EmbassyClock).await;
        warn!("host link dropped");
    }
}

/// The fixed-rate bus loop. Feeding the watchdog here means a hang anywhere (bus, link task hogging
/// the executor, flash) resets the board, which then comes up in the safe state.
#[embassy_executor::task]
async fn bus_task(
    uart: BufferedUart,
    direction: Direction,
    board: &'static Board,
    mut watchdog: Watchdog,
) -> ! {
    let mut baud = board.with(|c| c.config().baud);
    let mut bus = BusMaster::new(BusUart(uart), direction, EmbassyClock, master_config(baud));
    let mut schedule = BusLoop::new();
    loop {
        let want = board.with(|c| c.config().baud);
        if want != baud {
            // Only allowed while nothing moves; the servos must already be set to the new rate.
            let (mut uart, dir, clock) = bus.into_parts();
            uart.0.set_baudrate(want);
            bus = BusMaster::new(uart, dir, clock, master_config(want));
            baud = want;
            info!("bus UART now at {} baud", baud);
        }
        schedule.run_cycle(board, &mut bus).await;
        watchdog.feed(WATCHDOG_TIMEOUT);
    }
}

/// Reply slack for servos set to Return Delay Time 0, with margin for their turnaround
/// (about 50 us reported for the MX-64) and the UART's receive interrupt latency.
fn master_config(baud: u32) -> MasterConfig {
    MasterConfig {
        baud,
        reply_slack_us: 300,
    }
}
