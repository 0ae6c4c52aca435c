//! The descending command's messages: which slots form the steering family, and the heading and
//! speed the board walks at (the rule behind both: [`crate::steer`]).

/// Parameters of [`crate::Request::SetSteerFamily`]: the gaits over heading, each planned with
/// the same leg phases, slices and period.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SteerFamily {
    /// The gait for heading 0.
    pub straight: u8,
    /// The gait for heading `+range_mrad` (turning left).
    pub left: u8,
    /// The gait for heading `-range_mrad` (turning right).
    pub right: u8,
    /// The heading the side gaits stand for, mrad (not 0).
    pub range_mrad: u16,
}

/// Parameters of [`crate::Request::Steer`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SteerCommand {
    /// Heading from straight forward, mrad, positive left, within the family's range.
    pub heading_mrad: i16,
    /// Speed, 1e-3 of the planned one ([`crate::steer::SPEED_PERMILLE`]).
    pub speed_permille: u16,
}
