//! Why strain cannot be predicted: each names the gauge or the slice count.

/// Strain could not be predicted.
#[derive(Debug, thiserror::Error)]
pub enum StrainError {
    /// The gauge's segment has no proximal joint or no axis (a model file's validation refuses
    /// these; a model built in code may not have been checked).
    #[error("gauge {gauge}: its segment has no proximal joint and single distal end to cut")]
    NoAxis { gauge: String },
    /// The dynamics and the slice inputs are of different cycles.
    #[error("strain: {inputs} slice inputs but {solved} solved slices")]
    Slices { inputs: usize, solved: usize },
}
