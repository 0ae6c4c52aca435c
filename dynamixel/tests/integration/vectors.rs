//! Every packet of the e-manual test vectors (../shared/reference/dynamixel.md): our encoder must
//! produce these exact bytes, and the parser must read the status packets back.

use dynamixel::encode;
use dynamixel::parser::Parser;

fn hex(s: &str) -> Vec<u8> {
    s.split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect()
}

fn encoded(f: impl FnOnce(&mut [u8]) -> Result<usize, encode::EncodeError>) -> Vec<u8> {
    let mut buf = [0u8; 256];
    let n = f(&mut buf).unwrap();
    buf[..n].to_vec()
}

#[test]
fn ping_id_1() {
    assert_eq!(
        encoded(|b| encode::ping(b, 1)),
        hex("FF FF FD 00 01 03 00 01 19 4E")
    );
}

#[test]
fn read_id_1_addr_132_len_4() {
    assert_eq!(
        encoded(|b| encode::read(b, 1, 132, 4)),
        hex("FF FF FD 00 01 07 00 02 84 00 04 00 1D 15")
    );
}

#[test]
fn write_id_1_goal_512() {
    assert_eq!(
        encoded(|b| encode::write(b, 1, 116, &512u32.to_le_bytes())),
        hex("FF FF FD 00 01 09 00 03 74 00 00 02 00 00 CA 89")
    );
}

#[test]
fn sync_read_132_len_4_ids_1_2() {
    assert_eq!(
        encoded(|b| encode::sync_read(b, 132, 4, &[1, 2])),
        hex("FF FF FD 00 FE 09 00 82 84 00 04 00 01 02 CE FA")
    );
}

#[test]
fn sync_write_116_ids_1_2() {
    let want = hex("FF FF FD 00 FE 11 00 83 74 00 04 00 01 96 00 00 00 02 AA 00 00 00 82 87");
    assert_eq!(
        encoded(|b| encode::sync_write_u32(b, 116, [(1, 150), (2, 170)])),
        want
    );
    let (a, c) = (150u32.to_le_bytes(), 170u32.to_le_bytes());
    assert_eq!(
        encoded(|b| encode::sync_write(b, 116, 4, [(1, &a[..]), (2, &c[..])])),
        want
    );
}

#[test]
fn reboot_id_1() {
    assert_eq!(
        encoded(|b| encode::reboot(b, 1)),
        hex("FF FF FD 00 01 03 00 08 2F 4E")
    );
}

#[test]
fn ping_status_model_1030_fw_0x26() {
    let bytes = hex("FF FF FD 00 01 07 00 55 00 06 04 26 65 5D");
    let mut p: Parser = Parser::new();
    assert_eq!(p.feed(&bytes), bytes.len());
    let frame = p.next_frame().unwrap().unwrap();
    let s = frame.status().unwrap();
    assert_eq!(s.id, 1);
    assert_eq!(s.error.0, 0);
    assert_eq!(u16::from_le_bytes([s.data[0], s.data[1]]), 1030);
    assert_eq!(s.data[2], 0x26);
    assert!(p.next_frame().is_none());
    // And the encoder of the virtual servo produces it.
    assert_eq!(
        encoded(|b| encode::status(b, 1, 0, &[0x06, 0x04, 0x26])),
        bytes
    );
}

#[test]
fn write_status() {
    let bytes = hex("FF FF FD 00 01 04 00 55 00 A1 0C");
    let mut p: Parser = Parser::new();
    p.feed(&bytes);
    let s = p.next_frame().unwrap().unwrap().status().unwrap();
    assert_eq!((s.id, s.error.0, s.data.len()), (1, 0, 0));
    assert_eq!(encoded(|b| encode::status(b, 1, 0, &[])), bytes);
}

#[test]
fn instruction_vectors_parse_as_instructions() {
    // The master's own echo: the parser must return these as instruction packets (not status).
    let bytes = hex("FF FF FD 00 FE 11 00 83 74 00 04 00 01 96 00 00 00 02 AA 00 00 00 82 87");
    let mut p: Parser = Parser::new();
    p.feed(&bytes);
    let f = p.next_frame().unwrap().unwrap();
    assert_eq!((f.id, f.instruction), (0xFE, 0x83));
    assert_eq!(f.params, &bytes[8..22]);
    assert!(f.status().is_none());
}

#[test]
fn one_flipped_bit_is_a_crc_error_naming_the_id() {
    let mut bytes = hex("FF FF FD 00 01 04 00 55 00 A1 0C");
    bytes[8] ^= 0x01;
    let mut p: Parser = Parser::new();
    p.feed(&bytes);
    match p.next_frame() {
        Some(Err(dynamixel::parser::FrameError::Crc {
            id: 1,
            received: 0x0CA1,
            ..
        })) => {}
        other => panic!("expected a CRC error for ID 1, got {other:?}"),
    }
}
