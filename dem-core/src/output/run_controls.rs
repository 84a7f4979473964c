//! Run controls of the driver that read the world at history rows: position gauges
//! (`outputs.gauges`: the mean centre of the discs in a region when the scene is built, fixed
//! by disc id so a restart keeps them) and the stop-at-failure load of `run.stop_after_peak`.

use crate::pipeline::World;
use crate::scene::model::{Scene, StopAfterPeak};
use crate::scene::SceneError;

/// |Σ force component `axis` of the walls of `s`| (N).
pub(crate) fn wall_load(walls: &[crate::state::Wall], s: &StopAfterPeak) -> f64 {
    s.walls
        .iter()
        .map(|&i| walls[i].force[s.axis])
        .sum::<f64>()
        .abs()
}

/// Largest load of the history rows a restart continues, as [`wall_load`] sums it.
pub(crate) fn peak_of_record(r: &super::history::Record, s: &StopAfterPeak) -> f64 {
    (0..r.len())
        .map(|k| {
            (s.walls.iter())
                .map(|&i| {
                    let w = &r.walls[i];
                    [&w.fx, &w.fy][s.axis][k]
                })
                .sum::<f64>()
                .abs()
        })
        .fold(0.0, f64::max)
}

/// Membership (by disc id) of each gauge of the scene: the discs of `world` (as built from the
/// scene) whose centre lies in the region. A gauge holding no disc is an error.
pub(crate) fn gauge_members(scene: &Scene, world: &World) -> Result<Vec<Vec<bool>>, SceneError> {
    let d = &world.state.discs;
    let n = d.id.iter().map(|&i| i as usize + 1).max().unwrap_or(0);
    scene
        .outputs
        .gauges
        .iter()
        .enumerate()
        .map(|(k, g)| {
            let [x0, y0, x1, y1] = g.region;
            let mut mask = vec![false; n];
            let mut count = 0;
            for i in 0..d.len() {
                if d.x[i] >= x0 && d.x[i] <= x1 && d.y[i] >= y0 && d.y[i] <= y1 {
                    mask[d.id[i] as usize] = true;
                    count += 1;
                }
            }
            if count == 0 {
                return Err(SceneError::Field {
                    file: scene.file.display().to_string(),
                    field: format!("outputs.gauges[{k}].region"),
                    reason: "holds no disc centre when the scene is built".into(),
                });
            }
            Ok(mask)
        })
        .collect()
}

/// Mean centre of each gauge's discs (m).
pub(crate) fn gauge_positions(st: &crate::state::State, gauges: &[Vec<bool>]) -> Vec<[f64; 2]> {
    let d = &st.discs;
    gauges
        .iter()
        .map(|mask| {
            let (mut sx, mut sy, mut n) = (0.0, 0.0, 0usize);
            for i in 0..d.len() {
                if mask.get(d.id[i] as usize).copied().unwrap_or(false) {
                    sx += d.x[i];
                    sy += d.y[i];
                    n += 1;
                }
            }
            let n = n.max(1) as f64;
            [sx / n, sy / n]
        })
        .collect()
}
