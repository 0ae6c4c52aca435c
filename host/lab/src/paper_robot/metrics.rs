//! Figures of merit over [`PhaseRow`]s, per leg pair (front, middle, hind) and phase of the leg
//! (swing, stance): how far the loads are from the planned torques, how far two runs are apart,
//! and the step-to-step spread. All are root mean squares over the group's joints and slices.

use std::collections::HashMap;

use planner::analysis::fit::{prediction_r2, rms};

use super::experiment::PhaseRow;

/// A leg pair, named by the second letter of its legs (`LF`, `RF` -> front).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pair {
    Front,
    Middle,
    Hind,
}

impl Pair {
    pub const ALL: [Pair; 3] = [Pair::Front, Pair::Middle, Pair::Hind];

    pub fn name(self) -> &'static str {
        match self {
            Pair::Front => "front",
            Pair::Middle => "middle",
            Pair::Hind => "hind",
        }
    }

    /// The pair of a joint named `LEG_KIND` (`LF_ThC1`).
    pub fn of(joint: &str) -> Option<Pair> {
        match joint.as_bytes().get(1) {
            Some(b'F') => Some(Pair::Front),
            Some(b'M') => Some(Pair::Middle),
            Some(b'H') => Some(Pair::Hind),
            _ => None,
        }
    }
}

/// A group of rows: one leg pair in swing or in stance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Group {
    pub pair: Pair,
    pub stance: bool,
}

impl Group {
    pub fn all() -> impl Iterator<Item = Group> {
        Pair::ALL.into_iter().flat_map(|pair| {
            [false, true]
                .into_iter()
                .map(move |stance| Group { pair, stance })
        })
    }

    pub fn name(self) -> String {
        format!(
            "{} {}",
            self.pair.name(),
            if self.stance { "stance" } else { "swing" }
        )
    }

    pub fn holds(self, r: &PhaseRow) -> bool {
        Pair::of(&r.joint) == Some(self.pair) && r.stance == self.stance
    }
}

fn rows<'a>(all: &'a [PhaseRow], exp: &'a str, g: Group) -> impl Iterator<Item = &'a PhaseRow> {
    all.iter()
        .filter(move |r| r.experiment == exp && g.holds(r))
}

/// RMS of (load - planned torque) of `exp` in `g`, N m.
pub fn load_vs_plan(all: &[PhaseRow], exp: &str, g: Group) -> Option<f64> {
    rms(rows(all, exp, g).map(|r| r.mean_nm - r.planned_nm))
}

/// The R^2 of the planned torque as a predictor of the load in `g` (`prediction_r2`: 1 -
/// residual / total sum of squares about the loads' mean).
pub fn load_r2(all: &[PhaseRow], exp: &str, g: Group) -> Option<f64> {
    let pairs: Vec<(f64, f64)> = rows(all, exp, g)
        .map(|r| (r.mean_nm, r.planned_nm))
        .collect();
    prediction_r2(&pairs)
}

/// RMS of the step-to-step SD of the loads of `exp` in `g`, N m.
pub fn spread(all: &[PhaseRow], exp: &str, g: Group) -> Option<f64> {
    rms(rows(all, exp, g).map(|r| r.sd_nm))
}

/// The row of `exp` for `joint` at `slice`, by a lookup built once per call site.
fn index<'a>(all: &'a [PhaseRow], exp: &str) -> HashMap<(&'a str, usize), &'a PhaseRow> {
    all.iter()
        .filter(|r| r.experiment == exp)
        .map(|r| ((r.joint.as_str(), r.slice), r))
        .collect()
}

/// RMS difference between runs `a` and `b` in `g` (same joint, same slice): of the loads, or of
/// the planned torques with `planned`.
pub fn apart(all: &[PhaseRow], a: &str, b: &str, g: Group, planned: bool) -> Option<f64> {
    let pick = |r: &PhaseRow| if planned { r.planned_nm } else { r.mean_nm };
    let bs = index(all, b);
    rms(rows(all, a, g).filter_map(|ra| {
        bs.get(&(ra.joint.as_str(), ra.slice))
            .map(|rb| pick(ra) - pick(rb))
    }))
}

/// Largest |a - b| of the planned torques (or loads) of `g`, N m, and the joint where it occurs.
pub fn peak_apart(
    all: &[PhaseRow],
    a: &str,
    b: &str,
    g: Group,
    planned: bool,
) -> Option<(f64, String)> {
    let pick = |r: &PhaseRow| if planned { r.planned_nm } else { r.mean_nm };
    let bs = index(all, b);
    rows(all, a, g)
        .filter_map(|ra| {
            bs.get(&(ra.joint.as_str(), ra.slice))
                .map(|rb| ((pick(ra) - pick(rb)).abs(), ra.joint.clone()))
        })
        .max_by(|x, y| x.0.total_cmp(&y.0))
}

/// Per joint of `a`: RMS over the step of (load in a - load in b) and RMS of the two runs' SDs.
pub fn joint_change(all: &[PhaseRow], a: &str, b: &str) -> Vec<(String, f64, f64)> {
    let mut joints: Vec<String> = Vec::new();
    for r in all.iter().filter(|r| r.experiment == a) {
        if !joints.contains(&r.joint) {
            joints.push(r.joint.clone());
        }
    }
    let bs = index(all, b);
    joints
        .into_iter()
        .filter_map(|j| {
            let pairs: Vec<(&PhaseRow, &PhaseRow)> = all
                .iter()
                .filter(|r| r.experiment == a && r.joint == j)
                .filter_map(|ra| bs.get(&(ra.joint.as_str(), ra.slice)).map(|rb| (ra, *rb)))
                .collect();
            let d = rms(pairs.iter().map(|(x, y)| x.mean_nm - y.mean_nm))?;
            let sd = rms(pairs.iter().flat_map(|(x, y)| [x.sd_nm, y.sd_nm]))?;
            Some((j, d, sd))
        })
        .collect()
}

/// Per joint of `exp`: RMS of the load over the joint's stance slices, N m.
pub fn stance_load(all: &[PhaseRow], exp: &str) -> Vec<(String, f64)> {
    stance_rms(all, exp, |r| r.mean_nm)
}

/// Per joint of `exp`: RMS of the planned torque over the joint's stance slices, N m.
pub fn stance_planned(all: &[PhaseRow], exp: &str) -> Vec<(String, f64)> {
    stance_rms(all, exp, |r| r.planned_nm)
}

/// Per joint of `exp`: RMS of `value` over the joint's stance slices.
fn stance_rms(all: &[PhaseRow], exp: &str, value: impl Fn(&PhaseRow) -> f64) -> Vec<(String, f64)> {
    let mut out: Vec<(String, f64)> = Vec::new();
    for r in all.iter().filter(|r| r.experiment == exp) {
        if !out.iter().any(|(j, _)| *j == r.joint) {
            let v = rms(all
                .iter()
                .filter(|x| x.experiment == exp && x.joint == r.joint && x.stance)
                .map(&value));
            if let Some(v) = v {
                out.push((r.joint.clone(), v));
            }
        }
    }
    out
}

/// Per joint: how many slices the loads of `a` lag those of `b` (the circular shift within
/// +-`max` slices that best correlates them, mean removed), and that lag as a fraction of the step.
pub fn lag(all: &[PhaseRow], a: &str, b: &str, max: usize) -> Vec<(String, f64)> {
    let series = |e: &str, j: &str| -> Vec<f64> {
        let mut v: Vec<(usize, f64)> = all
            .iter()
            .filter(|r| r.experiment == e && r.joint == j)
            .map(|r| (r.slice, r.mean_nm))
            .collect();
        v.sort_by_key(|x| x.0);
        let m = v.iter().map(|x| x.1).sum::<f64>() / v.len().max(1) as f64;
        v.into_iter().map(|x| x.1 - m).collect()
    };
    let mut joints: Vec<&str> = Vec::new();
    for r in all.iter().filter(|r| r.experiment == a) {
        if !joints.contains(&r.joint.as_str()) {
            joints.push(&r.joint);
        }
    }
    joints
        .into_iter()
        .filter_map(|j| {
            let (x, y) = (series(a, j), series(b, j));
            let n = x.len();
            if n == 0 || n != y.len() {
                return None;
            }
            let max = max.min(n / 2) as isize;
            let best = (-max..=max)
                .map(|k| {
                    let c: f64 = (0..n)
                        .map(|s| x[(s as isize + k).rem_euclid(n as isize) as usize] * y[s])
                        .sum();
                    (k, c)
                })
                .max_by(|p, q| p.1.total_cmp(&q.1))?;
            Some((j.to_owned(), best.0 as f64 / n as f64))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(
        exp: &str,
        joint: &str,
        slice: usize,
        stance: bool,
        planned: f64,
        mean: f64,
    ) -> PhaseRow {
        PhaseRow {
            experiment: exp.into(),
            joint: joint.into(),
            slice,
            slices: 4,
            stance,
            planned_nm: planned,
            mean_nm: mean,
            sd_nm: 0.1,
            n: 3,
        }
    }

    #[test]
    fn rms_figures_match_a_hand_calculation() {
        // Front swing: loads off the plan by 0.3 and 0.4 -> RMS sqrt((0.09 + 0.16) / 2).
        let mut rows = vec![
            row("a", "LF_ThC1", 0, false, 1.0, 1.3),
            row("a", "RF_ThC1", 0, false, 0.0, -0.4),
            row("a", "LH_CTr", 0, false, 5.0, 0.0),
            row("b", "LF_ThC1", 0, false, 2.0, 1.0),
            row("b", "RF_ThC1", 0, false, 0.0, -0.4),
        ];
        let g = Group {
            pair: Pair::Front,
            stance: false,
        };
        let v = load_vs_plan(&rows, "a", g).unwrap();
        assert!((v - (0.125f64).sqrt()).abs() < 1e-12);
        // a - b loads: 0.3 and 0 -> sqrt(0.09 / 2); planned: -1 and 0 -> sqrt(1 / 2).
        assert!((apart(&rows, "a", "b", g, false).unwrap() - 0.045f64.sqrt()).abs() < 1e-12);
        assert!((apart(&rows, "a", "b", g, true).unwrap() - 0.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(
            peak_apart(&rows, "a", "b", g, true),
            Some((1.0, "LF_ThC1".to_string()))
        );
        // Two rows are too few for an R^2 (fit::MIN_SAMPLES); with a third, loads 1.3, -0.4 and
        // 0.6 (planned 0.5) about their mean 0.5: tot = 0.64 + 0.81 + 0.01 = 1.46; res = 0.09 +
        // 0.16 + 0.01 = 0.26.
        assert_eq!(load_r2(&rows, "a", g), None);
        rows.push(row("a", "LF_ThC2", 0, false, 0.5, 0.6));
        let r2 = load_r2(&rows, "a", g).unwrap();
        assert!((r2 - (1.0 - 0.26 / 1.46)).abs() < 1e-12);
        assert_eq!(
            load_vs_plan(
                &rows,
                "a",
                Group {
                    pair: Pair::Middle,
                    stance: true
                }
            ),
            None
        );
    }

    #[test]
    fn lag_finds_a_shifted_copy() {
        // b is a triangle over 8 slices; a is b delayed by 2 slices: a[s] = b[s - 2].
        let b = [0.0, 1.0, 2.0, 3.0, 2.0, 1.0, 0.0, -1.0];
        let mut rows = Vec::new();
        for s in 0..8 {
            rows.push(row("b", "LF_CTr", s, true, 0.0, b[s]));
            rows.push(row("a", "LF_CTr", s, true, 0.0, b[(s + 6) % 8]));
        }
        assert_eq!(
            lag(&rows, "a", "b", 3),
            vec![("LF_CTr".to_string(), 2.0 / 8.0)]
        );
    }
}
