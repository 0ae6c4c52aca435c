//! The error of a host link that has gone away (USB unplugged on the board, the pipe closed in a
//! test): [`super::serve`] ends with `LinkEnd::Dropped` on it and the board carries on.

/// The host link is down.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LinkDown;

impl core::fmt::Display for LinkDown {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("USB link down")
    }
}

impl core::error::Error for LinkDown {}

impl embedded_io_async::Error for LinkDown {
    fn kind(&self) -> embedded_io_async::ErrorKind {
        embedded_io_async::ErrorKind::NotConnected
    }
}
