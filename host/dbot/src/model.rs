//! `dbot model`: export a model as URDF, TOML or MJCF, import an AnimatLab project.

use anyhow::{Context, Result};
use clap::{Args as ClapArgs, Subcommand};
use planner::model;

use crate::common::model_spec::load_model;
use crate::common::output::replace_file;
use std::io::Write;
use std::path::PathBuf;

/// Work with organism models (built-in names: drosophibot2, scale-drosophila).
#[derive(Debug, ClapArgs)]
#[command(after_help = "Examples:
  dbot model show --model drosophibot2
  dbot model export --model scale-drosophila --urdf fly.urdf")]
pub struct Args {
    #[command(subcommand)]
    cmd: ModelCmd,
}

#[derive(Debug, Subcommand)]
enum ModelCmd {
    /// Write a model as URDF (SI units, root link `thorax`) and/or as a TOML model file.
    Export {
        /// Built-in model name, a .toml model file or an AnimatLab .aproj file.
        #[arg(long)]
        model: String,
        /// URDF output file.
        #[arg(long)]
        urdf: Option<PathBuf>,
        /// TOML model file output.
        #[arg(long)]
        toml: Option<PathBuf>,
        #[command(flatten)]
        springs: crate::spring_args::SpringArgs,
        /// MJCF (MuJoCo) output file: the model standing in the planner's resting posture, with
        /// servo actuators, foot spheres and the terrain of --scene. Timestep 0.5 ms, or less
        /// when the model's stiffest actuated joint would ring at that (said when it happens).
        #[arg(long)]
        mjcf: Option<PathBuf>,
        /// MJCF scene: flat, incline:DEG, ball[:R[:OFFSET]] (thorax held, ball spinning, as in the
        /// fly rig), ball-fixed[:R[:OFFSET]] or blocks[:SEED[:HEIGHT_M[:SIZE_M[:GAPS]]]] (seeded
        /// random block heights, m; GAPS the fraction of cells left out).
        #[arg(long, default_value = "flat")]
        scene: planner::terrain::Ground,
    },
    /// Print a summary: bodies, joints (limits in degrees), feet, total mass.
    Show {
        /// Built-in model name, a .toml model file or an AnimatLab .aproj file.
        #[arg(long)]
        model: String,
    },
}

impl Args {
    pub fn run(self) -> Result<()> {
        match self.cmd {
            ModelCmd::Export {
                model,
                urdf,
                toml,
                springs,
                mjcf,
                scene,
            } => {
                let m = springs.apply(load_model(&model)?)?;
                if urdf.is_none() && toml.is_none() && mjcf.is_none() {
                    anyhow::bail!(
                        "nothing to do: give --urdf FILE, --toml FILE and/or --mjcf FILE"
                    );
                }
                if let Some(p) = mjcf {
                    let mut options = model::MjcfOptions::stance(&m, &scene)
                        .with_context(|| format!("--scene {scene} for model {}", m.name))?;
                    stable_timestep(&m, &mut options)?;
                    let xml = model::to_mjcf(&m, &options);
                    replace_file(&p, |f| Ok(std::fs::write(f, &xml)?))?;
                }
                if let Some(p) = urdf {
                    let urdf = model::to_urdf(&m);
                    replace_file(&p, |f| Ok(std::fs::write(f, &urdf)?))?;
                }
                if let Some(p) = toml {
                    let notes = format!("Exported by dbot from `{model}`.");
                    let text = model::to_toml_string(&m, &notes, &|_| String::new());
                    replace_file(&p, |f| Ok(std::fs::write(f, &text)?))?;
                }
                Ok(())
            }
            ModelCmd::Show { model } => {
                let m = load_model(&model)?;
                // writeln! rather than println!: a closed pipe (`| head`) is an error, not a panic.
                let mut out = std::io::stdout().lock();
                writeln!(
                    out,
                    "{}: {} bodies, {} joints ({} actuated), {} feet, {:.6} kg",
                    m.name,
                    m.bodies.len(),
                    m.joints.len(),
                    m.actuated_joints().len(),
                    m.feet.len(),
                    m.total_mass()
                )?;
                for j in &m.joints {
                    writeln!(
                        out,
                        "  {:10} {:>8} -> {:16} limits [{:7.1}, {:7.1}] deg  {}",
                        j.name,
                        m.bodies[j.parent].name,
                        m.bodies[j.child].name,
                        j.limits.0.to_degrees(),
                        j.limits.1.to_degrees(),
                        j.actuation
                    )?;
                }
                for leg in m.legs() {
                    writeln!(
                        out,
                        "  {} leg length {:.4} m",
                        leg.name(),
                        m.leg_length(leg)
                    )?;
                }
                Ok(())
            }
        }
    }
}

/// Lowers `options`' timestep to one at which the model's stiffest actuated joint does not ring
/// (`physics::stiffest_joint`: omega dt under the limit the physics robot enforces), rounded down
/// to one significant digit, and says so: the scale fly's 3.8e-8 N m/rad on 5e-15 kg m^2 rings
/// at 2740 rad/s, far too fast for the default 0.5 ms.
fn stable_timestep(m: &model::Model, options: &mut model::MjcfOptions) -> Result<()> {
    let Some(s) = physics::stiffest_joint(m, options)? else {
        return Ok(());
    };
    let stable = s.stable_timestep_s();
    if options.timestep_s <= stable {
        return Ok(());
    }
    let decade = 10f64.powf(stable.log10().floor());
    let dt = (stable / decade).floor() * decade;
    println!(
        "{}: MJCF timestep {} ms, not the default {} ms: joint {}'s actuator ({:.3e} N m/rad on \
         {:.3e} kg m^2) rings at {:.0} rad/s, and MuJoCo is stable below {:.3} ms",
        m.name,
        dt * 1e3,
        options.timestep_s * 1e3,
        s.joint,
        s.kp,
        s.inertia,
        s.omega_rad_s,
        stable * 1e3
    );
    options.timestep_s = dt;
    Ok(())
}
