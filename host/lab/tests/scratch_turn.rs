use planner::gait::{StepParams, Turn};
#[test]
fn scratch() {
    let model = planner::model::builtin("drosophibot2").unwrap();
    let mut base = StepParams::preset("servo-safe", "drosophibot2").unwrap();
    base.slices = std::env::var("SL")
        .map(|s| s.parse().unwrap())
        .unwrap_or(50);
    let steps: u32 = std::env::var("ST").map(|s| s.parse().unwrap()).unwrap_or(3);
    let cases: Vec<(Option<f64>, Option<f64>)> = vec![
        (Some(-5.0), None),
        (Some(-20.0), Some(0.0)),
        (None, Some(-1.0)),
        (None, Some(1.0)),
        (Some(-15.0), Some(0.0)),
        (Some(-20.0), None),
        (Some(6.0), None),
    ];
    for (t, r) in cases {
        let mut p = base.clone();
        Turn {
            turn_deg: t,
            radius_m: r,
        }
        .apply(&mut p)
        .unwrap();
        let w = std::time::Instant::now();
        match lab::walk_turn::walk_turn(&model, &p, steps) {
            Ok(tw) => eprintln!(
                "{t:?} {r:?}: plan {:.2} deg/step R {:?} | meas {:.2} deg/step R {:.3} ahead {:.3} | heading {:.1} deg slip {:?} sag {:.1} mm | {:.1?}",
                tw.planned.turn_per_step_rad.to_degrees(),
                tw.planned.radius_m,
                tw.measured.turn_per_step_rad.to_degrees(),
                tw.measured.radius_m,
                tw.measured.centre_ahead_m,
                tw.figures.heading_rad.to_degrees(),
                tw.figures
                    .slip_m
                    .iter()
                    .map(|(_, s)| (s * 1000.0).round())
                    .collect::<Vec<_>>(),
                (tw.figures.height_start_m - tw.figures.height_min_m) * 1e3,
                w.elapsed()
            ),
            Err(e) => eprintln!("{t:?} {r:?}: {}", e.chain_text()),
        }
    }
}
