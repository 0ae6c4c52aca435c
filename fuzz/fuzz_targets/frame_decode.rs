//! Frame decoding: any byte stream, delivered in any chunking, gives messages or errors and never
//! panics; a decoded message re-encodes to a frame that decodes to the same message. With the first
//! byte's top bit set the rest is taken as a message body and gets a valid CRC and COBS encoding, so
//! the fuzzer reaches the postcard decoder instead of stopping at the frame CRC.
#![no_main]

use libfuzzer_sys::fuzz_target;
use protocol::{DeviceMessage, FrameAccumulator, HostMessage, frame::encode_frame_vec};
use serde::Serialize;
use serde::de::DeserializeOwned;

fn check<T: Serialize + DeserializeOwned + PartialEq + core::fmt::Debug>(data: &[u8], chunk: usize) {
    let mut acc = FrameAccumulator::new();
    for piece in data.chunks(chunk) {
        let decoded: Vec<_> = acc.messages::<T>(piece).collect();
        for message in decoded.into_iter().flatten() {
            let frame = encode_frame_vec(&message).expect("a decoded message fits a frame");
            let mut again = FrameAccumulator::new();
            let back: Vec<_> = again.messages::<T>(&frame).collect();
            assert_eq!(back.len(), 1);
            assert_eq!(back[0].as_ref().ok(), Some(&message));
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&first, rest)) = data.split_first() else { return };
    let chunk = usize::from(first & 0x7F).max(1);
    if first & 0x80 == 0 {
        check::<HostMessage>(rest, chunk);
        check::<DeviceMessage>(rest, chunk);
        return;
    }
    let mut body = rest.to_vec();
    body.extend(protocol::crc32::checksum(rest).to_le_bytes());
    let _ = protocol::decode_message::<HostMessage>(&body);
    let _ = protocol::decode_message::<DeviceMessage>(&body);
    let mut framed = cobs_encode(&body);
    framed.push(0);
    check::<HostMessage>(&framed, chunk);
    check::<DeviceMessage>(&framed, chunk);
});

/// COBS written out here (not the crate's encoder) so that the fuzzer feeds frames the crate did
/// not produce itself.
fn cobs_encode(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0];
    let mut code_at = 0;
    for &b in data {
        if b == 0 {
            out[code_at] = (out.len() - code_at) as u8;
            code_at = out.len();
            out.push(0);
        } else {
            out.push(b);
            if out.len() - code_at == 0xFF {
                out[code_at] = 0xFF;
                code_at = out.len();
                out.push(0);
            }
        }
    }
    out[code_at] = (out.len() - code_at) as u8;
    out
}
