//! Telemetry records a recording does not hold. The board numbers its bus cycles and sends a
//! record every `every` cycles, so a jump in the cycle numbers larger than that step counts the
//! records missing ([`missing_cycles`]). Not every missing record was lost: the cycles that switch
//! torque, reboot servos, read a servo's hardware error or check the platform make none
//! (`firmware::controller`'s feedback). The records lost are those the board dropped (its queue
//! full: `Counters::telemetry_dropped`) and the host dropped (`Board::telemetry_dropped`),
//! counted over the recording; [`missing_words`] says both.

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

/// The words for a recording's `missing` records (skipped cycle numbers) of which `lost` were
/// dropped on the board or the host (`None`: not known, e.g. the link failed before the board's
/// counters could be read at the end).
pub fn missing_words(missing: u64, lost: Option<u64>) -> String {
    match (missing, lost) {
        (0, None | Some(0)) => "no telemetry record missing".to_owned(),
        (m, None) => format!("{m} telemetry records missing (skipped cycle numbers)"),
        (m, Some(0)) => format!(
            "no telemetry record lost ({m} bus cycle(s) made none: torque switched, servos \
             rebooted, an error read or the platform checked)"
        ),
        (m, Some(l)) => format!(
            "{l} telemetry record(s) lost (dropped on the board or the host: read too slowly); \
             {m} skipped cycle number(s) in all"
        ),
    }
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
            state: None,
            temperature_c: None,
            input_voltage_v: None,
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

    #[test]
    fn missing_records_are_lost_only_when_something_dropped_them() {
        assert_eq!(missing_words(0, Some(0)), "no telemetry record missing");
        assert_eq!(missing_words(0, None), "no telemetry record missing");
        assert_eq!(
            missing_words(2, None),
            "2 telemetry records missing (skipped cycle numbers)"
        );
        assert!(missing_words(2, Some(0)).starts_with("no telemetry record lost (2 bus cycle(s)"));
        assert!(missing_words(5, Some(3)).starts_with("3 telemetry record(s) lost"));
    }
}
