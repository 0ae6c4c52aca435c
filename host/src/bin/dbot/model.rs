//! `dbot model`: export a model as URDF, TOML or MJCF, import an AnimatLab project.

use anyhow::{Context, Result};
use clap::{Args as ClapArgs, Subcommand};
use host::model::{self, ImportOptions, Model};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Work with organism models (built-in names: drosophibot2, scale-drosophila).
#[derive(Debug, ClapArgs)]
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
        /// MJCF (MuJoCo) output file: the model standing in the planner's resting posture, with
        /// servo actuators, foot spheres and the terrain of --scene.
        #[arg(long)]
        mjcf: Option<PathBuf>,
        /// MJCF scene: flat, incline:DEG, ball[:R[:OFFSET]] (thorax held, ball spinning, as in the
        /// fly rig) or ball-fixed[:R[:OFFSET]].
        #[arg(long, default_value = "flat")]
        scene: String,
    },
    /// Print a summary: bodies, joints (limits in degrees), feet, total mass.
    Show {
        /// Built-in model name, a .toml model file or an AnimatLab .aproj file.
        #[arg(long)]
        model: String,
    },
}

/// Loads a model from a built-in name, a .toml file or an .aproj file.
pub fn load_model(spec: &str) -> Result<Model> {
    let path = Path::new(spec);
    match path.extension().and_then(|e| e.to_str()) {
        Some("toml") => model::load(path).with_context(|| format!("loading model file {spec}")),
        Some("aproj") => model::import_aproj_file(path, &ImportOptions::default())
            .with_context(|| format!("importing {spec}")),
        _ => {
            model::builtin(spec).context("--model takes a built-in name, a .toml or an .aproj file")
        }
    }
}

impl Args {
    pub fn run(self) -> Result<()> {
        match self.cmd {
            ModelCmd::Export {
                model,
                urdf,
                toml,
                mjcf,
                scene,
            } => {
                let m = load_model(&model)?;
                if urdf.is_none() && toml.is_none() && mjcf.is_none() {
                    anyhow::bail!(
                        "nothing to do: give --urdf FILE, --toml FILE and/or --mjcf FILE"
                    );
                }
                if let Some(p) = mjcf {
                    let options = model::MjcfOptions::stance(&m, &scene)
                        .with_context(|| format!("--scene {scene} for model {}", m.name))?;
                    write_whole(&p, &model::to_mjcf(&m, &options))?;
                }
                if let Some(p) = urdf {
                    write_whole(&p, &model::to_urdf(&m))?;
                }
                if let Some(p) = toml {
                    let notes = format!("Exported by dbot from `{model}`.");
                    write_whole(&p, &model::to_toml_string(&m, &notes, &|_| String::new()))?;
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
                        "  {:10} {:>8} -> {:16} limits [{:7.1}, {:7.1}] deg  {:?}",
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

/// Writes `text` to `path` so that an interrupted run never leaves it half written
/// ([`crate::plan::replace`]).
fn write_whole(path: &Path, text: &str) -> Result<()> {
    let name = path
        .file_name()
        .with_context(|| format!("{} is not a file name", path.display()))?
        .to_string_lossy();
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    crate::plan::replace(dir, &name, |p| Ok(std::fs::write(p, text)?))
}
