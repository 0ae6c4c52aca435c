//! The physics robot's walk figures, pinned: the default gait (the `servo-safe` preset, planned
//! and built as `dbot table --plan` builds it) walked two steps from power-on on flat ground
//! (distance per step, heading, lowest thorax height, largest tilt, slip per foot), and the
//! steepest whole-degree incline that gait, planned for the slope, climbs (it climbs the pinned
//! angle and not one degree more).
//!
//! The simulation is deterministic (the body steps on simulated time alone: the physics test
//! `bus_traffic`), so the bounds are tight: any change that moves what the physics robot does
//! (model, servo dynamics, firmware timing, planner) fails here and must regenerate the pinned
//! file, with the reason in its commit:
//!
//! ```sh
//! DBOT_REPIN=1 cargo nextest run -p lab -E 'test(/pinned_walk::/)'
//! ```
//!
//! which measures again (the incline by bisection over whole degrees) and rewrites
//! `pinned_walk.json` beside this file. The SNS example's climb is pinned on the Python side
//! (python/tests/test_sns_walk.py).

use std::path::PathBuf;
use std::time::Duration;

use lab::physics_walk::{End, Follow, Walk, walk_and_record};
use physics::{Figures, PhysicsRobot};
use planner::gait::StepParams;
use planner::terrain::Ground;
use protocol::{PlayCommand, Steps};
use serde_json::{Value, json};

/// Steps walked; the figures cover the start ramp, both steps and the stop.
const STEPS: u32 = 2;
/// Bounds around the pinned figures: far below any change of the model or the servos (the walk
/// is deterministic to the last bit; these leave room for a different libm's last digits only).
const DISTANCE_M: f64 = 5e-5;
const HEADING_DEG: f64 = 0.005;
const HEIGHT_M: f64 = 2e-5;
const TILT_DEG: f64 = 0.005;
const SLIP_M: f64 = 5e-5;
/// A climb: no fault, no fall, no sag beyond 1 cm, and at least half the planned travel.
const SAG_M: f64 = 0.01;

fn pinned_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/integration/pinned_walk.json")
}

fn repin() -> bool {
    std::env::var_os("DBOT_REPIN").is_some()
}

fn pinned() -> Value {
    let path = pinned_path();
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (DBOT_REPIN=1 writes it)", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Writes `key` of the pinned file (the other keys kept).
fn write_pinned(key: &str, value: Value) {
    let path = pinned_path();
    let mut all = std::fs::read_to_string(&path)
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
        .unwrap_or_else(|| json!({}));
    all[key] = value;
    let text = serde_json::to_string_pretty(&all).unwrap() + "\n";
    std::fs::write(&path, text).unwrap();
    eprintln!("wrote {key} of {}", path.display());
}

fn number(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("pinned_walk.json: no number `{key}` in {v}"))
}

/// The servo-safe tripod planned on `terrain`, the planned thorax travel per step (m) and its
/// step table; `None` when the planner cannot plan it there.
fn gait(terrain: Ground) -> Option<(f64, Vec<u8>)> {
    let model = planner::model::builtin("drosophibot2").unwrap();
    let mut params = StepParams::preset("servo-safe", "drosophibot2").unwrap();
    params.terrain = terrain;
    let plan = planner::plan::plan(&model, &params).ok()?;
    let table = lab::walk_turn::walk_table(&plan, "pinned").ok()?;
    let per_step = plan.thorax_velocity.x * plan.period_s;
    Some((per_step, table.bytes().to_vec()))
}

/// `table` walked `STEPS` steps from power-on on `scene` until the robot stands again.
fn walk(scene: &Ground, table: &[u8]) -> lab::Result<Figures> {
    let robot = PhysicsRobot::drosophibot(scene)?;
    let period_s = f64::from(protocol::GaitTable::parse(table)?.header().step_period_us) * 1e-6;
    let w = Walk {
        tables: vec![(0, table)],
        play: PlayCommand::forward(0, Steps::Count(STEPS)),
        queue: Vec::new(),
        what: format!("the pinned walk on {scene}"),
    };
    let follow = Follow {
        every: Duration::from_millis(10),
        limit_s: 2.0 * f64::from(STEPS) * period_s + 5.0,
        end: End::Standing,
    };
    Ok(walk_and_record(robot, &w, follow, |_| Ok(()), |_, _| Ok(()))?.figures)
}

/// Whether the servo-safe tripod planned for an incline of `deg` climbs it (see [`SAG_M`]).
fn climbs(deg: f64) -> bool {
    let ground = Ground::Incline { angle_deg: deg };
    let Some((per_step, table)) = gait(ground) else {
        eprintln!("incline {deg} deg: the planner cannot plan it");
        return false;
    };
    match walk(&ground, &table) {
        Ok(f) => {
            let along = f.forward_m / deg.to_radians().cos();
            let ok = f.verdict(SAG_M).is_none() && along > 0.5 * per_step * f64::from(STEPS);
            eprintln!(
                "incline {deg} deg: {} ({:.1} mm along the slope of {:.1} planned; {:?})",
                if ok { "climbs" } else { "does not climb" },
                along * 1e3,
                per_step * f64::from(STEPS) * 1e3,
                f.verdict(SAG_M)
            );
            ok
        }
        Err(e) => {
            eprintln!("incline {deg} deg: {e}");
            false
        }
    }
}

#[test]
fn the_flat_walks_figures_are_the_pinned_ones() {
    let (per_step, table) = gait(Ground::Flat).unwrap();
    let f = walk(&Ground::Flat, &table).unwrap();
    eprintln!("{f:?}");
    let slip: serde_json::Map<String, Value> = f
        .slip_m
        .iter()
        .map(|(leg, s)| (format!("{leg:?}"), json!(s)))
        .collect();
    let now = json!({
        "planned_per_step_m": per_step,
        "per_step_m": f.forward_m / f64::from(STEPS),
        "heading_deg": f.heading_rad.to_degrees(),
        "height_start_m": f.height_start_m,
        "height_min_m": f.height_min_m,
        "tilt_max_deg": f.tilt_max_rad.to_degrees(),
        "slip_m": slip,
    });
    // Whatever is pinned, the walk must carry the robot: no sag beyond 1 cm, no fall.
    assert_eq!(f.verdict(SAG_M), None, "{f:?}");
    if repin() {
        write_pinned("flat", now);
        return;
    }
    let pin = &pinned()["flat"];
    let close = |key: &str, tol: f64| {
        let (p, n) = (number(pin, key), number(&now, key));
        assert!(
            (p - n).abs() <= tol,
            "{key}: pinned {p}, now {n} (bound {tol}); a change that moves the physics robot \
             regenerates the pins (DBOT_REPIN=1, see this file's header) with the reason in its commit"
        );
    };
    close("planned_per_step_m", 1e-9);
    close("per_step_m", DISTANCE_M);
    close("heading_deg", HEADING_DEG);
    close("height_start_m", HEIGHT_M);
    close("height_min_m", HEIGHT_M);
    close("tilt_max_deg", TILT_DEG);
    for (leg, s) in &f.slip_m {
        let p = pin["slip_m"][format!("{leg:?}")]
            .as_f64()
            .unwrap_or_else(|| panic!("no pinned slip for {leg:?}"));
        assert!(
            (p - s).abs() <= SLIP_M,
            "{leg:?} slip: pinned {p} m, now {s} m (bound {SLIP_M}); regenerate the pins with the \
             reason in the commit (this file's header)"
        );
    }
}

#[test]
fn the_planned_gait_climbs_the_pinned_incline_and_no_steeper() {
    if repin() {
        // Coarse bisection over whole degrees between flat (climbed) and 30 degrees (assumed
        // not: the test below checks the pinned angle's neighbour).
        let (mut lo, mut hi) = (0u32, 30u32);
        assert!(!climbs(f64::from(hi)), "the gait climbs {hi} degrees");
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if climbs(f64::from(mid)) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        write_pinned("steepest_incline_deg", json!(lo));
        return;
    }
    let steepest = number(&pinned(), "steepest_incline_deg");
    assert!(
        climbs(steepest),
        "no longer climbs the pinned {steepest} deg"
    );
    assert!(
        !climbs(steepest + 1.0),
        "now climbs {} deg, one more than pinned",
        steepest + 1.0
    );
}
