//! Pictures of a simulated pose for Python: `render_pose` (one RGB frame, the environment's
//! `rgb_array`), `camera_half_extent` (the scale to keep over a run) and `write_walk_gif` (a run
//! as the demo's walk GIF, camera following the thorax), all on the scene's ground; the drawing
//! is `report::robot`'s.

use std::path::PathBuf;

use numpy::ndarray::Array3;
use numpy::{PyArray3, ToPyArray};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;
use crate::model::Model;
use report::robot::{FRAME_SIZE, WalkPose};

/// The terrain of `scene` (a physics port's scene: `flat+floor+model:FILE` draws `flat`).
fn ground(scene: &str) -> PyResult<report::robot::Ground> {
    let terrain = scene.split('+').next().unwrap_or(scene);
    let g = planner::terrain::Ground::parse(terrain).map_err(|e| value_error(e.to_string()))?;
    Ok(report::robot::scene_ground(&g))
}

fn pose_of(model: &Model, d: &Bound<'_, PyDict>) -> PyResult<WalkPose> {
    let get = |k: &str| -> PyResult<Bound<'_, PyAny>> {
        d.get_item(k)?
            .ok_or_else(|| value_error(format!("pose: no `{k}`")))
    };
    let position: [f64; 3] = get("thorax_position_m")?.extract()?;
    let orientation: [f64; 4] = get("thorax_orientation")?.extract()?;
    let q: Vec<f64> = get("q")?.extract()?;
    let n = model.inner.joints.len();
    if q.len() != n {
        return Err(value_error(format!(
            "pose: q has {} angles, model {} has {n} joints",
            q.len(),
            model.inner.name
        )));
    }
    let stance: Vec<bool> = match d.get_item("stance")? {
        Some(s) => s.extract()?,
        None => vec![false; model.inner.feet.len()],
    };
    let caption: String = match d.get_item("caption")? {
        Some(c) => c.extract()?,
        None => String::new(),
    };
    Ok(WalkPose {
        thorax: (position, orientation),
        q,
        stance,
        caption,
    })
}

/// The camera half-extent (m, x y z) that holds `pose` around its thorax on `scene`.
#[pyfunction]
#[pyo3(signature = (model, pose, scene = "flat"))]
pub fn camera_half_extent(
    model: &Model,
    pose: &Bound<'_, PyDict>,
    scene: &str,
) -> PyResult<[f64; 3]> {
    let p = pose_of(model, pose)?;
    report::robot::camera_half_extent(&model.inner, &p, &ground(scene)?)
        .map_err(|e| value_error(e.to_string()))
}

/// One RGB frame (rows, columns, 3; uint8) of `pose` (a dict: thorax_position_m,
/// thorax_orientation (w, x, y, z), q (one angle per model joint, rad), stance (one flag per
/// foot), caption) on `scene`, the camera on the thorax with `half_extent_m`.
#[pyfunction]
#[pyo3(signature = (model, pose, half_extent_m, scene = "flat"))]
pub fn render_pose<'py>(
    py: Python<'py>,
    model: &Model,
    pose: &Bound<'py, PyDict>,
    half_extent_m: [f64; 3],
    scene: &str,
) -> PyResult<Bound<'py, PyArray3<u8>>> {
    let p = pose_of(model, pose)?;
    let rgb = report::robot::pose_rgb(&model.inner, &p, &ground(scene)?, half_extent_m)
        .map_err(|e| value_error(e.to_string()))?;
    let (w, h) = (FRAME_SIZE.0 as usize, FRAME_SIZE.1 as usize);
    let a = Array3::from_shape_vec((h, w, 3), rgb).map_err(|e| value_error(e.to_string()))?;
    Ok(a.to_pyarray(py))
}

/// Writes `poses` (dicts as for `render_pose`) as a looping GIF at `path`, each frame shown
/// `delay_ms`, the camera following the thorax at one scale, on `scene`.
#[pyfunction]
#[pyo3(signature = (model, poses, path, scene = "flat", delay_ms = 100))]
pub fn write_walk_gif(
    model: &Model,
    poses: Vec<Bound<'_, PyDict>>,
    path: PathBuf,
    scene: &str,
    delay_ms: u32,
) -> PyResult<usize> {
    let ps = poses
        .iter()
        .map(|d| pose_of(model, d))
        .collect::<PyResult<Vec<_>>>()?;
    report::robot::animate_walk_on(&model.inner, &ps, &path, delay_ms, &ground(scene)?)
        .map_err(|e| value_error(e.to_string()))?;
    Ok(ps.len())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(camera_half_extent, m)?)?;
    m.add_function(wrap_pyfunction!(render_pose, m)?)?;
    m.add_function(wrap_pyfunction!(write_walk_gif, m)?)?;
    Ok(())
}
