//! Start times of trials as the lab writes them (`YYYY-MM-DD HH_MM_SS`, a folder name) and as
//! ISO 8601 (`YYYY-MM-DDTHH:MM:SSZ`, in trial.json), both in UTC so that a folder's name does
//! not depend on the machine's time zone.

use std::time::{SystemTime, UNIX_EPOCH};

/// A moment to the second, UTC.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct UtcSecond {
    pub year: i64,
    pub month: u32,
    pub day: u32,
    pub hour: u32,
    pub minute: u32,
    pub second: u32,
}

impl UtcSecond {
    /// The second `t` falls in (times before 1970 count as 1970-01-01 00:00:00).
    pub fn of(t: SystemTime) -> Self {
        let secs = t.duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
        let days = (secs / 86_400) as i64;
        let rest = secs % 86_400;
        let (year, month, day) = civil_from_days(days);
        Self {
            year,
            month,
            day,
            hour: (rest / 3600) as u32,
            minute: (rest % 3600 / 60) as u32,
            second: (rest % 60) as u32,
        }
    }

    /// The lab's folder name: `2026-12-02 06_30_05`.
    pub fn folder_name(&self) -> String {
        format!(
            "{:04}-{:02}-{:02} {:02}_{:02}_{:02}",
            self.year, self.month, self.day, self.hour, self.minute, self.second
        )
    }

    /// ISO 8601: `2026-12-02T06:30:05Z`.
    pub fn iso(&self) -> String {
        format!(
            "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z",
            self.year, self.month, self.day, self.hour, self.minute, self.second
        )
    }
}

/// Year, month (1..=12), day (1..=31) of the day `days` after 1970-01-01 in the proleptic
/// Gregorian calendar (H. Hinnant's `civil_from_days`, eras of 400 years).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn at(secs: u64) -> UtcSecond {
        UtcSecond::of(UNIX_EPOCH + Duration::from_secs(secs))
    }

    #[test]
    fn known_dates() {
        assert_eq!(at(0).folder_name(), "1970-01-01 00_00_00");
        // `date -u -d @951782400`: 2000-02-29 00:00:00 (a leap day of a year divisible by 400).
        assert_eq!(at(951_782_400).iso(), "2000-02-29T00:00:00Z");
        // `date -u -d @1796193005`: 2026-12-02 06:30:05.
        assert_eq!(at(1_796_193_005).folder_name(), "2026-12-02 06_30_05");
        // The last second of 2024, a leap year (day 366).
        assert_eq!(at(1_735_689_599).iso(), "2024-12-31T23:59:59Z");
    }
}
