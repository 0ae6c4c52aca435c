//! Byte stuffing cases built by hand from the specification ("after every FF FF FD from INST to
//! the last parameter insert FD; LEN counts stuffed bytes; CRC over the stuffed packet"). The CRC
//! bytes come from the `crc` crate's CRC-16/UMTS, an implementation independent of ours.

use dynamixel::encode;
use dynamixel::parser::Parser;

fn with_crc(mut body: Vec<u8>) -> Vec<u8> {
    let c = crc::Crc::<u16>::new(&crc::CRC_16_UMTS).checksum(&body);
    body.extend_from_slice(&c.to_le_bytes());
    body
}

fn parse_one(bytes: &[u8]) -> (u8, u8, Vec<u8>) {
    let mut p: Parser = Parser::new();
    assert_eq!(p.feed(bytes), bytes.len());
    let f = p.next_frame().expect("a frame").expect("a valid frame");
    (f.id, f.instruction, f.params.to_vec())
}

#[test]
fn independent_crc_agrees_with_e_manual() {
    assert_eq!(
        with_crc(vec![0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01]),
        [0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01, 0x19, 0x4E]
    );
}

#[test]
fn write_of_ff_ff_fd_00() {
    // Write ID 1, addr 116, data FF FF FD 00. Params 74 00 FF FF FD 00 -> stuffed 74 00 FF FF FD FD 00;
    // INST + 7 stuffed params + CRC = 10 = LEN.
    let want = with_crc(vec![
        0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x0A, 0x00, 0x03, 0x74, 0x00, 0xFF, 0xFF, 0xFD, 0xFD, 0x00,
    ]);
    let mut buf = [0u8; 64];
    let n = encode::write(&mut buf, 1, 116, &[0xFF, 0xFF, 0xFD, 0x00]).unwrap();
    assert_eq!(&buf[..n], &want[..]);
    assert_eq!(
        parse_one(&want),
        (1, 0x03, vec![0x74, 0x00, 0xFF, 0xFF, 0xFD, 0x00])
    );
}

#[test]
fn status_with_current_minus_one_then_fd() {
    // A Sync Read reply of 126..=135: current -1 (FF FF), velocity starting with FD, position 2048.
    // Data FF FF FD 00 00 00 00 08 00 00 after ERR 00 -> stuffed FF FF FD FD 00 ...; LEN = 1 + 1 + 11 + 2 = 15.
    let want = with_crc(vec![
        0xFF, 0xFF, 0xFD, 0x00, 0x07, 0x0F, 0x00, 0x55, 0x00, 0xFF, 0xFF, 0xFD, 0xFD, 0x00, 0x00,
        0x00, 0x00, 0x08, 0x00, 0x00,
    ]);
    let data = [0xFF, 0xFF, 0xFD, 0x00, 0x00, 0x00, 0x00, 0x08, 0x00, 0x00];
    let mut buf = [0u8; 64];
    let n = encode::status(&mut buf, 7, 0, &data).unwrap();
    assert_eq!(&buf[..n], &want[..]);
    let (id, inst, params) = parse_one(&want);
    assert_eq!((id, inst), (7, 0x55));
    assert_eq!(params[0], 0);
    assert_eq!(&params[1..], &data);
}

#[test]
fn twice_in_a_row_and_already_fd_fd() {
    // Data FF FF FD FF FF FD FD: each FF FF FD gets an FD, including when an FD already follows:
    // FF FF FD [FD] FF FF FD [FD] FD.
    // LEN = INST + 2 addr + 9 stuffed + 2 CRC = 14.
    assert_write_is_stuffed(
        (3, 512, &[0xFF, 0xFF, 0xFD, 0xFF, 0xFF, 0xFD, 0xFD]),
        &[0xFF, 0xFF, 0xFD, 0x00, 0x03, 0x0E, 0x00, 0x03, 0x00, 0x02],
        &[0xFF, 0xFF, 0xFD, 0xFD, 0xFF, 0xFF, 0xFD, 0xFD, 0xFD],
    );
}

#[test]
fn triple_ff_and_lone_ff_fd_are_not_stuffed_wrongly() {
    // FF FF FF FD: the last three are FF FF FD -> one FD inserted. FF FD alone: nothing.
    assert_write_is_stuffed(
        (2, 64, &[0xFF, 0xFF, 0xFF, 0xFD, 0x10, 0xFF, 0xFD]),
        &[0xFF, 0xFF, 0xFD, 0x00, 0x02, 0x0D, 0x00, 0x03, 0x40, 0x00],
        &[0xFF, 0xFF, 0xFF, 0xFD, 0xFD, 0x10, 0xFF, 0xFD],
    );
}

/// A Write of `data` to servo `id` at `addr` is the hand-built `head` (header, ID, LEN, INST and
/// the address) followed by the hand-stuffed `stuffed` data and the CRC, and parses back to the
/// address and `data`.
fn assert_write_is_stuffed((id, addr, data): (u8, u16, &[u8]), head: &[u8], stuffed: &[u8]) {
    let want = with_crc([head, stuffed].concat());
    let mut buf = [0u8; 64];
    let n = encode::write(&mut buf, id, addr, data).unwrap();
    assert_eq!(&buf[..n], &want[..]);
    let (_, _, params) = parse_one(&want);
    assert_eq!(&params[..2], &addr.to_le_bytes());
    assert_eq!(&params[2..], data);
}

#[test]
fn sync_write_goal_with_header_pattern() {
    // Goal 0xFDFFFF00 for ID 1: entry 01 00 FF FF FD -> 01 00 FF FF FD FD. LEN = 1 + 4 + 6 + 2 = 13.
    let want = with_crc(vec![
        0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x0D, 0x00, 0x83, 0x74, 0x00, 0x04, 0x00, 0x01, 0x00, 0xFF,
        0xFF, 0xFD, 0xFD,
    ]);
    let mut buf = [0u8; 64];
    let n = encode::sync_write_u32(&mut buf, 116, [(1, 0xFDFF_FF00)]).unwrap();
    assert_eq!(&buf[..n], &want[..]);
}

#[test]
fn unstuffed_sender_is_still_understood() {
    // The Python SDK transmits without stuffing: FF FF FD 00 inside a Write arrives raw.
    let want = with_crc(vec![
        0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x09, 0x00, 0x03, 0x74, 0x00, 0xFF, 0xFF, 0xFD, 0x00,
    ]);
    assert_eq!(
        parse_one(&want),
        (1, 0x03, vec![0x74, 0x00, 0xFF, 0xFF, 0xFD, 0x00])
    );
}

/// The specification's rule read backwards, written for clarity rather than speed: the sender
/// put an `FD` after every `FF FF FD` of the unstuffed stream, so an `FD` that follows `FF FF FD`
/// in what has been kept so far is dropped (any other byte there is kept: a sender that did not
/// stuff). The reference `parser::unstuff` is held to.
fn unstuff_reference(region: &[u8]) -> Vec<u8> {
    let mut kept: Vec<u8> = Vec::new();
    let mut i = 0;
    while i < region.len() {
        kept.push(region[i]);
        if kept.ends_with(&[0xFF, 0xFF, 0xFD]) && region.get(i + 1) == Some(&0xFD) {
            i += 1;
        }
        i += 1;
    }
    kept
}

/// Every sequence of up to 8 bytes over FF, FD and 00 (the bytes stuffing turns on; 9 841 of
/// them), and longer ones built from them: the unstuffed bytes and length are the reference's.
#[test]
fn unstuff_is_the_byte_by_byte_reference_over_every_short_sequence() {
    let alphabet = [0xFF, 0xFD, 0x00];
    let mut checked = 0;
    for len in 0..=8u32 {
        for code in 0..3usize.pow(len) {
            let mut c = code;
            let bytes: Vec<u8> = (0..len)
                .map(|_| {
                    let b = alphabet[c % 3];
                    c /= 3;
                    b
                })
                .collect();
            // Alone, and after a prefix that shifts it (a stuffed byte late in a region).
            for prefix in [&[][..], &[0x01, 0xFF, 0xFF, 0xFD, 0xFD, 0x07][..]] {
                let mut region = [prefix, &bytes[..]].concat();
                let want = unstuff_reference(&region);
                let n = dynamixel::parser::unstuff(&mut region);
                assert_eq!(region[..n], want[..], "{bytes:02X?} after {prefix:02X?}");
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 2 * 9841);
}

/// `PacketWriter::extend` (a copy when nothing needs stuffing and the bytes fit) writes what
/// pushing each byte does, for parameters cut into pieces at every point, around FF FF FD
/// across the cut, and in buffers from too small to roomy: the same packet, or the same refusal.
#[test]
fn extend_writes_what_pushing_each_byte_writes() {
    let params: [&[u8]; 8] = [
        &[0x74, 0x00, 0xFF, 0xFF, 0xFD, 0x00],
        &[0xFF, 0xFD, 0x00],
        &[0xFD, 0xFD, 0xFF],
        &[0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09],
        &[0xFF, 0xFF, 0xFF, 0xFD, 0xFD, 0xFF, 0xFF, 0xFD],
        &[0x00, 0xFF],
        &[0xFF],
        &[],
    ];
    for p in params {
        for cut in 0..=p.len() {
            for cap in 8..(p.len() * 2 + 14) {
                let mut a = vec![0u8; cap];
                let mut b = vec![0u8; cap];
                let got = encode::PacketWriter::new(&mut a, 3, 0x03).map(|mut w| {
                    w.push(0xFF); // an FF before the cut: FF FF FD can span it
                    w.extend(&p[..cut]);
                    w.extend(&p[cut..]);
                    w.finish()
                });
                let want = encode::PacketWriter::new(&mut b, 3, 0x03).map(|mut w| {
                    w.push(0xFF);
                    for &x in p {
                        w.push(x);
                    }
                    w.finish()
                });
                assert_eq!(got, want, "{p:02X?} cut at {cut}, {cap} bytes");
                assert_eq!(a, b, "{p:02X?} cut at {cut}, {cap} bytes");
                // Each byte through `extend` on its own (the one-byte copy).
                let mut c = vec![0u8; cap];
                let each = encode::PacketWriter::new(&mut c, 3, 0x03).map(|mut w| {
                    w.push(0xFF);
                    for x in p.chunks(1) {
                        w.extend(x);
                    }
                    w.finish()
                });
                assert_eq!(each, want, "{p:02X?} byte by byte, {cap} bytes");
                assert_eq!(c, b, "{p:02X?} byte by byte, {cap} bytes");
            }
        }
    }
}
