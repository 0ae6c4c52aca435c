//! Bounded fuzzing in the normal suite (the cargo-fuzz targets in ../fuzz run the same checks
//! unbounded): arbitrary bytes give a value or an error, never a panic or an out-of-bounds read,
//! and the receiver recovers at the next frame.

use crate::common;
use proptest::collection::vec;
use proptest::prelude::*;
use protocol::gait::{GaitTable, HEADER_LEN, MAGIC, TableError};
use protocol::*;

fn encode<T: serde::Serialize>(m: &T) -> Vec<u8> {
    protocol::frame::encode_frame_vec(m).unwrap()
}

/// Whatever decodes survives a round trip. (Not byte-identical: postcard accepts over-long varints
/// such as `81 80 00` for 1, so one message has several spellings; only the value matters.)
fn reencoded<T: serde::Serialize + serde::de::DeserializeOwned>(m: &T) -> T {
    let mut acc = FrameAccumulator::new();
    let mut out: Vec<_> = acc.messages::<T>(&encode(m)).collect();
    out.pop().unwrap().unwrap()
}

proptest! {
    #![proptest_config(common::config(1000))]

    #[test]
    fn arbitrary_bytes_never_panic_the_frame_decoder(bytes in vec(any::<u8>(), 0..2000)) {
        let mut acc = FrameAccumulator::new();
        let zeros = bytes.iter().filter(|&&b| b == 0).count();
        let n = acc.messages::<HostMessage>(&bytes).count();
        // At most one result per delimiter (empty frames give none).
        prop_assert!(n <= zeros);
        let mut acc = FrameAccumulator::new();
        prop_assert!(acc.messages::<DeviceMessage>(&bytes).count() <= zeros);
    }

    /// Arbitrary message bodies with a valid CRC reach the postcard decoder: a value or an error.
    #[test]
    fn arbitrary_bodies_with_a_valid_crc_decode_or_fail_cleanly(body in vec(any::<u8>(), 0..700)) {
        let mut raw = body.clone();
        raw.extend(protocol::crc32::checksum(&body).to_le_bytes());
        if let Ok(m) = protocol::decode_message::<HostMessage>(&raw) {
            prop_assert_eq!(reencoded(&m), m);
        }
        if let Ok(m) = protocol::decode_message::<DeviceMessage>(&raw) {
            prop_assert_eq!(reencoded(&m), m);
        }
    }

    /// Valid encodings with one byte changed or cut short: deep into the decoder, never a panic.
    #[test]
    fn mutated_message_bodies_decode_or_fail_cleanly(
        msg in common::device_message(),
        at in any::<usize>(),
        value in any::<u8>(),
        cut in any::<bool>(),
    ) {
        let mut body = postcard::to_allocvec(&msg).unwrap();
        let i = at % body.len();
        if cut { body.truncate(i) } else { body[i] = value }
        let mut raw = body.clone();
        raw.extend(protocol::crc32::checksum(&body).to_le_bytes());
        if let Ok(m) = protocol::decode_message::<DeviceMessage>(&raw) {
            prop_assert_eq!(reencoded(&m), m);
        }
    }

    #[test]
    fn the_next_frame_after_garbage_is_recovered(
        garbage in vec(any::<u8>(), 0..1500),
        msg in common::host_message(),
    ) {
        let mut stream = garbage;
        stream.push(0); // the sender's delimiter that ends whatever the garbage was
        stream.extend(encode(&msg));
        let mut acc = FrameAccumulator::new();
        let out: Vec<_> = acc.messages::<HostMessage>(&stream).collect();
        prop_assert_eq!(out.last(), Some(&Ok(msg)));
    }

    #[test]
    fn a_corrupted_frame_is_an_error_never_another_message(
        msg in common::device_message(),
        at in any::<usize>(),
        flip in 1u8..=255,
    ) {
        let mut frame = encode(&msg);
        let i = at % (frame.len() - 1);
        frame[i] ^= flip;
        let mut acc = FrameAccumulator::new();
        for out in acc.messages::<DeviceMessage>(&frame) {
            match out {
                Err(_) => {}
                // Only a different COBS spelling of the same bytes may decode.
                Ok(m) => prop_assert_eq!(m, msg.clone()),
            }
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic_table_validation(bytes in vec(any::<u8>(), 0..600)) {
        let _ = GaitTable::parse(&bytes);
    }

    /// A valid table with one byte changed and the CRC fixed up: validation reaches every check.
    #[test]
    fn mutated_valid_tables_never_panic(
        g in common::random_gait(6, 6),
        at in any::<usize>(),
        value in any::<u8>(),
    ) {
        let mut t = g.builder().build().unwrap();
        let n = t.len();
        t[at % (n - 4)] = value;
        let crc = protocol::crc32::checksum(&t[..n - 4]);
        t[n - 4..].copy_from_slice(&crc.to_le_bytes());
        if let Ok(table) = GaitTable::parse(&t) {
            for s in 0..=table.slice_count() {
                for j in 0..=table.joint_count() {
                    if let (Some(map), Some(angle)) = (table.joint(j), table.angle(s, j)) {
                        prop_assert!(map.min <= angle && angle <= map.max);
                    }
                }
            }
        }
    }

    /// Random bytes behind a plausible header with the right length and CRC, so validation gets past
    /// the cheap checks and reads joint records and slices.
    #[test]
    fn plausible_tables_with_random_contents_never_panic(
        joints in 0u8..=40,
        slices in 0u16..=20,
        body in vec(any::<u8>(), 0..4000),
        tail in vec(any::<u8>(), 0..8),
    ) {
        let len = gait::table_len(joints.into(), slices.into());
        let mut t = vec![0u8; len.max(HEADER_LEN + 4)];
        for (dst, src) in t.iter_mut().zip(body.iter()) {
            *dst = *src;
        }
        t[..4].copy_from_slice(&MAGIC);
        t[4..6].copy_from_slice(&gait::FORMAT_VERSION.to_le_bytes());
        t[6] = joints;
        t[8..10].copy_from_slice(&slices.to_le_bytes());
        t[16..20].copy_from_slice(&(len as u32).to_le_bytes());
        let n = t.len();
        let crc = protocol::crc32::checksum(&t[..n - 4]);
        t[n - 4..].copy_from_slice(&crc.to_le_bytes());
        t.extend(tail);
        match GaitTable::parse(&t) {
            Ok(table) => {
                // Every accessor stays in bounds, including one past the end.
                for s in 0..=table.slice_count() {
                    let _ = table.stance(s);
                    for j in 0..=table.joint_count() {
                        let _ = (table.joint(j), table.angle(s, j), table.torque(s, j));
                    }
                }
            }
            Err(e) => {
                let cheap = matches!(e, TableError::Crc { .. } | TableError::BadMagic { .. });
                prop_assert!(!cheap, "{:?}", e);
            }
        }
    }
}

#[test]
fn an_oversized_frame_is_too_long_and_the_next_one_decodes() {
    let mut stream = vec![0x42; 3 * MAX_FRAME_LEN];
    stream.push(0);
    let msg = HostMessage::Request {
        seq: 1,
        request: Request::EmergencyStop,
    };
    stream.extend(encode(&msg));
    let mut acc = FrameAccumulator::new();
    let out: Vec<_> = acc.messages::<HostMessage>(&stream).collect();
    assert_eq!(out, vec![Err(FrameError::TooLong), Ok(msg)]);
}

#[test]
fn each_malformation_has_its_own_error() {
    let mut acc = FrameAccumulator::new();
    // A code byte promising 5 bytes, then the delimiter after 2: broken COBS.
    assert_eq!(
        acc.messages::<HostMessage>(&[0x06, 1, 2, 0])
            .collect::<Vec<_>>(),
        vec![Err(FrameError::Cobs)]
    );
    // Three bytes cannot hold a CRC.
    assert_eq!(
        acc.messages::<HostMessage>(&[0x04, 1, 2, 3, 0])
            .collect::<Vec<_>>(),
        vec![Err(FrameError::TooShort { len: 3 })]
    );
    // A good frame with its last CRC byte changed: the CRC check names both values.
    let mut frame = encode(&HostMessage::Request {
        seq: 300,
        request: Request::GetStatus,
    });
    let n = frame.len();
    frame[n - 2] ^= 0x01;
    let out: Vec<_> = acc.messages::<HostMessage>(&frame).collect();
    assert!(matches!(out[..], [Err(FrameError::Crc { .. })]), "{out:?}");
    // A valid frame of an unknown Request variant (index 200): postcard refuses it.
    let body = [0x00, 0x01, 0xC8, 0x01];
    let mut raw = body.to_vec();
    raw.extend(protocol::crc32::checksum(&body).to_le_bytes());
    assert_eq!(
        protocol::decode_message::<HostMessage>(&raw),
        Err(FrameError::Decode)
    );
    // A valid message followed by one extra byte inside the CRC-covered part.
    let body = [0x00, 0x01, 0x01, 0x77];
    let mut raw = body.to_vec();
    raw.extend(protocol::crc32::checksum(&body).to_le_bytes());
    assert_eq!(
        protocol::decode_message::<HostMessage>(&raw),
        Err(FrameError::TrailingBytes { extra: 1 })
    );
}

#[test]
fn empty_frames_and_repeated_delimiters_are_ignored() {
    let msg = HostMessage::Request {
        seq: 9,
        request: Request::Stop,
    };
    let mut stream = vec![0, 0, 0];
    stream.extend(encode(&msg));
    stream.extend([0, 0]);
    let mut acc = FrameAccumulator::new();
    assert_eq!(
        acc.messages::<HostMessage>(&stream).collect::<Vec<_>>(),
        vec![Ok(msg)]
    );
}

#[test]
fn a_chunk_larger_than_max_chunk_len_is_a_decode_error() {
    // UploadChunk with 513 data bytes, hand-built: 00 (Request) 00 (seq 0) 04 (UploadChunk)
    // 00 (offset 0) 81 04 (length 513) then 513 x 0x55.
    let mut body = vec![0x00, 0x00, 0x04, 0x00, 0x81, 0x04];
    body.extend([0x55; MAX_CHUNK_LEN + 1]);
    let mut raw = body.clone();
    raw.extend(protocol::crc32::checksum(&body).to_le_bytes());
    assert_eq!(
        protocol::decode_message::<HostMessage>(&raw),
        Err(FrameError::Decode)
    );
    // The same with 512 bytes decodes.
    let mut body = vec![0x00, 0x00, 0x04, 0x00, 0x80, 0x04];
    body.extend([0x55; MAX_CHUNK_LEN]);
    let mut raw = body.clone();
    raw.extend(protocol::crc32::checksum(&body).to_le_bytes());
    assert!(matches!(
        protocol::decode_message::<HostMessage>(&raw),
        Ok(HostMessage::Request { request: Request::UploadChunk { offset: 0, ref data }, .. }) if data.len() == MAX_CHUNK_LEN
    ));
}

#[test]
fn encoding_into_a_short_buffer_is_an_error() {
    let msg = HostMessage::Request {
        seq: 300,
        request: Request::GetStatus,
    };
    for len in 0..10 {
        let mut buf = vec![0u8; len];
        assert_eq!(
            encode_frame(&msg, &mut buf),
            Err(FrameError::BufferTooSmall),
            "buffer of {len}"
        );
    }
    let mut buf = [0u8; 10];
    assert_eq!(encode_frame(&msg, &mut buf).unwrap().len(), 10);
}
