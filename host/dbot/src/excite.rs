//! `dbot excite`: the excitation trials a lab plays on the robot to identify it
//! (`planner::excitation`), as step tables built under the board's rules.

use planner::excitation::ExcitationKind;

/// Write the excitation trials that identify the robot: step tables to upload and record.
///
/// `suspended` (the robot on a stand, feet in the air): one table per joint kind (`sus-ThC1`,
/// `sus-CTr`, ...) moving that joint on every leg: steps of up to 0.15 rad each held 1 s, then a
/// linear chirp from 0.1 to 2 Hz over about 20 s, within 3 degrees of the joint limits and at
/// most half the servo's no-load speed. `standing` (the robot on its feet): one table (`stand`)
/// shifting the thorax slowly (heave 10 mm, surge and sway 15 mm, roll, pitch and yaw 4 degrees,
/// 8 s each) with the feet held. Every table starts and ends at the resting posture and has no
/// torque bias; the board's rules check it as any gait's (slot size, servo speed, IK jumps, P
/// gain). Writes DIR/NAME.dbgt per table and DIR/excitation.json (what each joint does when).
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot excite --kind suspended --out out/excite       # then per table: dbot record --table out/excite/sus-CTr.dbgt ...
  dbot excite --kind standing --out out/excite-stand")]
pub struct Args {
    /// `suspended` (feet in the air: per-joint steps and chirps) or `standing` (slow posture
    /// changes under the body's weight).
    #[arg(long)]
    kind: ExcitationKind,
    /// Output directory.
    #[arg(long)]
    out: std::path::PathBuf,
    #[command(flatten)]
    model: crate::args::setup::ModelArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let model = crate::common::model_spec::load_model(&self.model.spec()?)?;
        let said = lab::excite_files::write_excitation(&model, self.kind, &self.out)?;
        print!("{said}");
        Ok(())
    }
}
