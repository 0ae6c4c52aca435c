//! The board's counters in words, as `dbot status` prints them.

/// `3 cycles, 0 missed deadlines, ..., 0 goal moves rate-limited`.
pub fn counters_line(c: &protocol::Counters) -> String {
    format!(
        "{} cycles, {} missed deadlines, {} bus timeouts, {} CRC errors, {} rejected frames, {} \
         telemetry dropped, {} goal moves rate-limited",
        c.cycles,
        c.missed_deadlines,
        c.bus_timeouts,
        c.crc_errors,
        c.rejected_frames,
        c.telemetry_dropped,
        c.rate_limited
    )
}
