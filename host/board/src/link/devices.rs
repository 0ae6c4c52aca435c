//! Finding boards: USB serial ports with the board's vendor and product ID.

use protocol::{USB_PID, USB_VID};

/// A USB serial port that looks like a board (by VID/PID).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BoardPort {
    pub path: String,
    pub serial_number: Option<String>,
    pub manufacturer: Option<String>,
    pub product: Option<String>,
}

/// USB serial ports whose VID/PID are the board's ([`protocol::USB_VID`], [`protocol::USB_PID`]).
pub fn list_boards() -> Result<Vec<BoardPort>, serialport::Error> {
    let mut out = Vec::new();
    for p in serialport::available_ports()? {
        if let serialport::SerialPortType::UsbPort(usb) = p.port_type
            && usb.vid == USB_VID
            && usb.pid == USB_PID
        {
            out.push(BoardPort {
                path: p.port_name,
                serial_number: usb.serial_number,
                manufacturer: usb.manufacturer,
                product: usb.product,
            });
        }
    }
    out.sort_by(|a, b| a.path.cmp(&b.path));
    Ok(out)
}
