//! `[tool]`: the parametric tool's outline or a mesh tool, where and how the tool moves, its contact law and the
//! thermal tool (docs/scenes.md).

use super::*;

/// The `[tool]` table.
const TOOL_KEYS: &[&str] = &[
    "rake_angle",
    "clearance_angle",
    "edge_radius",
    "length",
    "height",
    "position",
    "depth_of_cut",
    "body",
    "velocity",
    "ramp",
    "rotation",
    "contact_law",
    "contact_stiffness",
    "contact_damping",
    "friction_stiffness",
    "friction",
    "friction_cap",
    "friction_cap_factor",
    "friction_heating",
    "usui",
    "chip_station",
    "thermal",
    "mesh",
];

/// The outline's keys, refused beside `mesh`.
const OUTLINE_KEYS: [&str; 5] = ["rake_angle", "clearance_angle", "edge_radius", "length", "height"];

/// `[tool]` (one tool, path `tool`) or `[[tool]]` (several, paths `tool.0`, `tool.1`, …), each read by `read`;
/// several tools must be all parametric or all meshes, and only a lone tool may carry `[tool.thermal]`.
pub(super) fn tools(root: &Tab<'_>, read: impl Fn(&Tab<'_>) -> Result<Tool>) -> Result<Vec<Tool>> {
    let expected = "a table [tool], or [[tool]] tables (several tools)";
    let Some(node) = root.get("tool") else { return Ok(Vec::new()) };
    if let Val::Table(entries) = &node.val {
        return Ok(vec![read(&Tab { doc: root.doc, path: "tool", node, entries })?]);
    }
    let tables = root.tables("tool", expected)?;
    let paths: Vec<String> = (0..tables.len()).map(|i| format!("tool.{i}")).collect();
    let mut tools: Vec<Tool> = Vec::with_capacity(tables.len());
    for (&(node, entries), path) in tables.iter().zip(&paths) {
        let t = Tab { doc: root.doc, path, node, entries };
        if tables.len() > 1 && t.get("thermal").is_some() {
            return Err(t.invalid("thermal", t.get("thermal"), "no [tool.thermal] with several tools (a lone tool's)"));
        }
        let tool = read(&t)?;
        if let Some(first) = tools.first()
            && tool.mesh.is_some() != first.mesh.is_some()
        {
            let e = "every tool of one kind: all meshes, or all parametric outlines, as the first [[tool]]";
            return Err(t.invalid("mesh", t.get("mesh").or(Some(node)), e));
        }
        tools.push(tool);
    }
    if tools.is_empty() {
        return Err(root.invalid("tool", Some(node), expected));
    }
    Ok(tools)
}

/// `[tool]`, read in steps: the shape (the outline, or in 3D a mesh), where and how the tool moves, the contact
/// law, the thermal tool, then the checks that need several of them.
#[allow(clippy::too_many_arguments)]
pub(super) fn tool(
    t: &Tab<'_>,
    doc: &Doc,
    dim: usize,
    dx: f64,
    support: f64,
    physics: &Physics,
    bodies: &[Body],
    switches: super::model::ModelSwitches,
) -> Result<Tool> {
    t.check_keys(TOOL_KEYS, &[], "")?;
    let mesh = tool_mesh(t, doc, dim, support)?;
    let outline = match &mesh {
        Some(_) => Outline::none(),
        None => tool_outline(t)?,
    };
    let (position, depth_of_cut, body, velocity) = tool_placement(t, dx, bodies, switches, mesh.is_some())?;
    let ramp = t.number("ramp", "a non-negative time in s", non_negative)?.unwrap_or(0.0);
    let rotation = tool_rotation(t, mesh.is_some())?;
    let law = tool_contact(t, physics, switches)?;
    let chip_station = t.number("chip_station", "a positive distance in m", positive)?;
    let thermal = tool_thermal(t, doc, dx, physics, mesh.is_some())?;
    if law.friction_heating > 0.0 && !(physics.plastic_heating || physics.conduction != Conduction::Off) {
        return Err(t.invalid(
            "friction_heating",
            t.get("friction_heating"),
            "0: friction heating needs the thermal model (plastic heating or conduction, and the material's \
             specific heat)",
        ));
    }
    if mesh.is_none() {
        check_outline(t, &outline)?;
    }
    if rotation.is_some() && thermal.is_some() {
        return Err(t.invalid(
            "rotation",
            t.get("rotation"),
            "no rotation with [tool.thermal]: the thermal tool particles move with the tool's translation only",
        ));
    }
    if thermal.is_some() && dim != 2 && mesh.is_none() {
        return Err(t.invalid(
            "thermal",
            t.get("thermal"),
            "no [tool.thermal] with the parametric tool in 3D (its particles fill the 2D outline); a mesh tool's fill it",
        ));
    }
    if mesh.is_some() && chip_station.is_some() {
        return Err(t.invalid(
            "chip_station",
            t.get("chip_station"),
            "no chip_station with a mesh tool (it has no rake face)",
        ));
    }
    Ok(Tool {
        rake_angle: outline.rake_angle,
        clearance_angle: outline.clearance_angle,
        edge_radius: outline.edge_radius,
        length: outline.length,
        height: outline.height,
        mesh,
        position,
        depth_of_cut,
        body,
        velocity,
        ramp,
        rotation,
        contact_law: law.contact_law,
        contact_stiffness: law.contact_stiffness,
        contact_damping: law.contact_damping,
        friction_stiffness: law.friction_stiffness,
        friction: law.friction,
        friction_cap: law.friction_cap,
        friction_cap_factor: law.friction_cap_factor,
        friction_heating: law.friction_heating,
        usui: law.usui,
        chip_station,
        thermal,
    })
}

/// Where the tool is at t = 0 and how fast it moves: the parametric tool's `position` ([x, y], or [x] with
/// `depth_of_cut`) and `velocity` [vx, vy], z = 0; a mesh tool's `[x, y, z]` and `[vx, vy, vz]`.
#[allow(clippy::type_complexity)]
fn tool_placement(
    t: &Tab<'_>,
    dx: f64,
    bodies: &[Body],
    switches: super::model::ModelSwitches,
    mesh: bool,
) -> Result<([f64; 3], Option<f64>, Option<usize>, [f64; 3])> {
    if !mesh {
        let row_datum = switches.has(super::model::Switch::RowDatum);
        let (p, depth_of_cut, body) = tool_position(t, dx, bodies, row_datum)?;
        let e = "the cutting velocity [vx, vy] in m/s";
        let v = t.required("velocity", e, t.vector("velocity", 2, e)?)?;
        return Ok(([p[0], p[1], 0.0], depth_of_cut, body, v));
    }
    for k in ["depth_of_cut", "body"] {
        if t.get(k).is_some() {
            return Err(t.invalid(
                k,
                t.get(k),
                "no depth_of_cut or body with a mesh tool: position = [x, y, z] places it",
            ));
        }
    }
    let e = "where the mesh tool's frame origin is at t = 0, [x, y, z] in m";
    let p = t.required("position", e, t.vector("position", 3, e)?)?;
    let e = "the tool's velocity [vx, vy, vz] in m/s";
    let v = t.required("velocity", e, t.vector("velocity", 3, e)?)?;
    Ok((p, None, None, v))
}

/// `mesh = { ... }` (3D): read, weld, check, place and hash the tool's surface ([`ToolMesh`]); a file that cannot
/// be read or a mesh that is not closed and consistently oriented is refused here, naming the key and what is
/// wrong where.
fn tool_mesh(t: &Tab<'_>, doc: &Doc, dim: usize, support: f64) -> Result<Option<ToolMesh>> {
    let e = "a table { file = \"tool.stl\", scale, axis, angle, weld, cell, cutoff, safe }";
    let Some(m) = t.table("mesh", "tool.mesh", e)? else { return Ok(None) };
    if dim != 3 {
        return Err(t.invalid("mesh", t.get("mesh"), "a 3D scene (dim = 3): mesh tools are 3D"));
    }
    if let Some(k) = OUTLINE_KEYS.iter().find(|k| t.get(k).is_some()) {
        return Err(t.invalid(k, t.get(k), "no outline keys beside mesh (the mesh is the tool's shape)"));
    }
    m.check_keys(&["file", "scale", "axis", "angle", "weld", "cell", "cutoff", "safe"], &[], "")?;
    let e = "a mesh file (.stl, .obj, .k) relative to the scene's folder";
    let file = m.required("file", e, m.string("file", e, |s| !s.trim().is_empty())?)?;
    let scale = m.number("scale", "a positive scale (the file's unit in m)", positive)?.unwrap_or(1.0);
    let e = "a finite, non-zero axis [x, y, z]";
    let axis = m.vector("axis", 3, e)?.unwrap_or([0.0, 0.0, 1.0]);
    let angle = m.number("angle", "a finite angle in degrees", |_| true)?.unwrap_or(0.0);
    let weld = m.number("weld", "a non-negative fraction of the mesh's diagonal", non_negative)?.unwrap_or(1e-9);
    let cell = m.number("cell", "a positive cell size in m", positive)?;
    let cutoff = m.number("cutoff", "a positive distance in m", positive)?.unwrap_or(support);
    let safe = m.boolean("safe", "true or false")?.unwrap_or(false);
    let placement = crate::mesh::Placement::from_axis_angle(scale, axis, angle.to_radians(), [0.0; 3])
        .map_err(|err| m.invalid("axis", m.get("axis"), format!("{e} ({err})")))?;
    let path = mesh_path(doc, file);
    let built = || -> std::result::Result<_, crate::mesh::MeshError> {
        let raw = crate::mesh::read(&path)?;
        let (checked, _) = crate::mesh::prepare(&raw, weld)?;
        let placed = placement.apply(&checked);
        let opts = crate::mesh::GridOptions { cell, safe, ..crate::mesh::GridOptions::new(cutoff) };
        crate::mesh::MeshGridData::build(&placed, &opts)
    };
    let grid = built().map_err(|err| {
        m.invalid("file", m.get("file"), format!("a closed, consistently oriented triangle mesh: {err}"))
    })?;
    Ok(Some(ToolMesh {
        file: file.to_string(),
        scale,
        axis,
        angle,
        weld,
        cell,
        cutoff,
        safe,
        triangles: grid.face_n.len(),
        grid: std::sync::Arc::new(grid),
    }))
}

/// A mesh file named in a scene ([`super::super::mesh_file_path`]).
fn mesh_path(doc: &Doc, file: &str) -> std::path::PathBuf {
    super::super::mesh_file_path(&doc.file, file)
}

/// The tool's outline as the file gives it (angles in degrees).
struct Outline {
    rake_angle: f64,
    clearance_angle: f64,
    edge_radius: f64,
    length: f64,
    height: f64,
}

impl Outline {
    /// A mesh tool's: no outline (NaN, null in summary.json).
    fn none() -> Self {
        Outline {
            rake_angle: f64::NAN,
            clearance_angle: f64::NAN,
            edge_radius: f64::NAN,
            length: f64::NAN,
            height: f64::NAN,
        }
    }
}

fn tool_outline(t: &Tab<'_>) -> Result<Outline> {
    let e = "an angle in degrees in (-90, 90)";
    let rake_angle = t.required("rake_angle", e, t.number("rake_angle", e, |x| x > -90.0 && x < 90.0)?)?;
    let e = "an angle in degrees >= 0 with rake_angle + clearance_angle < 90";
    let clearance_angle =
        t.required("clearance_angle", e, t.number("clearance_angle", e, |x| x >= 0.0 && x + rake_angle < 90.0)?)?;
    let edge_radius = t.number("edge_radius", "a non-negative radius in m", non_negative)?.unwrap_or(0.0);
    let e = "a positive length in m";
    let length = t.required("length", e, t.number("length", e, positive)?)?;
    let height = t.required("height", e, t.number("height", e, positive)?)?;
    Ok(Outline { rake_angle, clearance_angle, edge_radius, length, height })
}

/// Refuses an outline the parametric tool cannot build (kernels/src/contact/tool2d.rs), at `length`.
fn check_outline(t: &Tab<'_>, o: &Outline) -> Result<()> {
    let shape = crate::kernels::contact::ToolShape {
        rake_angle: o.rake_angle.to_radians(),
        clearance_angle: o.clearance_angle.to_radians(),
        edge_radius: o.edge_radius,
        length: o.length,
        height: o.height,
    };
    if let Err(err) = crate::kernels::contact::Tool2d::new(&shape) {
        let why = match err {
            crate::kernels::contact::tool2d::ShapeError::Angles => "angles with a wedge 90 - rake - clearance > 0",
            crate::kernels::contact::tool2d::ShapeError::Size => "finite, non-negative sizes",
            crate::kernels::contact::tool2d::ShapeError::TooSmall => {
                "a tool large enough for its edge radius (faces longer than the arc's tangent length, the flank \
                 below the top)"
            }
        };
        return Err(t.invalid("length", t.get("length"), why));
    }
    Ok(())
}

/// `rotation = { axis, centre, rpm }`: the axis must be a finite, non-zero vector; along z for the parametric tool,
/// which can only turn in its plane; any axis for a mesh tool.
fn tool_rotation(t: &Tab<'_>, any_axis: bool) -> Result<Option<ToolRotation>> {
    let e = "a table { axis = [x, y, z], centre = [x, y, z], rpm = n }";
    let Some(r) = t.table("rotation", "tool.rotation", e)? else { return Ok(None) };
    r.check_keys(&["axis", "centre", "rpm"], &[], "")?;
    let e = "a finite, non-zero axis [x, y, z]";
    let axis = r.required("axis", e, r.vector("axis", 3, e)?)?;
    let norm = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    if !(norm.is_finite() && norm > 0.0) {
        return Err(r.invalid("axis", r.get("axis"), e));
    }
    if !any_axis && (axis[0] != 0.0 || axis[1] != 0.0) {
        return Err(r.invalid(
            "axis",
            r.get("axis"),
            "an axis along z, [0, 0, 1] or [0, 0, -1]: the parametric tool is 2D and turns in its plane only",
        ));
    }
    let e = "the rotation centre [x, y, z] in m, in the tool frame";
    let centre = r.required("centre", e, r.vector("centre", 3, e)?)?;
    let e = "a finite rotational speed in revolutions per minute (positive: right-handed about axis)";
    let rpm = r.required("rpm", e, r.number("rpm", e, |_| true)?)?;
    Ok(Some(ToolRotation { axis, centre, rpm }))
}

/// The contact law's keys of `[tool]`.
struct ContactLaw {
    contact_law: ContactLawKind,
    contact_stiffness: f64,
    contact_damping: f64,
    friction_stiffness: Option<f64>,
    friction: f64,
    friction_cap: FrictionCap,
    friction_cap_factor: f64,
    friction_heating: f64,
    usui: Option<[f64; 2]>,
}

/// The contact law's defaults: `"bulk"` with ξ = 1 (converged in Δt and κ, docs/validation.md), or the theses'
/// undamped `"step"` under the original model's `step_contact` switch.
fn tool_contact(t: &Tab<'_>, physics: &Physics, switches: super::model::ModelSwitches) -> Result<ContactLaw> {
    let theses = switches.has(super::model::Switch::StepContact);
    let contact_law = match t.string("contact_law", "\"step\" or \"bulk\"", |s| matches!(s, "step" | "bulk"))? {
        Some("bulk") => ContactLawKind::Bulk,
        Some(_) => ContactLawKind::Step,
        None if theses => ContactLawKind::Step,
        None => ContactLawKind::Bulk,
    };
    let contact_stiffness =
        t.number("contact_stiffness", "a fraction in (0, 1]", |x| x > 0.0 && x <= 1.0)?.unwrap_or(0.1);
    let contact_damping = t
        .number("contact_damping", "a fraction of critical damping in [0, 1]", |x| (0.0..=1.0).contains(&x))?
        .unwrap_or(if theses { 0.0 } else { 1.0 });
    let friction_stiffness = t.number("friction_stiffness", "a fraction in (0, 1]", |x| x > 0.0 && x <= 1.0)?;
    let friction = t.number("friction", "a non-negative coefficient", non_negative)?.unwrap_or(0.0);
    let e = "\"none\", \"static\" or \"current\"";
    let friction_cap = match t.string("friction_cap", e, |s| matches!(s, "none" | "static" | "current"))? {
        Some("static") => FrictionCap::Static,
        Some("current") => FrictionCap::Current,
        _ => FrictionCap::None,
    };
    if friction_cap != FrictionCap::None && !physics.plasticity {
        return Err(t.invalid("friction_cap", t.get("friction_cap"), "\"none\": a yield-stress cap needs plasticity"));
    }
    let friction_cap_factor = t.number("friction_cap_factor", "a positive factor", positive)?.unwrap_or(1.0);
    let friction_heating =
        t.number("friction_heating", "a fraction in [0, 1]", |x| (0.0..=1.0).contains(&x))?.unwrap_or(0.0);
    let usui = match t.table("usui", "tool.usui", "a table { psi, xi }")? {
        Some(u) => {
            u.check_keys(&["psi", "xi"], &[], "")?;
            Some([
                u.number("psi", "a positive coefficient in 1/Pa", positive)?.unwrap_or(7.8e-9),
                u.number("xi", "a positive temperature in K", positive)?.unwrap_or(2500.0),
            ])
        }
        None => None,
    };
    Ok(ContactLaw {
        contact_law,
        contact_stiffness,
        contact_damping,
        friction_stiffness,
        friction,
        friction_cap,
        friction_cap_factor,
        friction_heating,
        usui,
    })
}

/// `[tool.thermal]`: the tool as a heat sink of thermal-only particles.
fn tool_thermal(t: &Tab<'_>, doc: &Doc, dx: f64, physics: &Physics, mesh: bool) -> Result<Option<ToolThermal>> {
    let Some(th) = t.table("thermal", "tool.thermal", "a table [tool.thermal] with material")? else {
        return Ok(None);
    };
    th.check_keys(&["material", "temperature", "fixed_width", "lattice"], &[], "")?;
    let lattice_expected = if mesh { "\"cells\" (a mesh tool is filled by cells)" } else { "\"nodes\" or \"cells\"" };
    let material = library_material(&th, doc, "material")?;
    let ok =
        material.thermal.is_some_and(|m| m.density.is_some() && m.specific_heat.is_some() && m.conductivity.is_some());
    if !ok {
        return Err(th.invalid(
            "material",
            th.get("material"),
            "a library material with [thermal] density, specific_heat and conductivity",
        ));
    }
    if physics.conduction == Conduction::Off {
        return Err(th.invalid(
            "material",
            th.get("material"),
            "a scene that conducts heat (physics.conduction): the thermal tool is a heat sink",
        ));
    }
    Ok(Some(ToolThermal {
        material: Some(material),
        temperature: th
            .number("temperature", "a positive temperature in K", positive)?
            .unwrap_or(physics.initial_temperature),
        fixed_width: th.number("fixed_width", "a non-negative width in m", non_negative)?.unwrap_or(2.0 * dx),
        // The nodes are the original code's sampling of its 2D outline's bounding box; a mesh is filled by cells.
        lattice: th
            .named("lattice", lattice_expected, |s| Lattice::parse(s).filter(|l| !mesh || *l == Lattice::Cells))?
            .unwrap_or(Lattice::Cells),
    }))
}

/// `position` and `depth_of_cut`: the edge's lowest point at t = 0, y = top + dx/2 − depth (the uncut surface half a
/// spacing above the top row's centres), or with `row_datum` (`model = "mfree_iwf"`) y = top − depth, the original
/// code's datum (`setup_ref_cut`: the feed measured from the top row's centres).
fn tool_position(
    t: &Tab<'_>,
    dx: f64,
    bodies: &[Body],
    row_datum: bool,
) -> Result<([f64; 2], Option<f64>, Option<usize>)> {
    let depth = t.number("depth_of_cut", "a positive depth in m below the workpiece's uncut surface", positive)?;
    let names = bodies.iter().map(|b| format!("'{}'", b.name)).collect::<Vec<_>>().join(", ");
    let body_expected = format!("the name of the workpiece body depth_of_cut is measured from (one of: {names})");
    let body = match t.string("body", &body_expected, |_| true)? {
        Some(name) => match bodies.iter().position(|b| b.name == name) {
            Some(i) => Some(i),
            None => return Err(t.invalid("body", t.get("body"), body_expected)),
        },
        None => None,
    };
    let Some(depth) = depth else {
        if body.is_some() {
            return Err(t.invalid(
                "body",
                t.get("body"),
                "no body without depth_of_cut (it names the surface the depth is measured from)",
            ));
        }
        let e = format!("{} (or [x] with depth_of_cut)", point_text("the edge's lowest point at t = 0", 2, "m"));
        let p = t.required("position", &e, t.vector("position", 2, &e)?)?;
        return Ok(([p[0], p[1]], None, None));
    };
    if let Some(node @ Node { val: Val::Array(items), .. }) = t.get("position")
        && items.len() == 2
    {
        return Err(t.invalid(
            "position",
            Some(node),
            "[x] only: depth_of_cut places the edge's y (give position = [x, y] or depth_of_cut, not both)",
        ));
    }
    let e = "[x] of the edge's lowest point at t = 0 in m (depth_of_cut places y)";
    let x = t.required("position", e, t.vector("position", 1, e)?)?[0];
    let k = body.unwrap_or(0);
    let b = &bodies[k];
    let top = super::generate::top_row(&b.shape, b.lattice, dx).ok_or_else(|| {
        t.invalid(
            "depth_of_cut",
            t.get("depth_of_cut"),
            format!("a workpiece with particles: body '{}' holds no lattice point at dx = {dx} m", b.name),
        )
    })?;
    // top + (dx/2 − depth), in this order: it rounds V0060's 2.9e-4 + (5e-6 − 1e-4) to exactly the 1.95e-4 the
    // scene gave before depth_of_cut existed, so its runs are unchanged bit for bit.
    let y = if row_datum { top - depth } else { top + (0.5 * dx - depth) };
    Ok(([x, y], Some(depth), body))
}
