//! `dbot steer`: the descending command. Sets the family of gaits the board blends, walks at the
//! heading for the given steps, then stops at the end of the step. The rules (which gaits can be
//! blended, the heading's range, the speed's, and faster than planned the servos' limits) are the
//! board's and the library's (`protocol::steer`, `board::rules::steer`).

use std::time::Duration;

use anyhow::{Context, bail};
use protocol::RunState;

use crate::args::board::BoardArgs;

/// Walk at a heading: the board blends a straight and a turning gait at the heading's share.
///
/// The three slots hold gaits planned with the same leg phases, slices and period, for headings
/// 0, +RANGE and -RANGE (rad of yaw per stance, `dbot plan`'s rotation); the board refuses a
/// family it cannot blend, saying why.
#[derive(Debug, clap::Args)]
#[command(after_help = "Example:
  dbot steer --family 0,1,2 --range 0.06 --heading 0.03 --steps 4   # half the left turn")]
pub struct Args {
    /// Slots of the straight, the left-turning and the right-turning gait, `S,L,R`.
    #[arg(long, value_name = "S,L,R", value_parser = parse_family)]
    pub family: (u8, u8, u8),
    /// Heading the side gaits stand for, rad.
    #[arg(long)]
    pub range: f64,
    /// Heading to walk at, rad, positive left, within +-RANGE.
    #[arg(long, allow_hyphen_values = true)]
    pub heading: f64,
    /// Speed, 1 = as planned (0.1 to 10). Faster than planned only when every servo still follows
    /// the family's tables at that speed (checked on a `virtual:PATH` robot, whose tables the host
    /// holds; elsewhere give --allow-infeasible).
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Whole steps to walk before stopping at the end of the step.
    #[arg(long)]
    pub steps: u32,
    #[command(flatten)]
    pub feasibility: crate::feasibility_args::FeasibilityArgs,
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        if self.steps == 0 {
            bail!("--steps 0: give at least one step");
        }
        let mut s = self.board.connect()?;
        let (straight, left, right) = self.family;
        s.board
            .set_steer_family(straight, left, right, self.range)
            .with_context(|| format!("setting the steering family {straight},{left},{right}"))?;
        // Faster than planned: the family's tables against the servos at that speed (the
        // library's rule); the host holds the tables of a `virtual:PATH` robot in its image.
        let model = crate::common::model_spec::load_model(
            s.setup.model.as_deref().unwrap_or("drosophibot2"),
        )?;
        let port = s.board.port().to_owned();
        let held = |slot| board::rules::period::table_of_port(&port, slot);
        let warning = board::rules::steer::check_steer(
            &mut s.board,
            self.heading,
            self.speed,
            &held,
            &model,
            self.feasibility.overrides(),
        )
        .and_then(|checked| board::rules::steer::steer(&mut s.board, checked))
        .map_err(|e| match e {
            board::rules::RuleError::Link(e) => {
                anyhow::Error::new(e).context(format!("steering at {} rad", self.heading))
            }
            other => other.into(),
        })?;
        crate::feasibility_args::warn(warning.as_ref());
        println!(
            "steering at {} rad (family {straight},{left},{right} over +-{} rad), speed {}",
            self.heading, self.range, self.speed
        );
        let mut stopping = false;
        // Steps completed as the board last reported while playing (standing, it reports none).
        let mut walked = 0;
        loop {
            s.board.wait(Duration::from_millis(100))?;
            s.board.discard_telemetry();
            let st = s.board.status()?;
            let step = st.playback.map_or(walked, |p| p.step);
            walked = step;
            match st.state {
                // Completed steps: stopping during the last one ends the walk with it.
                RunState::Walking if !stopping && step + 1 >= self.steps => {
                    s.board.stop()?;
                    stopping = true;
                }
                RunState::Ramping | RunState::Walking | RunState::Stopping => {}
                RunState::Standing | RunState::Idle => {
                    // A stop ends the step it came in: that step completed too.
                    let done = if stopping { step + 1 } else { step };
                    println!("{done} step(s), the robot stands");
                    break;
                }
                RunState::Fault => bail!(
                    "the board stopped with a fault after {step} step(s): {} (see `dbot status`)",
                    st.fault
                        .map_or("no fault recorded".to_owned(), |f| f.to_string())
                ),
                _ => {
                    bail!("the board is in state {}", st.state.name())
                }
            }
        }
        s.close()
    }
}

/// `--family 0,1,2`.
fn parse_family(v: &str) -> Result<(u8, u8, u8), String> {
    let slots: Vec<&str> = v.split(',').collect();
    let [a, b, c] = slots[..] else {
        return Err(format!("`{v}`: give three slots, straight,left,right"));
    };
    let slot = |x: &str| {
        x.trim()
            .parse::<u8>()
            .map_err(|_| format!("`{x}` is not a slot number"))
    };
    Ok((slot(a)?, slot(b)?, slot(c)?))
}
