//! `dbot table`: turn a plan directory (from `dbot plan`, with torques) into the step table the
//! board plays back.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use planner::dynamics::table::{gait_table, stance_bits};
use planner::model::Leg;

/// Build the board's step table from a plan directory.
///
/// The table holds the planned angle (rad) and modelled actuator torque (N m) of every servo per
/// slice, stance flags, step period and duty; the firmware adds the torque bias (torque / servo
/// stiffness) to each command. The model is the plan's (plan.json); a setup file naming another
/// model gets a warning, since the table would not fit that robot.
#[derive(Debug, clap::Args)]
#[command(after_help = "Example:
  dbot table --plan out/walk --out walk.dbgt          # then: dbot upload --table walk.dbgt --slot 1")]
pub struct Args {
    /// Plan directory written by `dbot plan` (plan.json, joints.csv with torque_nm, feet.csv).
    #[arg(long)]
    plan: PathBuf,
    /// Output file for the table bytes.
    #[arg(long)]
    out: PathBuf,
    /// Gait name stored in the table (at most 16 bytes); default: the plan directory's name.
    #[arg(long)]
    name: Option<String>,
    #[command(flatten)]
    feasibility: crate::feasibility_args::FeasibilityArgs,
    /// Robot setup file (TOML) whose `model` the plan's is checked against. Default:
    /// $DBOT_CONFIG, ./dbot.toml, ~/.config/dbot/config.toml.
    #[arg(long)]
    config: Option<PathBuf>,
}

impl Args {
    pub fn run(self) -> Result<()> {
        let dir = &self.plan;
        let json_path = dir.join("plan.json");
        let text = std::fs::read_to_string(&json_path)
            .with_context(|| format!("reading {}", json_path.display()))?;
        let json: serde_json::Value = serde_json::from_str(&text)
            .with_context(|| format!("parsing {}", json_path.display()))?;
        let field = |k: &str| {
            json.get(k)
                .with_context(|| format!("{}: no `{k}`", json_path.display()))
        };
        let source = field("model_source")?
            .as_str()
            .with_context(|| format!("{}: `model_source` is not a string", json_path.display()))?;
        let period = field("period_s")?
            .as_f64()
            .with_context(|| format!("{}: `period_s` is not a number", json_path.display()))?;
        let duty = json["parameters"]["duty"]
            .as_f64()
            .with_context(|| format!("{}: no number `parameters.duty`", json_path.display()))?;
        let model = crate::common::model_spec::load_model(source)?;
        let (setup, setup_path) = crate::config::RobotConfig::find(self.config.as_deref())?;
        if let (Some(want), Some(file)) = (&setup.model, &setup_path)
            && want != source
            && *want != model.name
        {
            eprintln!(
                "warning: {} was planned for model {} but {} names model {want}: this table fits {}",
                dir.display(),
                model.name,
                file.display(),
                model.name
            );
        }
        let n = model.joints.len();

        let jpath = dir.join("joints.csv");
        let mut rd = csv::Reader::from_path(&jpath)
            .with_context(|| format!("opening {}", jpath.display()))?;
        let h = rd.headers()?.clone();
        let col = |name: &str| {
            h.iter()
                .position(|x| x == name)
                .with_context(|| format!("{}: no `{name}` column", jpath.display()))
        };
        let (sc, lc, jc, ac, tc) = (
            col("slice")?,
            col("leg")?,
            col("joint")?,
            col("angle_rad")?,
            col("torque_nm")?,
        );
        let mut q: Vec<Vec<f64>> = Vec::new();
        let mut torque: Vec<Vec<f64>> = Vec::new();
        for (i, rec) in rd.records().enumerate() {
            let at = format!("{} line {}", jpath.display(), i + 2);
            let rec = rec.with_context(|| at.clone())?;
            let slice: usize = rec[sc]
                .parse()
                .with_context(|| format!("{at}: slice `{}`", &rec[sc]))?;
            let j = i % n;
            let joint = &model.joints[j];
            if slice != i / n
                || rec[lc] != *joint.leg.name()
                || rec[jc] != format!("{:?}", joint.kind)
            {
                bail!(
                    "{at}: expected slice {} joint {} (rows in model order), found slice {} {} {}",
                    i / n,
                    joint.name,
                    &rec[sc],
                    &rec[lc],
                    &rec[jc]
                );
            }
            if j == 0 {
                q.push(Vec::with_capacity(n));
                torque.push(Vec::with_capacity(n));
            }
            let num = |c: usize| {
                rec[c]
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .with_context(|| format!("{at}: `{}` is not a finite number", &rec[c]))
            };
            q[slice].push(num(ac)?);
            torque[slice].push(num(tc)?);
        }

        let fpath = dir.join("feet.csv");
        let mut rd = csv::Reader::from_path(&fpath)
            .with_context(|| format!("opening {}", fpath.display()))?;
        let h = rd.headers()?.clone();
        let col = |name: &str| {
            h.iter()
                .position(|x| x == name)
                .with_context(|| format!("{}: no `{name}` column", fpath.display()))
        };
        let (sc, lc, stc) = (col("slice")?, col("leg")?, col("stance")?);
        let mut stance = vec![0u8; q.len()];
        for (i, rec) in rd.records().enumerate() {
            let at = format!("{} line {}", fpath.display(), i + 2);
            let rec = rec.with_context(|| at.clone())?;
            let slice: usize = rec[sc]
                .parse()
                .with_context(|| format!("{at}: slice `{}`", &rec[sc]))?;
            let leg = Leg::ALL
                .into_iter()
                .find(|l| l.name() == &rec[lc])
                .with_context(|| format!("{at}: leg `{}`", &rec[lc]))?;
            let bits = stance
                .get_mut(slice)
                .with_context(|| format!("{at}: slice {slice} beyond joints.csv"))?;
            *bits |= stance_bits(&[leg], &[&rec[stc] == "1"]);
        }

        // Default name: the directory's, cut to the table's 16 bytes on a character boundary.
        let name = self.name.unwrap_or_else(|| {
            let full = dir
                .file_name()
                .map_or("gait".into(), |s| s.to_string_lossy().into_owned());
            let mut end = full.len().min(16);
            while !full.is_char_boundary(end) {
                end -= 1;
            }
            full[..end].to_string()
        });
        crate::bounds::check_slices(
            &format!("{}: slices", jpath.display()),
            q.len(),
            crate::bounds::table_joints(&model),
        )?;
        let dt = period / q.len().max(1) as f64;
        let check = planner::plan::feasibility::check(&model, &q, Some(&torque), dt);
        self.feasibility
            .enforce(&check, &format!("step table of {}", dir.display()))?;
        let bytes = gait_table(&model, &name, period, duty, &q, &torque, &stance)
            .with_context(|| format!("building the step table of {}", dir.display()))?;
        crate::common::output::replace_file(&self.out, |p| Ok(std::fs::write(p, &bytes)?))?;
        println!(
            "{}: {} slices, period {period:.3} s, {} bytes to {}",
            model.name,
            q.len(),
            bytes.len(),
            self.out.display()
        );
        Ok(())
    }
}
