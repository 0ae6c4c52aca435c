//! `dbot status`: the board's state, a damaged gait store, fault, playback position, upload in
//! progress and counters.

use crate::args::board::BoardArgs;
use crate::common::words::state_name;
use board::slot_health;

/// Runs the command on the board `board` names.
pub fn run(board: BoardArgs) -> anyhow::Result<()> {
    let mut s = board.connect()?;
    let i = s.board.info().clone();
    let st = s.board.status()?;
    let set = s.board.settings()?;
    println!("port      {}", s.board.port());
    println!(
        "firmware  {}.{}.{} (protocol {}, table format {})",
        i.firmware.major,
        i.firmware.minor,
        i.firmware.patch,
        i.protocol_version,
        i.table_format_version
    );
    println!("state     {}", state_name(st.state));
    // The slots as the board found them at start-up (DeviceInfo carries them).
    if let Some(line) = slot_health::store_line(&i.slots) {
        println!("store     {}", line.strip_prefix("store ").unwrap_or(&line));
        for slot in i.slots.iter().filter(|s| s.is_damaged()) {
            println!("          {}", slot_health::slot_line(slot));
        }
    }
    if let Some(f) = st.fault {
        println!("fault     {f}");
    }
    if let Some(p) = st.playback {
        println!(
            "playback  slot {} {}, step {} slice {}, period x{:.3}",
            p.slot,
            p.direction.name(),
            p.step,
            p.slice,
            f64::from(p.period_scale) / 1000.0
        );
    }
    if let Some(u) = st.upload {
        println!(
            "upload    slot {}: {}/{} bytes",
            u.slot, u.received, u.total_len
        );
    }
    println!(
        "bus       {} bit/s, {} Hz, telemetry every {} cycles; torque on {} of {} joints",
        set.baud,
        set.cycle_hz,
        set.telemetry_every,
        st.torque_enabled.count_ones(),
        set.joints.len()
    );
    let c = st.counters;
    println!(
        "counters  {} cycles, {} missed deadlines, {} bus timeouts, {} CRC errors, {} rejected frames, {} telemetry dropped",
        c.cycles,
        c.missed_deadlines,
        c.bus_timeouts,
        c.crc_errors,
        c.rejected_frames,
        c.telemetry_dropped
    );
    s.close()
}
