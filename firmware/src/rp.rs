//! Board bring-up on the RP2040 with embassy: USB CDC-ACM link, bus UART, defmt logging.

use defmt::{info, unwrap, warn};
use defmt_rtt as _;
use embassy_executor::Spawner;
use embassy_rp::bind_interrupts;
use embassy_rp::gpio::{Level, Output};
use embassy_rp::peripherals::{UART0, USB};
use embassy_rp::uart::{self, BufferedInterruptHandler, BufferedUart};
use embassy_rp::usb::{self, Driver};
use embassy_usb::UsbDevice;
use embassy_usb::class::cdc_acm::{CdcAcmClass, State};
use panic_probe as _;
use static_cell::StaticCell;

bind_interrupts!(struct Irqs {
    USBCTRL_IRQ => usb::InterruptHandler<USB>;
    UART0_IRQ => BufferedInterruptHandler<UART0>;
});

type UsbDriver = Driver<'static, USB>;

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let p = embassy_rp::init(Default::default());
    info!(
        "drosophibot firmware {} (protocol {}), gait store {=u32:#x}+{=u32:#x}",
        env!("CARGO_PKG_VERSION"),
        protocol::PROTOCOL_VERSION,
        firmware::memory_map::GAIT_STORE_OFFSET,
        firmware::memory_map::GAIT_STORE_SIZE
    );

    // USB CDC-ACM link to the host.
    let driver = Driver::new(p.USB, Irqs);
    let mut config = embassy_usb::Config::new(protocol::USB_VID, protocol::USB_PID);
    config.manufacturer = Some("Drosophibot");
    config.product = Some(protocol::USB_PRODUCT);
    config.serial_number = Some("0001");
    config.max_power = 100;
    config.max_packet_size_0 = 64;
    static CONFIG_DESC: StaticCell<[u8; 256]> = StaticCell::new();
    static BOS_DESC: StaticCell<[u8; 256]> = StaticCell::new();
    static CONTROL_BUF: StaticCell<[u8; 64]> = StaticCell::new();
    static CDC_STATE: StaticCell<State> = StaticCell::new();
    let mut builder = embassy_usb::Builder::new(
        driver,
        config,
        CONFIG_DESC.init([0; 256]),
        BOS_DESC.init([0; 256]),
        &mut [],
        CONTROL_BUF.init([0; 64]),
    );
    let class = CdcAcmClass::new(&mut builder, CDC_STATE.init(State::new()), 64);
    spawner.spawn(unwrap!(usb_task(builder.build())));
    spawner.spawn(unwrap!(link_task(class)));

    // Half-duplex Dynamixel bus: UART0 at 1 Mbps, direction pin low = listen.
    static TX_BUF: StaticCell<[u8; 256]> = StaticCell::new();
    static RX_BUF: StaticCell<[u8; 1024]> = StaticCell::new();
    let mut uart_config = uart::Config::default();
    uart_config.baudrate = 1_000_000;
    let bus = BufferedUart::new(
        p.UART0,
        p.PIN_0,
        p.PIN_1,
        Irqs,
        TX_BUF.init([0; 256]),
        RX_BUF.init([0; 1024]),
        uart_config,
    );
    let direction = Output::new(p.PIN_2, Level::Low);
    info!("bus UART up at {} baud", uart_config.baudrate);
    spawner.spawn(unwrap!(bus_task(bus, direction)));
}

#[embassy_executor::task]
async fn usb_task(mut usb: UsbDevice<'static, UsbDriver>) -> ! {
    usb.run().await
}

/// Host link: for now it counts the bytes of each connection (the protocol dispatcher comes with the
/// firmware issue).
#[embassy_executor::task]
async fn link_task(mut class: CdcAcmClass<'static, UsbDriver>) -> ! {
    let mut buf = [0u8; 64];
    loop {
        class.wait_connection().await;
        info!("host connected");
        let mut received = 0usize;
        while let Ok(n) = class.read_packet(&mut buf).await {
            received += n;
        }
        warn!("host disconnected after {} bytes", received);
    }
}

/// Bus owner: holds the UART and the direction pin idle (listening) until the bus loop lands.
#[embassy_executor::task]
async fn bus_task(_bus: BufferedUart, _direction: Output<'static>) -> ! {
    loop {
        embassy_time::Timer::after_secs(1).await;
    }
}
