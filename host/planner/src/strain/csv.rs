//! strain.csv: one row per slice and gauge (tidy), with the predicted reading and the section
//! wrench behind it in the gauge's section frame `(a, n, t)` (see [`super::section`]).

use std::io::Write;

use super::StrainPrediction;
use crate::model::Model;
use crate::number::{SIGNIFICANT, plain};

/// The file's name in a plan directory.
pub const STRAIN_CSV: &str = "strain.csv";

/// The header: the wrench is the distal part's on the proximal about the section's centroid;
/// `axial` along the segment axis (distal), `normal` along the face normal, `side` along
/// axis x normal.
pub const HEADER: [&str; 12] = [
    "slice",
    "time_s",
    "gauge",
    "leg",
    "kind",
    "microstrain",
    "axial_force_n",
    "normal_shear_n",
    "side_shear_n",
    "torsion_nm",
    "normal_bending_nm",
    "side_bending_nm",
];

/// Writes strain.csv for the gauges of `model`; slice `s` is at `s * dt`.
pub fn write_strain_csv<W: Write>(
    w: W,
    model: &Model,
    dt: f64,
    prediction: &StrainPrediction,
) -> Result<(), ::csv::Error> {
    let mut out = ::csv::Writer::from_writer(w);
    out.write_record(HEADER)?;
    for (s, slice) in prediction.readings.iter().enumerate() {
        for (g, r) in model.gauges.iter().zip(slice) {
            let mut rec = vec![
                s.to_string(),
                plain(s as f64 * dt, SIGNIFICANT),
                g.name.clone(),
                g.leg.name().into(),
                g.direction.name().into(),
            ];
            let (f, m) = (r.wrench.force, r.wrench.moment);
            rec.extend(
                [r.microstrain, f.x, f.y, f.z, m.x, m.y, m.z]
                    .iter()
                    .map(|v| plain(*v, SIGNIFICANT)),
            );
            out.write_record(&rec)?;
        }
    }
    out.flush()?;
    Ok(())
}
