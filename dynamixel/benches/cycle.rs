//! Host benchmark of one 22-servo bus cycle's CPU work: encode the Sync Write of goal positions
//! and the Sync Read request, then parse the 22 status replies and decode their feedback.
//! Run: `cargo bench -p dynamixel --features std --bench cycle`.

use criterion::{Criterion, criterion_group, criterion_main};
use dynamixel::encode;
use dynamixel::master::Feedback;
use dynamixel::parser::Parser;
use std::hint::black_box;

fn replies() -> Vec<u8> {
    let mut wire = Vec::new();
    for id in 1..=22u8 {
        let mut data = [0u8; 10];
        data[0..2].copy_from_slice(&(-(id as i16) * 7).to_le_bytes());
        data[2..6].copy_from_slice(&(id as i32 * 3).to_le_bytes());
        data[6..10].copy_from_slice(&(2000 + id as i32).to_le_bytes());
        let mut buf = [0u8; 64];
        let n = encode::status(&mut buf, id, 0, &data).unwrap();
        wire.extend_from_slice(&buf[..n]);
    }
    assert_eq!(wire.len(), 22 * 21);
    wire
}

fn cycle(c: &mut Criterion) {
    let ids: Vec<u8> = (1..=22).collect();
    let goals: Vec<(u8, u32)> = ids.iter().map(|&id| (id, 2048 + id as u32)).collect();
    let wire = replies();
    let mut tx = [0u8; 512];
    let mut parser: Parser = Parser::new();
    let mut out = [Feedback::default(); 22];
    c.bench_function("encode 22-servo cycle + parse 22 replies", |b| {
        b.iter(|| {
            let n =
                encode::sync_write_u32(&mut tx, 116, black_box(&goals).iter().copied()).unwrap();
            let m = encode::sync_read(&mut tx[n..], 126, 10, black_box(&ids)).unwrap();
            black_box(&tx[..n + m]);
            let mut data = black_box(&wire[..]);
            let mut k = 0;
            while !data.is_empty() {
                let taken = parser.feed(data);
                data = &data[taken..];
                while let Some(Ok(f)) = parser.next_frame() {
                    let s = f.status().unwrap();
                    out[k] = Feedback::from_bytes(s.data.try_into().unwrap(), s.error.alert());
                    k += 1;
                }
            }
            assert_eq!(k, 22);
            black_box(&out);
        })
    });
}

criterion_group!(benches, cycle);
criterion_main!(benches);
