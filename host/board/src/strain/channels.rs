//! The strain board's 36 channels: which leg and which gauge each column of a sample line is, in
//! the order the board sends them (legs LH, RH, LM, RM, LF, RF; per leg trochanter axial,
//! trochanter transverse, trochanter 45 deg, femur +45 deg, femur -45 deg, femur axial), and their
//! names (`LF_troch_axial`, ...), the one table every strain file and message uses.
//!
//! The table is keyed by leg and gauge kind, so that when the model file lists gauge sites the
//! names and order can be read from it (a site's leg and kind give its column here).

use planner::model::Leg;

/// Number of gauges on a leg.
pub const GAUGES_PER_LEG: usize = 6;
/// Number of channels in a sample line.
pub const CHANNELS: usize = 36;

/// The legs in the order the board sends them (its analog inputs 0..5).
pub const BOARD_LEGS: [Leg; 6] = [Leg::LH, Leg::RH, Leg::LM, Leg::RM, Leg::LF, Leg::RF];

/// Which of a leg's six gauges, in the board's order (its multiplexer inputs 0..5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GaugeKind {
    /// Trochanter, along the segment axis.
    TrochAxial,
    /// Trochanter, across the segment axis.
    TrochTransverse,
    /// Trochanter, at 45 deg to the segment axis.
    Troch45,
    /// Femur, at +45 deg to the segment axis.
    FemurPlus45,
    /// Femur, at -45 deg to the segment axis.
    FemurMinus45,
    /// Femur, along the segment axis.
    FemurAxial,
}

impl GaugeKind {
    /// The six kinds in the board's order.
    pub const ALL: [GaugeKind; GAUGES_PER_LEG] = [
        GaugeKind::TrochAxial,
        GaugeKind::TrochTransverse,
        GaugeKind::Troch45,
        GaugeKind::FemurPlus45,
        GaugeKind::FemurMinus45,
        GaugeKind::FemurAxial,
    ];

    /// The kind's part of a channel name, e.g. `troch_axial`.
    pub fn name(self) -> &'static str {
        match self {
            GaugeKind::TrochAxial => "troch_axial",
            GaugeKind::TrochTransverse => "troch_transverse",
            GaugeKind::Troch45 => "troch_45",
            GaugeKind::FemurPlus45 => "femur_plus45",
            GaugeKind::FemurMinus45 => "femur_minus45",
            GaugeKind::FemurAxial => "femur_axial",
        }
    }

    /// The board's number for this gauge on its leg (0..5).
    pub fn board_index(self) -> usize {
        match self {
            GaugeKind::TrochAxial => 0,
            GaugeKind::TrochTransverse => 1,
            GaugeKind::Troch45 => 2,
            GaugeKind::FemurPlus45 => 3,
            GaugeKind::FemurMinus45 => 4,
            GaugeKind::FemurAxial => 5,
        }
    }
}

/// One channel: a gauge on a leg.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Channel {
    pub leg: Leg,
    pub kind: GaugeKind,
}

impl Channel {
    /// The channel of column `column` (0..36) of a sample line.
    pub fn at_column(column: usize) -> Option<Channel> {
        Self::on_board(column / GAUGES_PER_LEG, column % GAUGES_PER_LEG)
            .filter(|_| column < CHANNELS)
    }

    /// The channel the board calls gauge `gauge` on leg `leg` (both 0..5, as in its messages).
    pub fn on_board(leg: usize, gauge: usize) -> Option<Channel> {
        Some(Channel {
            leg: *BOARD_LEGS.get(leg)?,
            kind: *GaugeKind::ALL.get(gauge)?,
        })
    }

    /// The board's leg number (0..5).
    pub fn board_leg(self) -> usize {
        BOARD_LEGS
            .iter()
            .position(|&l| l == self.leg)
            .expect("every leg has a board input")
    }

    /// This channel's column in a sample line (0..36).
    pub fn column(self) -> usize {
        self.board_leg() * GAUGES_PER_LEG + self.kind.board_index()
    }

    /// The channel's name, e.g. `LF_troch_axial`.
    pub fn name(self) -> String {
        format!("{}_{}", self.leg.name(), self.kind.name())
    }

    /// The channel named `name` (as [`Channel::name`] writes it).
    pub fn parse(name: &str) -> Option<Channel> {
        all().find(|c| c.name() == name)
    }

    /// How a message names it: `LF_troch_axial (board leg 4, gauge 0)`.
    pub fn describe(self) -> String {
        format!(
            "{} (board leg {}, gauge {})",
            self.name(),
            self.board_leg(),
            self.kind.board_index()
        )
    }
}

/// All 36 channels in the board's column order.
pub fn all() -> impl Iterator<Item = Channel> {
    (0..CHANNELS).filter_map(Channel::at_column)
}

/// The 36 channel names in column order, the header of a strain file.
pub fn names() -> Vec<String> {
    all().map(Channel::name).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_follow_the_boards_leg_and_gauge_order() {
        // lab-practice.md: legs LH, RH, LM, RM, LF, RF; per leg troch axial .. femur axial.
        let n = names();
        assert_eq!(n.len(), 36);
        assert_eq!(n[0], "LH_troch_axial");
        assert_eq!(n[5], "LH_femur_axial");
        assert_eq!(n[6], "RH_troch_axial");
        assert_eq!(n[24], "LF_troch_axial");
        assert_eq!(n[27], "LF_femur_plus45");
        assert_eq!(n[35], "RF_femur_axial");
        for c in all() {
            assert_eq!(Channel::at_column(c.column()), Some(c));
            assert_eq!(Channel::parse(&c.name()), Some(c));
        }
        assert_eq!(Channel::at_column(36), None);
        assert_eq!(Channel::on_board(6, 0), None);
        assert_eq!(Channel::parse("LF_tibia"), None);
    }
}
