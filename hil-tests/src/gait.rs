//! Gait tables for the HIL tests and the upload procedure, written against the protocol crate's
//! public API only (the same steps `dbot upload` takes), so a firmware or protocol change that
//! breaks uploads fails here.

use crate::link::Link;
use anyhow::{Context, Result, ensure};
use protocol::gait::{GaitTableBuilder, JointSpec, ServoModel, Sign};
use protocol::{Request, Response};
use std::time::Duration;

/// Joints of Drosophibot II in servo-ID order 1..=22 (CTr joints on MX-64).
pub const JOINTS: usize = 22;

/// The robot's servos `(id, model)` as its model file (`drosophibot2.toml`) maps them: the chain
/// the emulated board talks to and the models the test gaits name.
pub fn robot_servos() -> Vec<(u8, ServoModel)> {
    planner::model::builtin("drosophibot2")
        .expect("the built-in model parses (tested in the planner)")
        .servo_chain()
}

/// The model file's servo at `id`; an ID the robot lacks is none.
pub fn servo_at(id: u8) -> Option<ServoModel> {
    robot_servos().into_iter().find(|s| s.0 == id).map(|s| s.1)
}

/// Servo stiffness in the test gaits, N m/rad (the torque bias is torque / stiffness).
pub const STIFFNESS_NM_PER_RAD: f64 = 10.0;

/// A test gait: `slices` slices of a sinusoid per joint (amplitude `amp_rad`, joint-dependent
/// phase) with zero torques, 0.6 s step period, duty 0.6.
pub fn sine_gait(name: &str, slices: usize, amp_rad: f64) -> Result<(GaitTableBuilder, Vec<u8>)> {
    sine_gait_with_torque(name, slices, amp_rad, 0.0)
}

/// Planned angle (rad) of joint `j` (0-based) at slice `s` of an `n`-slice test gait.
pub fn sine_angle(amp_rad: f64, s: usize, n: usize, j: usize) -> f64 {
    let phase = s as f64 / n as f64 * std::f64::consts::TAU;
    amp_rad * (phase + j as f64 * 0.3).sin()
}

/// Like [`sine_gait`] with the same planned torque `torque_nm` on every joint in every slice, so
/// the torque bias (`torque_nm / STIFFNESS_NM_PER_RAD` rad) is a known constant offset.
pub fn sine_gait_with_torque(
    name: &str,
    slices: usize,
    amp_rad: f64,
    torque_nm: f64,
) -> Result<(GaitTableBuilder, Vec<u8>)> {
    let servos = robot_servos();
    let joints: Vec<JointSpec> = (0..JOINTS)
        .map(|j| JointSpec {
            name: format!("joint{}", j + 1),
            servo_id: j as u8 + 1,
            model: servos
                .iter()
                .find(|s| usize::from(s.0) == j + 1)
                .map(|s| s.1)
                .expect("the robot has servos 1..=22"),
            sign: Sign::Positive,
            zero_offset: 2048,
            min_rad: -1.5,
            max_rad: 1.5,
            stiffness_nm_per_rad: STIFFNESS_NM_PER_RAD,
            leg: None,
        })
        .collect();
    let mut b = GaitTableBuilder::new(name, 0.6, 0.6, joints);
    for s in 0..slices {
        let angles: Vec<f64> = (0..JOINTS)
            .map(|j| sine_angle(amp_rad, s, slices, j))
            .collect();
        let stance = if s < slices * 6 / 10 {
            0b0010_1010
        } else {
            0b0001_0101
        };
        b.slice(stance, &angles, &[torque_nm; JOINTS]);
    }
    let bytes = b.build().context("building the test gait")?;
    Ok((b, bytes))
}

/// CRC-32/ISO-HDLC of `bytes` computed with the `crc` crate, independently of the protocol crate.
pub fn crc32(bytes: &[u8]) -> u32 {
    crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC).checksum(bytes)
}

/// Begins an upload of `table` into `slot` and sends chunks until `stop_after` bytes (or all).
pub fn upload_partial(
    link: &mut Link,
    slot: u8,
    builder: &GaitTableBuilder,
    table: &[u8],
    chunk: usize,
    stop_after: usize,
    timeout: Duration,
) -> Result<()> {
    let header = builder.header().context("gait header")?;
    send_chunks(link, slot, header, table, chunk, stop_after, timeout)
}

/// Sends `UploadBegin` with `header` and the chunks of `table` up to `stop_after` bytes.
fn send_chunks(
    link: &mut Link,
    slot: u8,
    header: protocol::GaitHeader,
    table: &[u8],
    chunk: usize,
    stop_after: usize,
    timeout: Duration,
) -> Result<()> {
    let begin = Request::UploadBegin {
        slot,
        header,
        total_len: table.len() as u32,
    };
    let r: Response = link.request(&begin, timeout)?;
    ensure!(r == Response::Ack, "UploadBegin answered {r:?}");
    let mut offset = 0;
    while offset < table.len().min(stop_after) {
        let end = (offset + chunk).min(table.len());
        let data = heapless::Vec::from_slice(&table[offset..end])
            .map_err(|_| anyhow::anyhow!("chunk of {} bytes is too long", end - offset))?;
        let req = Request::UploadChunk {
            offset: offset as u32,
            data,
        };
        let r: Response = link.request(&req, timeout)?;
        ensure!(
            r == Response::ChunkAccepted {
                received: end as u32
            },
            "chunk at {offset}: {r:?}"
        );
        offset = end;
    }
    Ok(())
}

/// Uploads a whole table and commits it with its CRC; returns the commit's response.
pub fn upload(
    link: &mut Link,
    slot: u8,
    builder: &GaitTableBuilder,
    table: &[u8],
    chunk: usize,
    timeout: Duration,
) -> Result<Response> {
    upload_partial(link, slot, builder, table, chunk, usize::MAX, timeout)?;
    link.request(&Request::UploadCommit { crc: crc32(table) }, timeout)
}

/// Uploads a table built elsewhere (e.g. `planner::plan::table::step_table`), its header read from
/// its own bytes, and commits it; returns the commit's response.
pub fn upload_table(
    link: &mut Link,
    slot: u8,
    table: &[u8],
    chunk: usize,
    timeout: Duration,
) -> Result<Response> {
    let header = protocol::GaitTable::parse(table)
        .map_err(|e| anyhow::anyhow!("the table for slot {slot} does not parse: {e}"))?
        .header();
    send_chunks(link, slot, header, table, chunk, usize::MAX, timeout)?;
    link.request(&Request::UploadCommit { crc: crc32(table) }, timeout)
}
