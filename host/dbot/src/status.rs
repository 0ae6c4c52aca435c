//! `dbot status`: the board's state, a damaged gait store, fault, playback position, upload in
//! progress, the servos' heat and supply (a warning, the servo that stopped the last walk) and
//! counters.

use crate::args::board::BoardArgs;
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
    println!("state     {}", st.state.name());
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
    if st.health_warning.is_some() || st.health_stop.is_some() {
        // Joints named by their servo IDs through the setup's model (the built-in robot's
        // without one).
        let ids = s
            .board
            .joint_map(None)?
            .map(|m| m.servo_ids.to_vec())
            .unwrap_or_default();
        let setup = board.setup()?;
        let model = crate::common::model_spec::load_model(
            setup.model.as_deref().unwrap_or("drosophibot2"),
        )?;
        let names = board::record::joint_names_by_ids(&model, &ids);
        if let Some(a) = st.health_warning {
            println!("warning   {}", board::health::alarm_line(&a, &names));
        }
        if let Some(a) = st.health_stop {
            println!("stopped   {}", board::health::alarm_line(&a, &names));
        }
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
    println!("health    {}", board::health::limits_line(&set.health));
    println!("counters  {}", board::counters::counters_line(&st.counters));
    s.close()
}
