//! Telemetry records that never arrived: the board numbers its bus cycles and sends a record every
//! `every` cycles, so a jump in the cycle numbers larger than that step counts the records lost.

use super::csv_out::Row;

/// Records missing between the first and last of `rows`: each gap between consecutive cycle
/// numbers, in units of the smallest step seen (the telemetry rate), less one.
pub fn missing_cycles(rows: &[Row]) -> u64 {
    let mut cycles: Vec<u32> = rows.iter().map(|r| r.cycle).collect();
    cycles.dedup();
    let step = cycles
        .windows(2)
        .map(|w| w[1].wrapping_sub(w[0]))
        .filter(|&d| d > 0)
        .min();
    let Some(step) = step else { return 0 };
    cycles
        .windows(2)
        .map(|w| u64::from(w[1].wrapping_sub(w[0]) / step).saturating_sub(1))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(cycle: u32) -> Row {
        Row {
            time_s: 0.0,
            cycle,
            step: 0,
            slice: 0,
            joint: 0,
            planned_rad: None,
            commanded_rad: 0.0,
            present_rad: 0.0,
            velocity_rad_s: 0.0,
            load_raw: 0,
            torque_estimate_nm: None,
            modelled_nm: None,
            error: 0,
            flags: 0,
            bus_cycle_us: 0,
            platform_goal_ticks: None,
            platform_present_ticks: None,
        }
    }

    #[test]
    fn counts_the_records_a_gap_skips() {
        // Every 2nd cycle; 10 -> 16 skips the records of cycles 12 and 14.
        let rows: Vec<Row> = [4, 6, 8, 10, 16, 18].into_iter().map(row).collect();
        assert_eq!(missing_cycles(&rows), 2);
        // Two joints per cycle repeat the number: no gap.
        let rows: Vec<Row> = [1, 1, 2, 2, 3, 3].into_iter().map(row).collect();
        assert_eq!(missing_cycles(&rows), 0);
        assert_eq!(missing_cycles(&[]), 0);
    }
}
