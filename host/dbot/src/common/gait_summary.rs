//! One line about a stored gait, as `upload` and `gaits` print it.

use protocol::GaitSummary;

/// One line about a stored gait: name, shape, timing, CRC.
pub fn describe(g: &GaitSummary) -> String {
    let h = &g.header;
    format!(
        "\"{}\" {} joints x {} slices, step {:.3} s, duty {:.2}, CRC {:#010x}",
        h.name_str().unwrap_or("(name not printable text)"),
        h.joint_count,
        h.slice_count,
        f64::from(h.step_period_us) * 1e-6,
        f64::from(h.duty) * 1e-4,
        g.crc
    )
}
