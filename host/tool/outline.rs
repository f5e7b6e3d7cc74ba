//! The 2D tool's outline as a closed polygon, in the tool frame and where the tool is at a given time: for
//! pictures of a run (`swarf render`). The shape is the kernels' [`Tool2d`] and the placement the run's own
//! [`ToolMotion`](super::ToolMotion), so the picture shows the tool the contact saw.

use crate::Result;
use crate::kernels::contact::Tool2d;
use crate::kernels::contact::tool2d::{BACK, FLANK, RAKE, TOP};
use crate::scene::Tool;

/// Points on the edge arc of the outline (a sharp edge gives one corner point).
const ARC_POINTS: usize = 24;

/// The outline in the tool frame, counter-clockwise: the rake face up from its arc tangent point, the top, the
/// back, the flank down to its tangent point, then the edge arc back to the rake's tangent point.
pub fn outline(tool: &Tool2d) -> Vec<[f64; 2]> {
    let start = |k: usize| [tool.seg[k][0], tool.seg[k][1]];
    let end = |k: usize| [tool.seg[k][2], tool.seg[k][3]];
    let mut out = vec![start(RAKE), end(RAKE), end(TOP), end(BACK), end(FLANK)];
    if tool.radius > 0.0 {
        let c = tool.centre;
        let angle = |p: [f64; 2]| (p[1] - c[1]).atan2(p[0] - c[0]);
        let from = angle(end(FLANK));
        let mut to = angle(start(RAKE));
        if to <= from {
            to += std::f64::consts::TAU;
        }
        // The arc's inner points; its ends are the tangent points already in the list.
        for k in 1..ARC_POINTS {
            let a = from + (to - from) * k as f64 / ARC_POINTS as f64;
            out.push([c[0] + tool.radius * a.cos(), c[1] + tool.radius * a.sin()]);
        }
    }
    out
}

/// The outline of the scene's tool in the world frame at time `t` [s]: built and moved by the run's own code
/// ([`super::setup::build_tool`], [`super::setup::motion`]).
pub fn outline_at(t: &Tool, time: f64) -> Result<Vec<[f64; 2]>> {
    let tool = super::setup::build_tool(t)?;
    let state = super::setup::motion(t).state_at(time, 0.0, 0.0);
    Ok(outline(&tool)
        .into_iter()
        .map(|p| {
            let w = state.point_to_world([p[0], p[1], 0.0]);
            [w[0], w[1]]
        })
        .collect())
}
