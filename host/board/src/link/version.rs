//! The version check for a board whose `DeviceInfo` reply this host cannot decode as a whole (a
//! board of another protocol version may have added, removed or changed fields).
//!
//! The protocol keeps the start of that reply stable across versions (`protocol/src/lib.rs`,
//! "Versioning": variants are appended, so `DeviceMessage::Reply` stays index 0 and
//! `Response::DeviceInfo` index 1, and `DeviceInfo` begins with the firmware and protocol
//! versions), so the versions can be read from the first bytes and the board refused with a
//! message naming both versions instead of a misleading "no reply".

use protocol::{FRAME_CRC_LEN, FirmwareVersion};

/// What the first bytes of an undecodable `DeviceInfo` reply say.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct ForeignInfo {
    /// Sequence number of the request it answers.
    pub seq: u16,
    pub firmware: FirmwareVersion,
    pub protocol_version: u16,
}

/// Postcard indices of `DeviceMessage::Reply` and `Response::DeviceInfo`.
const REPLY_VARIANT: u32 = 0;
const DEVICE_INFO_VARIANT: u32 = 1;

/// The versions at the start of a decoded frame (message + CRC) that is a `DeviceInfo` reply, if
/// its CRC holds; `None` for anything else.
pub(super) fn device_info_prefix(frame: &[u8]) -> Option<ForeignInfo> {
    let body_len = frame.len().checked_sub(FRAME_CRC_LEN)?;
    let (body, crc) = frame.split_at(body_len);
    if u32::from_le_bytes(crc.try_into().ok()?) != protocol::crc32::checksum(body) {
        return None;
    }
    // Postcard writes an enum's variant index as a varint u32 and a u16 as a varint; whatever
    // follows the protocol version is left unread.
    type Prefix = (u32, u16, u32, u16, u16, u16, u16);
    let ((reply, seq, info, major, minor, patch, protocol_version), _rest) =
        postcard::take_from_bytes::<Prefix>(body).ok()?;
    (reply == REPLY_VARIANT && info == DEVICE_INFO_VARIANT).then_some(ForeignInfo {
        seq,
        firmware: FirmwareVersion {
            major,
            minor,
            patch,
        },
        protocol_version,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::{DeviceInfo, DeviceMessage, FrameAccumulator, Response};

    fn with_crc(body: &[u8]) -> Vec<u8> {
        let mut f = body.to_vec();
        f.extend(protocol::crc32::checksum(body).to_le_bytes());
        f
    }

    #[test]
    fn reads_the_versions_from_hand_encoded_bytes_with_an_unknown_rest() {
        // Reply (0), seq 300 (varint 0xAC 0x02), DeviceInfo (1), firmware 1.2.3, protocol 7, then
        // bytes of fields this host does not know.
        let body = [
            0x00, 0xAC, 0x02, 0x01, 0x01, 0x02, 0x03, 0x07, 0xFF, 0xFF, 0x42,
        ];
        let got = device_info_prefix(&with_crc(&body)).unwrap();
        assert_eq!(got.seq, 300);
        assert_eq!(
            (got.firmware.major, got.firmware.minor, got.firmware.patch),
            (1, 2, 3)
        );
        assert_eq!(got.protocol_version, 7);
    }

    #[test]
    fn refuses_a_bad_crc_and_other_messages() {
        let body = [0x00, 0x05, 0x01, 0x01, 0x02, 0x03, 0x07];
        let mut f = with_crc(&body);
        f[1] ^= 1;
        assert_eq!(device_info_prefix(&f), None);
        // Reply to seq 5 with `Ack` (0), then bytes that would read as versions.
        assert_eq!(
            device_info_prefix(&with_crc(&[0x00, 0x05, 0x00, 1, 2, 3, 7])),
            None
        );
        // Telemetry (variant 1), not a reply.
        assert_eq!(
            device_info_prefix(&with_crc(&[0x01, 0x05, 0x01, 1, 2, 3, 7])),
            None
        );
        assert_eq!(device_info_prefix(&[1, 2]), None);
    }

    #[test]
    fn agrees_with_the_protocol_crates_encoding() {
        // A reply encoded by the protocol crate, with a version from the future.
        let info = DeviceInfo {
            firmware: FirmwareVersion {
                major: 4,
                minor: 0,
                patch: 9,
            },
            protocol_version: protocol::PROTOCOL_VERSION + 1,
            table_format_version: 1,
            build_id: 0xDEAD_BEEF,
            capabilities: protocol::Capabilities::empty(),
            slot_capacity: 64 * 1024,
            max_chunk_len: 256,
            slots: heapless::Vec::new(),
        };
        let msg = DeviceMessage::Reply {
            seq: 9,
            response: Response::DeviceInfo(info.clone()),
        };
        let bytes = protocol::frame::encode_frame_vec(&msg).unwrap();
        let mut acc = FrameAccumulator::new();
        let frame: Vec<u8> = bytes
            .iter()
            .find_map(|&b| acc.push(b).map(|f| f.unwrap().to_vec()))
            .unwrap();
        let got = device_info_prefix(&frame).unwrap();
        assert_eq!(got.seq, 9);
        assert_eq!(got.firmware, info.firmware);
        assert_eq!(got.protocol_version, protocol::PROTOCOL_VERSION + 1);
    }
}
