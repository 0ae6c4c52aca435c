//! A serial port (U2D2 or any USB-TTL adapter that switches direction itself) as the bus
//! master's `Read + Write` and [`Clock`], with a small blocking executor, so `dbot dxl` reuses
//! the no_std bus master.
//!
//! How it waits: `read` does a blocking read of at most one poll interval; when nothing came it
//! yields once, so the deadline future beside it gets polled and the executor loops. Wall-clock
//! deadlines are thus honoured to within that interval (1 ms).

use dynamixel::master::{AutoDirection, BusMaster, Clock, MasterConfig};
use std::future::Future;
use std::io::{Read as _, Write as _};
use std::pin::pin;
use std::task::{Context, Poll, Waker};
use std::time::{Duration, Instant};

/// How long one blocking read may wait before the executor checks deadlines again.
const POLL_INTERVAL: Duration = Duration::from_millis(1);

/// Errors of the serial client.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SerialError {
    #[error("cannot open serial port {port} at {baud} bit/s")]
    Open {
        port: String,
        baud: u32,
        source: serialport::Error,
    },
    #[error("cannot set serial port {port} to {baud} bit/s")]
    SetBaud {
        port: String,
        baud: u32,
        source: serialport::Error,
    },
}

/// A serial port as the master's UART.
pub struct SerialIo {
    port: Box<dyn serialport::SerialPort>,
    name: String,
}

impl std::fmt::Debug for SerialIo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SerialIo")
            .field("port", &self.name)
            .finish()
    }
}

impl SerialIo {
    pub fn open(port: &str, baud: u32) -> Result<Self, SerialError> {
        let p = serialport::new(port, baud)
            .timeout(POLL_INTERVAL)
            .open()
            .map_err(|source| SerialError::Open {
                port: port.to_string(),
                baud,
                source,
            })?;
        Ok(Self {
            port: p,
            name: port.to_string(),
        })
    }

    pub fn set_baud(&mut self, baud: u32) -> Result<(), SerialError> {
        self.port
            .set_baud_rate(baud)
            .map_err(|source| SerialError::SetBaud {
                port: self.name.clone(),
                baud,
                source,
            })
    }
}

impl embedded_io_async::ErrorType for SerialIo {
    type Error = std::io::Error;
}

impl embedded_io_async::Read for SerialIo {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        loop {
            match self.port.read(buf) {
                Ok(0) => {}
                Ok(n) => return Ok(n),
                Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {}
                Err(e) => return Err(e),
            }
            yield_once().await;
        }
    }
}

impl embedded_io_async::ReadReady for SerialIo {
    fn read_ready(&mut self) -> Result<bool, Self::Error> {
        Ok(self.port.bytes_to_read().map_err(std::io::Error::from)? > 0)
    }
}

impl embedded_io_async::Write for SerialIo {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        self.port.write(buf)
    }

    async fn flush(&mut self) -> Result<(), Self::Error> {
        self.port.flush()
    }
}

/// Wall-clock time since creation.
#[derive(Debug, Clone, Copy)]
pub struct StdClock {
    epoch: Instant,
}

impl Default for StdClock {
    fn default() -> Self {
        Self {
            epoch: Instant::now(),
        }
    }
}

impl Clock for StdClock {
    fn now_us(&self) -> u64 {
        self.epoch.elapsed().as_micros() as u64
    }

    async fn wait_until(&self, deadline_us: u64) {
        loop {
            let now = self.now_us();
            if now >= deadline_us {
                return;
            }
            // Short sleeps keep a racing read responsive; the read itself blocks for up to 1 ms.
            std::thread::sleep(Duration::from_micros((deadline_us - now).min(200)));
            yield_once().await;
        }
    }
}

async fn yield_once() {
    let mut yielded = false;
    std::future::poll_fn(|_| {
        if yielded {
            Poll::Ready(())
        } else {
            yielded = true;
            Poll::Pending
        }
    })
    .await
}

/// Polls `fut` in a loop until it completes (its futures never park).
pub fn block_on<F: Future>(fut: F) -> F::Output {
    let mut fut = pin!(fut);
    let mut cx = Context::from_waker(Waker::noop());
    loop {
        if let Poll::Ready(v) = fut.as_mut().poll(&mut cx) {
            return v;
        }
    }
}

/// The bus master on a serial adapter.
pub type SerialMaster = BusMaster<SerialIo, AutoDirection, StdClock>;

/// Opens `port` at `baud` with `reply_slack_us` of slack per reply (USB adapters add latency:
/// FTDI's latency timer is 16 ms by default, the U2D2's is usually set to 1 ms).
pub fn open_master(
    port: &str,
    baud: u32,
    reply_slack_us: u32,
) -> Result<SerialMaster, SerialError> {
    let io = SerialIo::open(port, baud)?;
    Ok(BusMaster::new(
        io,
        AutoDirection,
        StdClock::default(),
        MasterConfig {
            baud,
            reply_slack_us,
        },
    ))
}
