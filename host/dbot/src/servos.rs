//! `dbot servos`: per joint its servo (from a step table's joint map, which the board does not
//! report), stiffness, limits and torque, and the latest feedback if the board is walking.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Context;
use protocol::units::angle_to_rad;

use crate::args::board::BoardArgs;

/// Show the joints the board drives: servo IDs and models, stiffness, limits, torque, errors.
#[derive(Debug, clap::Args)]
#[command(after_help = "Example:
  dbot servos --table walk.dbgt")]
pub struct Args {
    /// Step table whose joint map names the servos (IDs, models); the protocol does not carry it.
    #[arg(long)]
    pub table: Option<PathBuf>,
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let bytes = match &self.table {
            Some(p) => Some(std::fs::read(p).with_context(|| format!("reading {}", p.display()))?),
            None => None,
        };
        let table =
            match &bytes {
                Some(b) => {
                    let path = self.table.as_deref().unwrap_or(std::path::Path::new("?"));
                    Some(protocol::GaitTable::parse(b).with_context(|| {
                        format!("{} (--table) is not a step table", path.display())
                    })?)
                }
                None => None,
            };
        let mut s = self.board.connect()?;
        let set = s.board.settings()?;
        // Feedback only flows while a gait plays; a short wait tells whether it does.
        let latest = s.board.telemetry(Duration::from_millis(200))?;
        println!(
            "joint  servo  model       stiffness N m/rad  limits rad        torque  error  load raw"
        );
        for (j, js) in set.joints.iter().enumerate() {
            let (id, model) = match table.as_ref().and_then(|t| t.joint(j)) {
                Some(m) => (m.servo_id.to_string(), m.model.name().to_owned()),
                None => ("?".into(), "?".into()),
            };
            let fb = latest.as_ref().and_then(|t| t.joints.get(j));
            println!(
                "{j:>5}  {id:>5}  {model:<10}  {:>17.3}  {:+.3} .. {:+.3}  {:>6}  {:>5}  {:>8}",
                js.stiffness as f64 / 1000.0,
                angle_to_rad(js.min),
                angle_to_rad(js.max),
                if js.torque_enabled { "on" } else { "off" },
                fb.map_or("-".into(), |f| format!("{:#04x}", f.error)),
                fb.map_or("-".into(), |f| f.load.to_string()),
            );
        }
        if set.joints.is_empty() {
            println!("(no joint map yet: the board takes it from the first stored gait)");
        }
        if table.is_none() {
            println!(
                "servo IDs and models: pass --table FILE (the board does not report its joint map)"
            );
        }
        println!("temperatures: not read by this firmware");
        s.close()
    }
}
