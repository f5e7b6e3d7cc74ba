//! The SPH method (roethlin-solver.md): its set-up from a scene (particles, boundary flags, the tool's contact and
//! thermal particles, parameters, grid, Δt, heat and plasticity), its memory estimate, and [`Method`] for the
//! [`Solver`].

use super::{Method, Output, Plan, StateBlobs, ToolSample};
use crate::backend::Backend;
use crate::grid::grid_with_skin;
use crate::kernels::sph::TensorOps;
use crate::kernels::sph::heat::{HeatParams, ThermalMaterial};
use crate::kernels::sph::params::flags;
use crate::kernels::{Real, Vector};
use crate::material::FlowModel;
use crate::scene::{Bc, Conduction, ParticleSet, Precision, Scene, Switch};
use crate::solver::blanking::Blanking;
use crate::solver::diagnostics::compute;
use crate::solver::params::{CspmSettings, StabiliserSettings, Viscosity, cfl_time_step, sph_params};
use crate::solver::{CohesiveSetup, ContactSetup, DamageSetup, PlasticSetup, Solver, ThermalSetup, ToolSetup};
use crate::state::HostParticles;
use crate::tool::{ContactPower, ToolLoad};
use crate::tuning::Tuning;
use crate::{Error, Result};

pub use crate::solver::Setup;

/// The index of prescribed velocity `v` with the reversal times `reverse` in the table the flags point into
/// (`table` and `reversals` side by side), adding it if new.
fn velocity_index(
    table: &mut Vec<[f64; 3]>,
    reversals: &mut Vec<Vec<f64>>,
    v: [f64; 3],
    reverse: &[f64],
    scene: &Scene,
) -> Result<usize> {
    let k = (0..table.len()).find(|&k| table[k] == v && reversals[k] == reverse).unwrap_or_else(|| {
        table.push(v);
        reversals.push(reverse.to_vec());
        table.len() - 1
    });
    if k > flags::VEL_INDEX_MASK as usize {
        return Err(Error::Scene(format!(
            "{}: more than {} distinct prescribed velocities",
            scene.origin,
            flags::VEL_INDEX_MASK + 1
        )));
    }
    Ok(k)
}

/// The particles of a set-up in f64, before they are rounded to the run's precision: the generated bodies, then
/// the tool's thermal-only particles.
struct Initial {
    flags: Vec<u32>,
    pos: Vec<[f64; 3]>,
    vel: Vec<[f64; 3]>,
    mass: Vec<f64>,
    density: Vec<f64>,
    temperature: Vec<f64>,
    /// The prescribed-velocity table the flags point into.
    table: Vec<[f64; 3]>,
    /// Each table entry's reversal times (a boundary's `reverse_at`; empty: constant).
    reversals: Vec<Vec<f64>>,
}

impl Initial {
    /// The generated bodies with their boundary flags.
    fn bodies(scene: &Scene, set: &ParticleSet) -> Result<Initial> {
        let n = set.len();
        let mut table: Vec<[f64; 3]> = Vec::new();
        let mut reversals: Vec<Vec<f64>> = Vec::new();
        let mut fl = Vec::with_capacity(n);
        // The original code holds every mechanically fixed particle at its initial temperature where it has thermal
        // tool constants (`perform_boundary_conditions_thermal` runs only then): with a thermal tool.
        let thermal_tool = scene.tool.as_ref().is_some_and(|t| t.thermal.is_some());
        let hold_fixed = thermal_tool && scene.model.switches().has(Switch::FixedTemperature);
        for i in 0..n {
            let (kind, idx) = match set.bc[i] {
                Bc::Free => (flags::FREE, 0),
                Bc::Fixed => (flags::FIXED, 0),
                Bc::Plane => (flags::PLANE, 0),
                Bc::Velocity(v) => {
                    let reverse = set.bc_source[i].map_or(&[][..], |j| &scene.boundaries[j].reverse_at[..]);
                    (flags::VELOCITY, velocity_index(&mut table, &mut reversals, v, reverse, scene)? as u32)
                }
            };
            let held = set.fixed_temperature[i] || (hold_fixed && kind == flags::FIXED);
            let thermal_fix = if held { flags::FIXED_TEMPERATURE } else { 0 };
            fl.push(kind | thermal_fix | idx << flags::VEL_INDEX_SHIFT | set.body[i] << flags::BODY_SHIFT);
        }
        Ok(Initial {
            flags: fl,
            pos: set.pos.clone(),
            vel: set.vel.clone(),
            mass: vec![set.mass; n],
            density: vec![scene.material.density; n],
            temperature: set.temperature.clone(),
            table,
            reversals,
        })
    }

    /// The tools: their contact set-up, and the (lone) tool's thermal-only particles appended as one more body
    /// (with their thermal material).
    fn tool(&mut self, scene: &Scene, set: &ParticleSet) -> Result<(Option<ContactSetup>, Option<ThermalMaterial>)> {
        let Some(t) = &scene.tool else { return Ok((None, None)) };
        let m = &scene.material;
        let model = flow_model(scene);
        let several = !scene.more_tools.is_empty();
        let mut tools = Vec::new();
        for (k, t) in scene.tools().enumerate() {
            let key = if several { format!("tool.{k}") } else { "tool".to_string() };
            let shape = crate::tool::setup::shape(t)?;
            let motion = crate::tool::setup::motion(t);
            crate::tool::setup::check_engagement(scene, &key, &shape, &motion, &set.pos, &set.vel)?;
            tools.push(ToolSetup {
                params: crate::tool::setup::contact_params(scene, t, model.as_ref()),
                shape,
                motion,
            });
        }
        let (tool, motion) = (&tools[0].shape, tools[0].motion);
        let mut tool_velocity_index = None;
        let mut tool_thermal = None;
        if let Some(th) = &t.thermal
            && let Some(mat) = th.material.as_ref().and_then(|m| m.thermal)
        {
            let dx = scene.discretisation.dx;
            let tp = crate::tool::setup::thermal_particles(tool, t, dx, th.fixed_width);
            let v0 = motion.velocity_at(0.0);
            let v = t.velocity;
            let k = velocity_index(&mut self.table, &mut self.reversals, v, &[], scene)?;
            tool_velocity_index = (t.ramp > 0.0).then_some(k);
            let body = scene.bodies.len() as u32;
            let rho_t = mat.density.unwrap_or(m.density);
            // The original code's conduction takes every neighbour's volume as the workpiece's particle mass over
            // its density (roethlin-solver.md §5.6): the tool particles' mass is the workpiece's then.
            let c2d = scene.model.switches().has(Switch::C2dConduction);
            let tool_mass = if c2d { m.density * set.volume } else { rho_t * set.volume };
            for (p, held) in tp.pos.iter().zip(&tp.held) {
                let hold = if *held { flags::FIXED_TEMPERATURE } else { 0 };
                self.flags.push(
                    flags::VELOCITY
                        | flags::THERMAL_ONLY
                        | hold
                        | (k as u32) << flags::VEL_INDEX_SHIFT
                        | body << flags::BODY_SHIFT,
                );
                self.pos.push(*p);
                self.vel.push(v0);
                self.mass.push(tool_mass);
                self.density.push(rho_t);
                self.temperature.push(th.temperature);
            }
            tool_thermal = Some(ThermalMaterial {
                conductivity: mat.conductivity.unwrap_or(0.0),
                specific_heat: mat.specific_heat.unwrap_or(1.0),
            });
        }
        let wear = scene.tools().any(|t| t.usui.is_some());
        let contact = ContactSetup { tools, tool_velocity_index, wear };
        Ok((Some(contact), tool_thermal))
    }
}

/// The scene material's flow-stress model as the run uses it: with the Uintah low-rate form under the original
/// model's `uintah_rate` switch.
fn flow_model(scene: &Scene) -> Option<FlowModel> {
    let model = scene.material.library.as_ref().and_then(|l| l.flow_stress)?;
    Some(if scene.model.switches().has(Switch::UintahRate) { model.with_uintah_rate() } else { model })
}

/// Builds the particles, parameters, grid and time step of `scene`, with the process's tuning switches
/// ([`Tuning::current`]).
pub fn setup<R: Real, D: TensorOps<R>>(scene: &Scene) -> Result<Setup<R, D>> {
    setup_with(scene, Tuning::current()?)
}

/// Builds the particles, parameters, grid and time step of `scene`, with the tuning switches `tuning`.
pub fn setup_with<R: Real, D: TensorOps<R>>(scene: &Scene, tuning: &Tuning) -> Result<Setup<R, D>> {
    let set = scene.generate().map_err(|e| Error::Scene(e.to_string()))?;
    let mut warnings = crate::scene::degenerate_input_warnings(scene, &set);
    let mut init = Initial::bodies(scene, &set)?;
    let (contact, tool_thermal) = init.tool(scene, &set)?;
    let conv = |c: &[f64; 3]| D::Vec::<R>::new(std::array::from_fn(|k| R::from_f64(c[k])));
    let Initial { flags: mut fl, pos, vel, mass, density, temperature, table, reversals } = init;
    let mut cohesive = cohesive_setup(scene, &mut fl, &pos)?;
    let n = pos.len();
    // The mixed precision keeps each coordinate as a pair hi + lo in R: lo is what rounding it to R dropped.
    // f32's only: the f64 corrector has no compensated sum (`sph::step::correct_particle`).
    let pos_lo = (scene.precision == Precision::Mixed && size_of::<R>() == 4).then(|| {
        let lo =
            |c: &[f64; 3]| D::Vec::<R>::new(std::array::from_fn(|k| R::from_f64(c[k] - R::from_f64(c[k]).to_f64())));
        pos.iter().map(lo).collect()
    });
    let particles = HostParticles::<R, D> {
        id: (0..n as u32).collect(),
        flags: fl,
        pos: pos.iter().map(conv).collect(),
        vel: vel.iter().map(conv).collect(),
        mass: mass.iter().map(|&x| R::from_f64(x)).collect(),
        rho: density.iter().map(|&x| R::from_f64(x)).collect(),
        stress: vec![Default::default(); n],
    };
    let st = &scene.stabilisation;
    let stabilisers = StabiliserSettings {
        viscosity: st.artificial_viscosity.as_ref().map(|a| Viscosity {
            alpha: a.alpha,
            beta: a.beta,
            eta: a.eta,
            balsara: a.switch == crate::scene::ViscositySwitch::Balsara,
        }),
        stress: st.artificial_stress.as_ref().map(|a| (a.epsilon, a.exponent)),
        xsph: st.xsph.as_ref().map(|x| x.epsilon),
        cspm: st.cspm.as_ref().map(|c| CspmSettings { min_det: c.min_determinant, path_only: c.path_only }),
    };
    let elastic = scene.material.elastic();
    let dx = scene.discretisation.dx;
    let h = scene.h();
    let mut params = sph_params::<R>(&elastic, dx, h, scene.dim, &stabilisers);
    params.expansion = R::from_f64(scene.physics.volumetric_expansion());
    params.expansion_t0 = R::from_f64(scene.physics.expansion_reference);
    let switches = scene.model.switches();
    if switches.has(Switch::KernelW6) {
        params.model_flags |= crate::kernels::sph::params::model::C2D_KERNEL_W;
    }
    if scene.damage.as_ref().is_some_and(|d| d.mask && d.mask_printed) {
        params.model_flags |= crate::kernels::sph::params::model::MASK_PRINTED;
    }
    if switches.has(Switch::AbsCutoff) {
        params.min_r2 = R::from_f64(code_units(scene).cutoff_squared());
    }
    let grid = grid(scene, &pos, contact.as_ref(), h)?;
    let c0 = elastic.sound_speed();
    let dt = time_step(scene, h, c0, &vel)?;
    let dt = bonded_step(scene, dt, cohesive.as_mut(), &mass, &mut warnings);
    // The PIC-damping analogue's α = (1 − β)/Δt (nairn-mpm.md §7.2, Eq. 8).
    params.pic_alpha = R::from_f64(st.xsph.as_ref().map_or(0.0, |x| x.pic / dt));
    let thermal = thermal(scene, h, tool_thermal);
    let ph = &scene.physics;
    let plastic = match (ph.plasticity, flow_model(scene)) {
        (true, Some(model)) => {
            use crate::kernels::sph::plastic::return_flags::{C2D_NORM, C2D_RETURN};
            let return_flags = if switches.has(Switch::C2dReturn) { C2D_RETURN } else { 0 }
                | if switches.has(Switch::C2dNorm) { C2D_NORM } else { 0 };
            Some(PlasticSetup {
                model,
                taylor_quinney: if ph.plastic_heating { ph.taylor_quinney } else { 0.0 },
                return_flags,
            })
        }
        _ => None,
    };
    let damage = damage_setup(scene, &particles.flags, &pos);
    let expands = ph.thermal_expansion > 0.0;
    let temperature = if thermal.is_some() || plastic.is_some() || expands { Some(temperature) } else { None };
    let blanking = blanking(scene, &grid, h, &pos)?;
    Ok(Setup {
        particles,
        pos_lo,
        params,
        stabilisers,
        bc_velocities: table.iter().map(conv).collect(),
        bc_reversals: reversals,
        grid,
        dt,
        c0,
        h,
        shear: elastic.shear_modulus(),
        temperature,
        thermal,
        plastic,
        damage,
        cohesive,
        contact,
        blanking,
        warnings,
        tuning: tuning.clone(),
    })
}

/// The run's blanking (None without `[blanking]`): the scene's box, jumping by the cell list's skin (h where the
/// list has none). A box that holds no particle at t = 0 is refused.
fn blanking(
    scene: &Scene,
    grid: &crate::kernels::neighbour::GridParams,
    h: f64,
    pos: &[[f64; 3]],
) -> Result<Option<Blanking>> {
    let Some(b) = scene.blanking else { return Ok(None) };
    let bl = Blanking { scene: b, step: if grid.skin > 0.0 { grid.skin } else { h } };
    let first = bl.box_at(0.0);
    // 2D positions and boxes have z = 0; where the box is, whatever the speeds.
    use crate::kernels::vector::V3f64;
    let rest = V3f64::new([0.0; 3]);
    if pos.iter().all(|p| first.blanks::<f64, V3f64>(&V3f64::new(*p), &rest)) {
        return Err(Error::Scene(format!(
            "{}: blanking.min, blanking.max: the box holds no particle at t = 0; expected a box around the tool's \
             path that holds part of the workpiece",
            scene.origin
        )));
    }
    Ok(Some(bl))
}

/// The cohesive path of `scene` (None without `[cohesive]`; docs/mpm.md "The cohesive path in SPH"). Each
/// mechanical particle whose x lies within the extent takes the side flag of its side of the plane; each particle
/// of the first row above the plane, outside the traction-free starter, owns a bond to the particle of the first
/// row below that faces it (the same x, and z in 3D, within a quarter spacing), of tributary area Δx (2D, per
/// unit depth) or Δx² (3D). A particle on the plane, or an extent with no facing pair, is refused.
fn cohesive_setup(scene: &Scene, fl: &mut [u32], pos: &[[f64; 3]]) -> Result<Option<CohesiveSetup>> {
    use crate::kernels::cohesive::{Cohesive, TractionLaw};
    use crate::kernels::sph::bond::{BondParams, NONE};
    let Some(c) = scene.cohesive.as_ref() else { return Ok(None) };
    let dx = scene.discretisation.dx;
    let bad = |key: &str, what: String| Error::Scene(format!("{}: cohesive.{key}: {what}", scene.origin));
    let on_path: Vec<usize> = (0..pos.len())
        .filter(|&i| fl[i] & flags::THERMAL_ONLY == 0 && (c.extent[0]..=c.extent[1]).contains(&pos[i][0]))
        .collect();
    let (mut above, mut below) = (Vec::new(), Vec::new());
    for &i in &on_path {
        let d = pos[i][1] - c.plane;
        if d.abs() < 1e-6 * dx {
            let e = format!("particle {i} lies on the plane y = {}; expected a y between two particle rows", c.plane);
            return Err(bad("plane", e));
        }
        fl[i] |= if d > 0.0 { flags::SIDE_ABOVE } else { flags::SIDE_BELOW };
        if d > 0.0 {
            above.push(i)
        } else {
            below.push(i)
        };
    }
    let gap = |v: &[usize]| v.iter().map(|&i| (pos[i][1] - c.plane).abs()).fold(f64::INFINITY, f64::min);
    let (ga, gb) = (gap(&above), gap(&below));
    let first = |v: &[usize], g: f64| -> Vec<usize> {
        v.iter().copied().filter(|&i| (pos[i][1] - c.plane).abs() < g + 0.25 * dx).collect()
    };
    let mut row_below = first(&below, gb);
    row_below.sort_by(|&a, &b| pos[a][0].total_cmp(&pos[b][0]));
    let free = |x: f64| c.traction_free.is_some_and(|[a, b]| (a..=b).contains(&x));
    let n = pos.len();
    let (mut partner, mut reference) = (vec![NONE; n], vec![[0.0; 3]; n]);
    let mut facing_pairs = 0usize;
    for i in first(&above, ga) {
        let start = row_below.partition_point(|&j| pos[j][0] < pos[i][0] - 0.25 * dx);
        let facing = row_below[start..]
            .iter()
            .take_while(|&&j| pos[j][0] <= pos[i][0] + 0.25 * dx)
            .find(|&&j| (pos[j][2] - pos[i][2]).abs() <= 0.25 * dx);
        if let Some(&j) = facing {
            facing_pairs += 1;
            if !free(pos[i][0]) {
                partner[i] = j as u32;
                reference[i] = std::array::from_fn(|k| pos[i][k] - pos[j][k]);
            }
        }
    }
    if facing_pairs == 0 {
        let e = "no particle pairs face each other across the plane; expected an extent over a body the plane cuts";
        return Err(bad("extent", e.to_string()));
    }
    let column = open_sides(scene, c, fl, pos, &partner, &on_path);
    let l = &c.law;
    let law = Cohesive {
        mode1: TractionLaw::of_toughness(l.law.kernel(), l.toughness, l.peak),
        mode2: TractionLaw::of_toughness(l.law.kernel(), l.toughness_shear, l.peak_shear),
    };
    // The damper's time step is the run's, set once it is known.
    let params = BondParams { law, area: scene.bond_area(), dt: 0.0, coupling: c.coupling as u32, _pad: 0 };
    Ok(Some(CohesiveSetup { params, partner, reference, column }))
}

/// The open flags (`flags::OPEN`) of the path's sided particles `on_path`, and the column of each under
/// `coupling = "continuum"` (docs/mpm.md "Continuum until onset"). Under `"bonds"` every sided particle is open
/// from the start (no column). Under `"continuum"` a particle within the kernel's support 2h of the plane and
/// outside the starter belongs to the column of the bond owner nearest it in x (and z in 3D) within a spacing, and
/// opens with that bond's onset; the starter's particles, those farther from the plane (which no particle across
/// reaches unless the cut brings them together) and those of no column are open from the start.
fn open_sides(
    scene: &Scene,
    c: &crate::scene::CohesivePath,
    fl: &mut [u32],
    pos: &[[f64; 3]],
    partner: &[u32],
    on_path: &[usize],
) -> Vec<u32> {
    use crate::kernels::sph::bond::NONE;
    use crate::scene::Coupling;
    let mut column = vec![NONE; pos.len()];
    if c.coupling == Coupling::Bonds {
        on_path.iter().for_each(|&i| fl[i] |= flags::OPEN);
        return column;
    }
    let dx = scene.discretisation.dx;
    let mut owners: Vec<usize> = (0..partner.len()).filter(|&i| partner[i] != NONE).collect();
    owners.sort_by(|&a, &b| pos[a][0].total_cmp(&pos[b][0]));
    let free = |x: f64| c.traction_free.is_some_and(|[a, b]| (a..=b).contains(&x));
    for &i in on_path {
        let near = (pos[i][1] - c.plane).abs() < 2.0 * scene.h() && !free(pos[i][0]);
        let owner = near.then(|| {
            let start = owners.partition_point(|&o| pos[o][0] < pos[i][0] - 0.5 * dx);
            owners[start..]
                .iter()
                .take_while(|&&o| pos[o][0] <= pos[i][0] + 0.5 * dx)
                .filter(|&&o| (pos[o][2] - pos[i][2]).abs() <= 0.5 * dx)
                .min_by(|&&a, &&b| {
                    let d = |o: usize| (pos[o][0] - pos[i][0]).hypot(pos[o][2] - pos[i][2]);
                    d(a).total_cmp(&d(b))
                })
        });
        match owner.flatten() {
            Some(&o) => column[i] = o as u32,
            None => fl[i] |= flags::OPEN,
        }
    }
    column
}

/// The run's step `dt` shortened where the cohesive path's bonds need it ([`bond_step`], with a warning), and given
/// to the bonds' dampers.
fn bonded_step(
    scene: &Scene,
    dt: f64,
    cohesive: Option<&mut CohesiveSetup>,
    mass: &[f64],
    warnings: &mut Vec<String>,
) -> f64 {
    let Some(c) = cohesive else { return dt };
    let bond_dt = bond_step(c, mass);
    let dt = if bond_dt < dt {
        warnings.push(format!(
            "{}: the cohesive path's bonds shorten the time step from {dt:.4e} s to {bond_dt:.4e} s (ωΔt ≤ {})",
            scene.origin,
            crate::kernels::sph::bond::MAX_OMEGA_DT
        ));
        bond_dt
    } else {
        dt
    };
    c.params.dt = dt;
    dt
}

/// The longest step the cohesive path's bonds allow: ωΔt ≤ `bond::MAX_OMEGA_DT` for every bond, ω = √(k/m_r) with
/// k the stiffer mode's initial stiffness times the area and m_r the reduced mass of its particles.
fn bond_step(c: &CohesiveSetup, mass: &[f64]) -> f64 {
    use crate::kernels::sph::bond::{MAX_OMEGA_DT, NONE};
    let law = &c.params.law;
    let k = law.mode1.stiffness::<f64>().max(law.mode2.stiffness::<f64>()) * c.params.area;
    let lightest = (0..c.partner.len())
        .filter(|&i| c.partner[i] != NONE)
        .map(|i| {
            let (mi, mj) = (mass[i], mass[c.partner[i] as usize]);
            mi * mj / (mi + mj)
        })
        .fold(f64::INFINITY, f64::min);
    MAX_OMEGA_DT * (lightest / k).sqrt()
}

/// The damage of `scene` (None without `[damage]`): its constants for the kernels (`kernels::damage`) and the
/// initial ω and D of every particle (`flags`, `pos` in the set-up's order), the pre-cracks' boxes applied in
/// order to the mechanical particles (the last box containing a particle wins).
fn damage_setup(scene: &Scene, fl: &[u32], pos: &[[f64; 3]]) -> Option<DamageSetup> {
    use crate::kernels::damage::{DamageParams, model, switches};
    let d = scene.damage.as_ref()?;
    let elastic = scene.material.elastic();
    let params = DamageParams {
        model: match d.model.as_str() {
            "jc_gg" => model::JC_GG,
            "rice_tracey" => model::RICE_TRACEY,
            _ => model::JC,
        },
        flags: if d.mask { switches::MASK } else { 0 } | if d.delete { switches::DELETE } else { 0 },
        d: d.constants,
        ref_rate: d.reference_strain_rate,
        ref_temp: d.reference_temperature,
        melt_temp: d.melt_temperature,
        fracture_energy: d.fracture_energy,
        c0sq: elastic.bulk_modulus() / elastic.density,
        rho0: elastic.density,
        // The same ρ0(T) as the EOS's (`SphParams::expansion`).
        expansion: scene.physics.volumetric_expansion(),
        expansion_t0: scene.physics.expansion_reference,
        dim: scene.dim as f64,
        bulk: elastic.bulk_modulus(),
    };
    let n = pos.len();
    let (mut omega, mut damage) = (vec![0.0; n], vec![0.0; n]);
    for (i, p) in pos.iter().enumerate() {
        if fl[i] & flags::THERMAL_ONLY != 0 {
            continue;
        }
        for c in &d.pre_cracks {
            if (0..scene.dim).all(|k| p[k] >= c.min[k] && p[k] <= c.max[k]) {
                (omega[i], damage[i]) = (c.omega, c.damage);
            }
        }
    }
    Some(DamageSetup { params, omega, damage })
}

/// A fixed ("locked") grid over the initial bodies with room to move; particles leaving it are clamped into its
/// boundary cells, which keeps the search exact (docs/neighbour-search.md).
fn grid(
    scene: &Scene,
    pos: &[[f64; 3]],
    contact: Option<&ContactSetup>,
    h: f64,
) -> Result<crate::kernels::neighbour::GridParams> {
    let mut corners: Vec<crate::kernels::vector::V3f64> =
        pos.iter().map(|p| crate::kernels::vector::V3f64([p[0], p[1], p[2], 0.0])).collect();
    let tools = scene.tools().zip(contact.map_or(&[][..], |c| &c.tools[..]));
    for (t, c) in tools {
        // The tool's path, and room above the workpiece for the chip (a tool height): cutting runs keep their
        // particles inside the grid instead of clamping the chip into boundary cells.
        let end = c.motion.offset_at(scene.time.end);
        let top = pos.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
        match &t.mesh {
            // A mesh tool: its vertices' bounding box at the start and the end of the path (a rotating tool's
            // sweep is not followed: particles beyond the grid are clamped into its boundary cells, still exact).
            Some(m) => {
                for o in [c.motion.start, end] {
                    for v in m.grid.verts.iter().step_by(3) {
                        corners.push(crate::kernels::vector::V3f64([o[0] + v[0], o[1] + v[1], o[2] + v[2], 0.0]));
                    }
                }
            }
            None => {
                for o in [c.motion.start, end] {
                    corners.push(crate::kernels::vector::V3f64([o[0] - t.length, o[1], 0.0, 0.0]));
                    corners.push(crate::kernels::vector::V3f64([o[0], o[1] + t.height, 0.0, 0.0]));
                }
                corners.push(crate::kernels::vector::V3f64([end[0], top + t.height, 0.0, 0.0]));
            }
        }
    }
    let (lo, hi) = crate::grid::bounding_box::<f64, _>(&corners);
    let mut glo = [0.0; 3];
    let mut ghi = [0.0; 3];
    for k in 0..scene.dim {
        let margin = 0.25 * (hi[k] - lo[k]) + 4.0 * h;
        glo[k] = lo[k] - margin;
        ghi[k] = hi[k] + margin;
    }
    let mut grid = grid_with_skin(glo, ghi, scene.dim, 2.0 * h, scene.discretisation.skin_over_h * h)?;
    if let Some(period) = scene.discretisation.period_z {
        grid = crate::grid::periodic_z(&grid, ghi, period)
            .map_err(|e| Error::Scene(format!("{}: discretisation.period_z: {e}", scene.origin)))?;
    }
    if scene.discretisation.verlet_list {
        grid.list_capacity = crate::neighbour::verlet_capacity(&grid, scene.discretisation.dx);
        grid.list_wide =
            crate::neighbour::wide_offsets(scene.discretisation.verlet_offsets, scene.dim, pos.len()) as u32;
    }
    Ok(grid)
}

/// The original code's units for the scene (`scene::model::CodeUnits`: its cut's cm and µs with a tool).
fn code_units(scene: &Scene) -> crate::scene::model::CodeUnits {
    crate::scene::model::CodeUnits::of(scene.tool.is_some())
}

/// The run's Δt: the scene's `time.dt` if it is stable, else the stability limit: the CFL step, and with
/// conduction 0.1 h² ρ c / k (Cleary & Monaghan's bound for the Brookshaw form; PSE is no less restrictive) over
/// the largest diffusivity of the scene's bodies and the tool.
///
/// The CFL step is CFL h/(c0 + |v|max) over the initial velocities (roethlin-solver.md (7.1)); under the original
/// model's `sqrt_v_dt` switch it is the original code's CFL h/(c0 + √v) (**a bug**, erratum 13: the root of a
/// speed), v the tool's speed (with a tool; else |v|max, as its rings and impact set-ups), its root taken in the
/// code's units (cm/µs for the cut: √v [cm/µs] = 100 √v [m/s] in m/s; SI otherwise).
fn time_step(scene: &Scene, h: f64, c0: f64, vel: &[[f64; 3]]) -> Result<f64> {
    let m = &scene.material;
    let vmax0 = vel.iter().map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()).fold(0.0, f64::max);
    let mut limit = if scene.model.switches().has(Switch::SqrtVDt) {
        let v = scene.tool.as_ref().map_or(vmax0, |t| t.velocity[0].hypot(t.velocity[1]));
        scene.time.cfl * h / (c0 + code_units(scene).sqrt_speed(v))
    } else {
        cfl_time_step(scene.time.cfl, h, c0, vmax0)
    };
    if scene.physics.conduction != Conduction::Off {
        let lib_th = m.library.as_ref().and_then(|l| l.thermal);
        for bd in &scene.bodies {
            let t = bd.material.as_ref().and_then(|l| l.thermal).or(lib_th);
            if let (Some(k), Some(c)) = (t.and_then(|t| t.conductivity), t.and_then(|t| t.specific_heat)) {
                limit = limit.min(0.1 * h * h * m.density * c / k);
            }
        }
        if let Some(tm) = scene.tool.as_ref().and_then(|t| t.thermal.as_ref()).and_then(|t| t.material.as_ref())
            && let Some(t) = tm.thermal
            && let (Some(rho), Some(c), Some(k)) = (t.density, t.specific_heat, t.conductivity)
        {
            limit = limit.min(0.1 * h * h * rho * c / k);
        }
    }
    match scene.time.dt {
        Some(dt) if dt > limit => Err(Error::Scene(format!(
            "{}: time.dt = {dt:e} s is above the stability limit {limit:e} s (cfl {} · h {h:e} m / (c0 {c0:.1} m/s + |v|max {vmax0:.1} m/s), and 0.1 h² ρ c / k with conduction)",
            scene.origin, scene.time.cfl
        ))),
        Some(dt) => Ok(dt),
        None => Ok(limit),
    }
}

/// Heat, from `[physics]` and the library material (scene validation already checked that the data it needs
/// exist): each body's thermal data (its own library material if it names one, else the scene material's), then
/// the tool's.
fn thermal(scene: &Scene, h: f64, tool_thermal: Option<ThermalMaterial>) -> Option<ThermalSetup> {
    let ph = &scene.physics;
    let th = scene.material.library.as_ref().and_then(|l| l.thermal);
    let friction_heat = scene.tool.as_ref().is_some_and(|t| t.friction_heating > 0.0);
    let needs_heat = ph.conduction != Conduction::Off || ph.plastic_heating || friction_heat;
    if !needs_heat {
        return None;
    }
    let mut materials: Vec<ThermalMaterial> = scene
        .bodies
        .iter()
        .map(|bd| {
            let t = bd.material.as_ref().and_then(|m| m.thermal).or(th);
            ThermalMaterial {
                conductivity: t.and_then(|t| t.conductivity).unwrap_or(0.0),
                specific_heat: t.and_then(|t| t.specific_heat).unwrap_or(1.0),
            }
        })
        .collect();
    materials.extend(tool_thermal);
    let mut heat = HeatParams::new(h, scene.dim);
    let switches = scene.model.switches();
    if switches.has(Switch::AbsCutoff) {
        heat.min_r2 = code_units(scene).cutoff_squared();
    }
    if switches.has(Switch::C2dConduction) {
        heat.flags |= crate::kernels::sph::heat::heat_flags::C2D;
        heat.rho0 = scene.material.density;
    }
    Some(ThermalSetup {
        materials,
        conduction: match ph.conduction {
            Conduction::Off => None,
            Conduction::Brookshaw => Some(false),
            Conduction::Pse => Some(true),
        },
        heat,
    })
}

/// Bytes the solver allocates: every per-particle buffer of the field registry (`solver::fields::FIELDS`, spares
/// included) and the buffers that are not per particle (cell starts, scan workspace, Verlet list, parameter
/// blocks); equal to what the backend allocates (tests/fields.rs).
pub fn memory_estimate<R: Real, D: TensorOps<R>>(s: &crate::solver::Setup<R, D>) -> usize {
    crate::solver::fields::memory_bytes(s)
}

/// The f64 positions of `p` (as `analysis::positions_f64`).
fn positions_f64<R: Real, V: Vector<R>>(pos: &[V]) -> Vec<[f64; 3]> {
    pos.iter().map(|p| std::array::from_fn(|k| p.get(k).to_f64())).collect()
}

/// The f64 positions of `p` (z = 0 in 2D).
fn widened<R: Real, D: TensorOps<R>>(p: &[D::Vec<R>]) -> Vec<[f64; 3]> {
    p.iter().map(|x| std::array::from_fn(|k| if k < D::D { x.get(k).to_f64() } else { 0.0 })).collect()
}

impl<B: Backend, R: Real, D: TensorOps<R>> Method<B> for Solver<B, R, D> {
    type R = R;
    type D = D;
    type Setup = Setup<R, D>;

    fn setup(scene: &Scene, tuning: &Tuning) -> Result<Setup<R, D>> {
        setup_with(scene, tuning)
    }

    fn plan(s: &Setup<R, D>) -> Plan {
        let host = &s.particles;
        let p = positions_f64(&host.pos);
        // Every particle's position at t = 0 by id, for the contact distance of the diagnostics.
        let mut initial = vec![[0.0; 3]; p.len()];
        for (k, &id) in host.id.iter().enumerate() {
            if let Some(slot) = initial.get_mut(id as usize) {
                *slot = p[k];
            }
        }
        let workpiece = widened::<R, D>(&host.pos)
            .into_iter()
            .zip(&host.flags)
            .filter(|(_, f)| **f & flags::THERMAL_ONLY == 0)
            .map(|(x, _)| x)
            .collect();
        Plan {
            particles: host.len(),
            dt: s.dt,
            h: s.h,
            c0: s.c0,
            precision: s.precision(),
            memory_bytes: memory_estimate(s),
            temperature: s.temperature.is_some(),
            warnings: s.warnings.clone(),
            initial,
            workpiece,
        }
    }

    fn new(b: &B, s: &Setup<R, D>) -> Result<Self> {
        Solver::new(b, s)
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn set_clock(&mut self, time: f64, steps: u64) {
        self.time = time;
        self.steps = steps;
    }

    fn particles(&self) -> usize {
        self.n
    }

    fn precision(&self) -> &'static str {
        Solver::precision(self)
    }

    fn set_nominal_dt(&mut self, dt: f64) {
        Solver::set_nominal_dt(self, dt);
    }

    fn step(&mut self, b: &B, dt: f64) -> Result<()> {
        Solver::step(self, b, dt)
    }

    fn advance(&mut self, b: &B, dt: f64, count: usize) -> Result<()> {
        Solver::advance(self, b, dt, count)
    }

    fn non_finite_seen(&self, b: &B) -> Result<bool> {
        Solver::non_finite_seen(self, b)
    }

    fn rebuilds(&self, b: &B) -> Result<u32> {
        self.cell_rebuilds(b)
    }

    fn output(&self, b: &B) -> Result<Output<R, D>> {
        let host = self.download(b)?;
        // The registry's frame fields are the internal variables: read once, used for both.
        let mut fields = self.download_frame_fields(b)?;
        if self.cells.blanking() {
            // The frozen particles, sorted after the active ones.
            let active = self.cells.active_count(b)?;
            let values = (0..host.len()).map(|i| if i < active { 0.0 } else { 1.0 }).collect();
            fields.push(crate::solver::fields::FrameField { name: "blanked", components: 1, values });
        }
        let field = |name: &str| fields.iter().find(|f| f.name == name).map(|f| f.values.clone());
        let (temp, eps, rate) = (field("temperature"), field("plastic_strain"), field("plastic_strain_rate"));
        let (omega, damage) = (field("damage_initiation"), field("damage"));
        let mut d = compute(&host, &self.host_params, self.time, self.steps, temp.as_deref(), damage.as_deref());
        crate::solver::diagnostics::internal(&mut d, &host.id, temp.as_deref(), eps.as_deref());
        crate::solver::diagnostics::dissipated(&mut d, &host, &self.download_dissipated(b)?);
        crate::solver::diagnostics::damaged(&mut d, &host, omega.as_deref(), damage.as_deref());
        crate::solver::diagnostics::cohesive(&mut d, self.bond_tally(b)?.as_ref());
        let mut now = positions_f64(&host.pos);
        // The mixed precision's positions are hi + lo: the observers and the displacements see them whole.
        if let Some(lo) = self.download_pos_lo(b)? {
            for (x, l) in now.iter_mut().zip(positions_f64(&lo)) {
                for (c, d) in x.iter_mut().zip(l) {
                    *c += d;
                }
            }
        }
        Ok(Output {
            diagnostics: d,
            host,
            internal: [temp, eps, rate],
            fields,
            positions: now,
            tools: self.tool_pictures(),
            params: self.host_params,
        })
    }

    fn tool_sample(&self, b: &B) -> Result<Option<ToolSample>> {
        if self.tool_state().is_none() {
            return Ok(None);
        }
        let (pos, fl) = self.positions(b)?;
        let samples = self.contact_samples_at(b, &pos)?;
        let Some(c) = samples.first() else { return Ok(None) };
        let workpiece = pos
            .iter()
            .zip(&fl)
            .filter(|(_, f)| **f & flags::THERMAL_ONLY == 0)
            .map(|(p, _)| [p.get(0).to_f64(), p.get(1).to_f64()])
            .collect();
        Ok(Some(ToolSample {
            time: self.time,
            steps: self.steps,
            force: c.force,
            moment: c.moment,
            contacts: c.contacts,
            wear_rate: c.wear_rate,
            friction_ratio: c.friction_ratio,
            power: samples.iter().fold(ContactPower::default(), |a, s| a.plus(s.power)),
            offset: self.tool_offset().unwrap_or([0.0; 3]),
            more: samples[1..]
                .iter()
                .map(|s| ToolLoad { force: s.force, moment: s.moment, contacts: s.contacts, wear_rate: s.wear_rate })
                .collect(),
            workpiece,
        }))
    }

    fn save_state(&self, b: &B) -> Result<StateBlobs> {
        Solver::save_state(self, b)
    }

    fn load_state(&mut self, b: &B, state: &StateBlobs) -> Result<()> {
        Solver::load_state(self, b, state)
    }
}
