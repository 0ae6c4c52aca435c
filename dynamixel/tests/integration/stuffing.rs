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
