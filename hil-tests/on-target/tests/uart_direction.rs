//! On-target: the half-duplex bus turnaround the firmware relies on, on real silicon. BUSY stays set
//! until the last stop bit has left the pin while `blocking_flush` returns earlier (so the direction pin
//! must wait for BUSY), and a Dynamixel PING sent with the direction pin high and answered after it
//! drops gets the servo's status packet (needs servo ID 1 on the bus, powered).
#![no_std]
#![no_main]

use hil_on_target as _;

#[cfg(test)]
#[embedded_test::tests]
mod tests {
    use embassy_rp::bind_interrupts;
    use embassy_rp::gpio::{Level, Output};
    use embassy_rp::peripherals::UART0;
    use embassy_rp::uart::{self, BufferedInterruptHandler, BufferedUart};
    use embassy_time::{Duration, Instant, with_timeout};
    use embedded_io_async::{Read, Write};
    use static_cell::StaticCell;

    bind_interrupts!(struct Irqs {
        UART0_IRQ => BufferedInterruptHandler<UART0>;
    });

    struct Bus {
        uart: BufferedUart,
        direction: Output<'static>,
    }

    #[init]
    fn init() -> Bus {
        let p = embassy_rp::init(Default::default());
        static TX: StaticCell<[u8; 256]> = StaticCell::new();
        static RX: StaticCell<[u8; 256]> = StaticCell::new();
        let mut config = uart::Config::default();
        config.baudrate = hil_on_target::BUS_BAUD;
        let uart = BufferedUart::new(
            p.UART0,
            p.PIN_0,
            p.PIN_1,
            Irqs,
            TX.init([0; 256]),
            RX.init([0; 256]),
            config,
        );
        Bus {
            uart,
            direction: Output::new(p.PIN_2, Level::Low),
        }
    }

    /// 8 bytes at 1 Mbaud 8N1 occupy the wire for 8 x 10 us = 80 us; BUSY must cover all of it.
    #[test]
    async fn busy_covers_the_last_stop_bit(mut bus: Bus) {
        bus.direction.set_high();
        let start = Instant::now();
        bus.uart.write_all(&[0x55; 8]).await.unwrap();
        bus.uart.flush().await.unwrap();
        let flushed = start.elapsed();
        while bus.uart.busy() {}
        let idle = start.elapsed();
        bus.direction.set_low();
        defmt::info!("flush after {} us, BUSY clear after {} us", flushed.as_micros(), idle.as_micros());
        // 1 us timer resolution: allow one tick.
        assert!(idle.as_micros() >= 79, "BUSY cleared before the last stop bit");
        assert!(flushed < idle, "flush waited for BUSY: the turnaround check would be moot");
    }

    /// PING to ID 1 (e-manual Protocol 2.0 example): FF FF FD 00 01 03 00 01 19 4E. The status packet
    /// is 14 bytes: header, ID 1, length 7, instruction 0x55, error, model number, firmware version, CRC.
    #[test]
    #[timeout(5)]
    async fn ping_through_direction_switching(mut bus: Bus) {
        let ping = [0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01, 0x19, 0x4E];
        bus.direction.set_high();
        bus.uart.write_all(&ping).await.unwrap();
        bus.uart.flush().await.unwrap();
        while bus.uart.busy() {}
        bus.direction.set_low();
        let mut status = [0u8; 14];
        with_timeout(Duration::from_millis(10), bus.uart.read_exact(&mut status))
            .await
            .expect("no status packet from servo 1 within 10 ms")
            .unwrap();
        assert_eq!(status[..8], [0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55]);
        assert_eq!(status[8], 0, "servo reported error {:#x}", status[8]);
    }
}
