//! Property tests of the streaming parser: any chunking of valid traffic parses identically,
//! random noise between packets never panics and the packet after it is recovered, and a caller
//! that skips `next_frame` while `awaiting_rest` holds (the simulated servos) gets every frame
//! and rejected packet at the same byte as one that asks at every byte, and so does one that
//! takes `quiet_bytes` bytes at once without asking.

use dynamixel::encode;
use dynamixel::parser::Parser;
use proptest::prelude::*;

/// A packet as sent: id, instruction byte, unstuffed params.
type Packet = (u8, u8, Vec<u8>);

fn byte() -> impl Strategy<Value = u8> {
    // Bias toward the bytes that matter to stuffing and headers.
    prop_oneof![Just(0xFF), Just(0xFD), Just(0x00), any::<u8>()]
}

fn packet() -> impl Strategy<Value = Packet> {
    (
        0u8..=252,
        prop_oneof![Just(0x55u8), Just(0x03u8), Just(0x83u8)],
        prop::collection::vec(byte(), 1..40),
    )
}

fn encode_packet(p: &Packet) -> Vec<u8> {
    let mut buf = [0u8; 256];
    let mut w = encode::PacketWriter::new(&mut buf, p.0, p.1).unwrap();
    w.extend(&p.2);
    let n = w.finish().unwrap();
    buf[..n].to_vec()
}

/// Feeds `chunks` and collects valid frames; at the end abandons partial packets, as the bus
/// master does after a timeout.
fn parse_chunks<'a>(chunks: impl IntoIterator<Item = &'a [u8]>) -> Vec<Packet> {
    let mut p: Parser = Parser::new();
    let mut out = Vec::new();
    let take = |p: &mut Parser, out: &mut Vec<Packet>| {
        while let Some(ev) = p.next_frame() {
            if let Ok(f) = ev {
                out.push((f.id, f.instruction, f.params.to_vec()));
            }
        }
    };
    for mut chunk in chunks {
        while !chunk.is_empty() {
            let n = p.feed(chunk);
            chunk = &chunk[n..];
            take(&mut p, &mut out);
        }
    }
    while p.buffered() > 0 {
        p.abandon_partial();
        take(&mut p, &mut out);
    }
    out
}

/// How a byte-by-byte caller asks the parser.
#[derive(Clone, Copy, PartialEq)]
enum Asking {
    /// `next_frame` after every byte.
    Always,
    /// Not while `awaiting_rest` holds.
    SkipAwaiting,
    /// Not while `awaiting_rest` holds, and `quiet_bytes` bytes pushed at once after a byte
    /// (as the simulated servos do).
    SkipQuiet,
}

/// What the parser gives, byte by byte: (index of the byte after which it came, the frame or
/// the rejected packet's ID and kind), asked as `asking` says.
fn events_bytewise(stream: &[u8], asking: Asking) -> Vec<(usize, Result<Packet, String>)> {
    let mut p: Parser = Parser::new();
    let mut out = Vec::new();
    let mut quiet = 0;
    for (i, b) in stream.iter().enumerate() {
        if quiet > 0 {
            quiet -= 1;
            assert!(p.push(*b));
            continue;
        }
        p.feed(std::slice::from_ref(b));
        if asking != Asking::Always && p.awaiting_rest() {
            if asking == Asking::SkipQuiet {
                quiet = p.quiet_bytes();
            }
            continue;
        }
        while let Some(ev) = p.next_frame() {
            out.push((
                i,
                ev.map(|f| (f.id, f.instruction, f.params.to_vec()))
                    .map_err(|e| format!("{e:?}")),
            ));
        }
    }
    out
}

proptest! {
    #[test]
    fn skipping_the_parser_while_it_awaits_a_packets_rest_changes_nothing(
        parts in prop::collection::vec(
            (packet(), prop::collection::vec(byte(), 0..12), any::<prop::sample::Index>(), any::<u8>(), any::<bool>()),
            1..8,
        ),
    ) {
        // Packets with noise between them, some with one byte corrupted (a bad CRC or LEN, a
        // false header): every event must come at the same byte either way.
        let mut stream = Vec::new();
        for (p, noise, at, flip, corrupt) in &parts {
            let mut bytes = encode_packet(p);
            if *corrupt {
                let i = at.index(bytes.len());
                bytes[i] ^= flip | 1;
            }
            stream.extend(bytes);
            stream.extend(noise);
        }
        let asked = events_bytewise(&stream, Asking::Always);
        let skipped = events_bytewise(&stream, Asking::SkipAwaiting);
        let quiet = events_bytewise(&stream, Asking::SkipQuiet);
        prop_assert_eq!(&skipped, &asked);
        prop_assert_eq!(&quiet, &asked);
    }

    #[test]
    fn any_chunking_parses_identically(packets in prop::collection::vec(packet(), 1..8), cuts in prop::collection::vec(any::<prop::sample::Index>(), 0..20)) {
        let stream: Vec<u8> = packets.iter().flat_map(encode_packet).collect();
        let mut points: Vec<usize> = cuts.iter().map(|i| i.index(stream.len() + 1)).collect();
        points.push(0);
        points.push(stream.len());
        points.sort_unstable();
        let chunks: Vec<&[u8]> = points.windows(2).map(|w| &stream[w[0]..w[1]]).collect();
        let whole = parse_chunks([&stream[..]]);
        let chunked = parse_chunks(chunks);
        let bytewise = parse_chunks(stream.chunks(1));
        prop_assert_eq!(&whole, &packets);
        prop_assert_eq!(&chunked, &packets);
        prop_assert_eq!(&bytewise, &packets);
    }

    #[test]
    fn noise_between_packets_never_panics_and_next_is_recovered(
        first in packet(),
        noise in prop::collection::vec(byte(), 0..300),
        second in packet(),
    ) {
        let mut stream = encode_packet(&first);
        stream.extend_from_slice(&noise);
        stream.extend(encode_packet(&second));
        let got = parse_chunks(stream.chunks(7));
        prop_assert!(got.first() == Some(&first), "first packet lost: {:?}", got);
        prop_assert!(got.last() == Some(&second), "packet after noise lost: {:?}", got);
    }

    #[test]
    fn pure_noise_never_panics(noise in prop::collection::vec(byte(), 0..600)) {
        let _ = parse_chunks(noise.chunks(5));
    }
}

/// `quiet_bytes` by hand: a Ping to ID 1 is 10 bytes (header 4, ID, LEN 2 = 3, INST, CRC 2).
/// With its first 7 bytes buffered (LEN known) the 8th and 9th cannot complete it: 2; with 9,
/// the 10th completes it: 0; with only the header's prefix or no LEN yet: 0.
#[test]
fn quiet_bytes_are_the_bytes_before_a_packets_last() {
    let ping = encode_packet(&(1, 0x01, vec![]));
    assert_eq!(ping.len(), 10);
    let mut p: Parser = Parser::new();
    let mut quiet = Vec::new();
    for &b in &ping[..9] {
        p.feed(&[b]);
        quiet.push(p.quiet_bytes());
    }
    assert_eq!(quiet, [0, 0, 0, 0, 0, 0, 2, 1, 0]);
    p.feed(&ping[9..]);
    assert!(matches!(p.next_frame(), Some(Ok(f)) if f.id == 1 && f.instruction == 0x01));
    assert_eq!(p.quiet_bytes(), 0);
}
