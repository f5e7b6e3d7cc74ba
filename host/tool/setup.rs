//! From a scene's `[tool]` to the solver's contact set-up: the built tool, its contact constants, its motion and
//! the thermal-only tool particles (roethlin-solver.md §5.4, §5.6).

use crate::kernels::contact::penalty::{cap, law, slip};
use crate::kernels::contact::tool2d::{BACK, TOP};
use crate::kernels::contact::{ContactParams, Tool2d, ToolGeometry, ToolShape};
use crate::material::FlowModel;
use crate::scene::{ContactLawKind, FrictionCap, Lattice, Scene, Switch, Tool};
use crate::{Error, Result};

use super::motion::{Rotation, ToolMotion};
use super::shape::Shape;

/// The tool's shape of a scene's `[tool]` (validated, and a mesh's grid built, when the scene was read).
pub fn shape(t: &Tool) -> Result<Shape> {
    match &t.mesh {
        Some(m) => Ok(Shape::Mesh(m.grid.clone())),
        None => build_tool(t).map(Shape::Parametric),
    }
}

/// The built parametric tool of a scene's `[tool]` (validated when the scene was read); a mesh tool has none.
pub fn build_tool(t: &Tool) -> Result<Tool2d> {
    if t.mesh.is_some() {
        return Err(Error::Scene("tool: a mesh tool has no outline (rake face, edge) to build".into()));
    }
    Tool2d::new(&ToolShape {
        rake_angle: t.rake_angle.to_radians(),
        clearance_angle: t.clearance_angle.to_radians(),
        edge_radius: t.edge_radius,
        length: t.length,
        height: t.height,
    })
    .map_err(|e| Error::Scene(format!("tool: {e:?}")))
}

/// The tool's motion: a translation in the plane and, with `rotation`, a turn about the unit axis a = axis/|axis|
/// at ω = 2π rpm/60 rad/s (none without the key, so those scenes keep the translating path's bits).
pub fn motion(t: &Tool) -> ToolMotion {
    let mut m = ToolMotion::translating(t.position, t.velocity, t.ramp);
    m.rotation = t.rotation.map(|r| {
        let norm = (r.axis[0] * r.axis[0] + r.axis[1] * r.axis[1] + r.axis[2] * r.axis[2]).sqrt();
        Rotation { axis: r.axis.map(|a| a / norm), centre: r.centre, rate: r.rpm * std::f64::consts::TAU / 60.0 }
    });
    m
}

/// The contact constants: κ, μ, the friction cap (static: κ_fric σ_y(0, ε̇0, T0)/√3 with T0 the initial
/// temperature; current: κ_fric/√3 times each particle's σ_y), friction heating, Usui's constants and the melt
/// temperature that caps friction heating.
pub fn contact_params(scene: &Scene, t: &Tool, model: Option<&FlowModel>) -> ContactParams {
    let inv_sqrt3 = 1.0 / 3f64.sqrt();
    let (cap_mode, cap_stress) = match (t.friction_cap, model) {
        (FrictionCap::Static, Some(m)) => {
            (cap::STATIC, t.friction_cap_factor * inv_sqrt3 * m.sigma_y(0.0, 0.0, scene.physics.initial_temperature))
        }
        (FrictionCap::Current, Some(_)) => (cap::CURRENT, t.friction_cap_factor * inv_sqrt3),
        _ => (cap::NONE, 0.0),
    };
    ContactParams {
        kappa: t.contact_stiffness,
        friction_kappa: t.friction_stiffness.unwrap_or(t.contact_stiffness),
        friction: t.friction,
        cap_stress,
        heat_fraction: t.friction_heating,
        usui_psi: t.usui.map_or(0.0, |u| u[0]),
        usui_xi: t.usui.map_or(0.0, |u| u[1]),
        melt: model.map_or(f64::INFINITY, |m| m.melt_temperature()),
        damping: t.contact_damping,
        bulk: scene.material.bulk_modulus(),
        cap_mode,
        law: match t.contact_law {
            ContactLawKind::Step => law::STEP,
            ContactLawKind::Bulk => law::BULK,
        },
        // The original code's sliding velocity and unprojected history (erratum 25) under `model = "mfree_iwf"`.
        slip_mode: if scene.model.switches().has(Switch::GlmSlip) { slip::C2D } else { slip::PROJECTED },
        _pad: 0,
    }
}

/// Thermal-only particles filling the tool: by default cell centres of a lattice of spacing `dx` in the tool frame,
/// kept when at least dx/2 inside the tool (`[tool.thermal].lattice` names the other sampling); `held` marks its
/// far boundary (the parametric tool's top and back faces, a mesh tool's top: its fixture), held at the tool's
/// temperature.
pub struct ToolParticles {
    /// World positions at t = 0 (z = 0 in 2D).
    pub pos: Vec<[f64; 3]>,
    pub held: Vec<bool>,
}

/// The tool particles of a scene's `[tool.thermal]`: the parametric tool's (2D) or a mesh tool's (3D).
pub fn thermal_particles(shape: &Shape, t: &Tool, dx: f64, band: f64) -> ToolParticles {
    match shape {
        Shape::Parametric(tool) => tool_particles(tool, t, dx, band),
        Shape::Mesh(m) => mesh_tool_particles(m, t, dx, band),
    }
}

/// A mesh tool's particles: the cell centres of a lattice of spacing `dx` from the mesh's lowest corner (tool
/// frame) that lie at least dx/2 inside it (a hair of rounding allowed, so that a box aligned with the lattice is
/// filled exactly); held: those within `band` of the mesh's highest y (its fixture, away from the cut).
pub fn mesh_tool_particles(m: &crate::mesh::MeshGridData, t: &Tool, dx: f64, band: f64) -> ToolParticles {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for v in &m.verts {
        for k in 0..3 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    let n: [usize; 3] = std::array::from_fn(|k| ((hi[k] - lo[k]) / dx).ceil().max(0.0) as usize);
    let query = m.tool();
    let mut out = ToolParticles { pos: Vec::new(), held: Vec::new() };
    for kz in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let p = [lo[0] + (i as f64 + 0.5) * dx, lo[1] + (j as f64 + 0.5) * dx, lo[2] + (kz as f64 + 0.5) * dx];
                if query.query(p).distance > -0.5 * dx * (1.0 - 1e-9) {
                    continue;
                }
                out.pos.push(std::array::from_fn(|k| p[k] + t.position[k]));
                out.held.push(hi[1] - p[1] < band);
            }
        }
    }
    out
}

/// The parametric tool's particles on the lattice `[tool.thermal].lattice` names (its doc), in the tool frame;
/// held: those within `band` of the top or back face.
pub fn tool_particles(tool: &Tool2d, t: &Tool, dx: f64, band: f64) -> ToolParticles {
    let lattice = t.thermal.as_ref().map_or(Lattice::Cells, |th| th.lattice);
    // The lattice's first point, its size, and the offset of its points within a spacing (cells: the centres).
    let (corner, n, shift) = match lattice {
        Lattice::Cells => {
            ([-t.length, 0.0], [(t.length / dx).ceil() as usize + 2, (t.height / dx).ceil() as usize + 2], 0.5)
        }
        Lattice::Nodes => {
            // The original's bounding box (`tool::safe_bb(0.1 dx)`): from the back and the edge's lowest point to
            // the top and the arc's front-most point, grown by 0.1 dx; nodes at corner + k dx, k = 0 ..= floor(extent
            // / dx), kept when inside (its `tool::inside`).
            let front = tool.seg.iter().fold(tool.centre[0] + tool.radius, |m, s| m.max(s[0]).max(s[2]));
            let lo = [-t.length - 0.1 * dx, -0.1 * dx];
            let hi = [front + 0.1 * dx, t.height + 0.1 * dx];
            (lo, std::array::from_fn(|k| ((hi[k] - lo[k]) / dx) as usize + 1), 0.0)
        }
    };
    let mut out = ToolParticles { pos: Vec::new(), held: Vec::new() };
    for j in 0..n[1] {
        for i in 0..n[0] {
            let p = [corner[0] + (i as f64 + shift) * dx, corner[1] + (j as f64 + shift) * dx];
            let d = tool.closest(p).distance;
            let kept = match lattice {
                Lattice::Cells => d <= -0.5 * dx,
                Lattice::Nodes => d < 0.0,
            };
            if !kept {
                continue;
            }
            let top = tool.seg[TOP][1] - p[1];
            let back = p[0] - tool.seg[BACK][0];
            out.pos.push([p[0] + t.position[0], p[1] + t.position[1], 0.0]);
            out.held.push(top < band || back < band);
        }
    }
    out
}

/// Refuses a tool that overlaps the workpiece at t = 0 (a particle strictly inside: the penalty force would
/// explode) or never meets it before the end of the run (nothing would be cut): the tool, in its motion, and the
/// particles, moving on with their initial velocities, are checked at 400 instants.
pub fn check_engagement<G: ToolGeometry>(
    scene: &Scene,
    key: &str,
    tool: &G,
    motion: &ToolMotion,
    pos: &[[f64; 3]],
    vel: &[[f64; 3]],
) -> Result<()> {
    let at = |time: f64| {
        let s = motion.state_at(time, 0.0, 0.0);
        pos.iter()
            .zip(vel)
            .filter(|(p, v)| tool.contains(s.to_tool(std::array::from_fn(|k| p[k] + v[k] * time))))
            .count()
    };
    // At t = 0 only a particle inside by more than 1e-6 Δx is refused: one on the outline (its distance is 0 up to
    // rounding) is a legitimate start, e.g. a block resting on the tool.
    let s = motion.state_at(0.0, 0.0, 0.0);
    let tol = 1e-6 * scene.discretisation.dx;
    let inside = pos.iter().filter(|p| tool.query(s.to_tool(**p)).distance < -tol).count();
    if inside > 0 {
        return Err(Error::Scene(format!(
            "{}: {key}.position: {inside} particles lie inside the tool at t = 0; expected the tool clear of the \
             workpiece (move it back along its velocity)",
            scene.origin
        )));
    }
    let end = scene.time.end;
    if !(1..=400).any(|k| at(end * k as f64 / 400.0) > 0) {
        return Err(Error::Scene(format!(
            "{}: {key}: the tool never meets the workpiece before time.end = {end:e} s; expected a position and \
             velocity that bring its edge into the material",
            scene.origin
        )));
    }
    Ok(())
}
