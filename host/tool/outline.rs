//! The tool's outline as a closed polyline, for pictures: the frames' `tool_*.vtp` and `swarf render`. The
//! parametric 2D tool's boundary (kernels/src/contact/tool2d.rs) counter-clockwise in the tool frame: flank F → T_f,
//! the edge arc T_f → T_r sampled at equal angles, rake T_r → R, top R → TL, back TL → F; then placed in the world
//! by the tool's rigid motion at an instant (`ToolState::point_to_world`).

use crate::kernels::contact::ToolState;
use crate::kernels::contact::tool2d::{BACK, FLANK, RAKE, TOP, Tool2d};

/// Points of the arc per radian of its sweep (at least 2 points on any arc with a radius).
const ARC_POINTS_PER_RADIAN: f64 = 16.0;

/// The outline's vertices in the tool frame, counter-clockwise, the first not repeated at the end: the corners
/// F, T_f, the arc's inner points, T_r, R and TL (a sharp edge: its corner once).
pub fn outline(tool: &Tool2d) -> Vec<[f64; 2]> {
    let end = |s: usize, k: usize| [tool.seg[s][2 * k], tool.seg[s][2 * k + 1]];
    let (f, t_f) = (end(FLANK, 0), end(FLANK, 1));
    let (t_r, r) = (end(RAKE, 0), end(RAKE, 1));
    let tl = end(TOP, 1);
    debug_assert_eq!(tl, end(BACK, 0));
    let mut pts = vec![f, t_f];
    if tool.radius > 0.0 {
        let a0 = tool.n_flank[1].atan2(tool.n_flank[0]);
        let mut a1 = tool.n_rake[1].atan2(tool.n_rake[0]);
        // The arc covers the normals from the flank's to the rake's counter-clockwise.
        if a1 < a0 {
            a1 += std::f64::consts::TAU;
        }
        let k = ((a1 - a0) * ARC_POINTS_PER_RADIAN).ceil().max(2.0) as usize;
        for j in 1..k {
            let a = a0 + (a1 - a0) * j as f64 / k as f64;
            pts.push([tool.centre[0] + tool.radius * a.cos(), tool.centre[1] + tool.radius * a.sin()]);
        }
        pts.push(t_r);
    }
    pts.push(r);
    pts.push(tl);
    pts
}

/// The outline placed in the world at the state `s` (z = 0 for a planar tool).
pub fn in_world(outline: &[[f64; 2]], s: &ToolState) -> Vec<[f64; 3]> {
    outline.iter().map(|p| s.point_to_world([p[0], p[1], 0.0])).collect()
}

/// The outline of the scene's tool `t` in the world at time `time` [s] (x, y), built and moved by the run's own
/// code (`setup::build_tool`, `setup::motion`): for pictures of run folders written before frames carried it.
pub fn outline_at(t: &crate::scene::Tool, time: f64) -> crate::Result<Vec<[f64; 2]>> {
    let tool = super::setup::build_tool(t)?;
    let state = super::setup::motion(t).state_at(time, 0.0, 0.0);
    Ok(in_world(&outline(&tool), &state).into_iter().map(|p| [p[0], p[1]]).collect())
}
