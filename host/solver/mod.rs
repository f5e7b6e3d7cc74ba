//! The SPH solver loop, written once against [`Backend`]. One step (roethlin-solver.md §5.2, reordered so that
//! the neighbour search is exact at the positions where the rates are evaluated):
//!
//! 1. predictor: y0 ← y, y ← y0 + ½Δt ẏ (ẏ from the previous step's midpoint; zero at the first step);
//! 2. cell list on the predicted positions; reorder y, y0 and the per-particle constants (mass, id, flags);
//! 3. pre-pass: σ/ρ², artificial stress, sound speed (the last two only when their stabiliser is on);
//! 4. pair interaction: ẏ at the midpoint, with the boundary conditions imposed on the rates;
//! 5. corrector: y ← y0 + Δt ẏ;
//! 6. plasticity (if on): radial return of S with ε̄, ε̄̇, T and plastic heating (operator split, §5.2 step 13).
//!
//! With heat conduction on, T joins x, v, ρ, S in the predictor–corrector and its rate comes from the conduction
//! pass after the interaction. Temperature, ε̄ and ε̄̇ are f64 in every precision; they exist only when the scene
//! models plasticity or heat.
//!
//! The rates are not reordered: the predictor consumes them in the order the corrector left, and the interaction
//! rewrites them. Buffers of a stabiliser that is off are not allocated.

pub mod diagnostics;
pub mod params;

pub use crate::cutting::motion::ToolMotion;

use crate::Result;
use crate::backend::{Backend, ContactInputs, FieldsMut, FieldsRef, SphInputs};
use crate::kernels::contact::{ContactParams, ToolState, penalty::cap};
use crate::kernels::neighbour::GridParams;
use crate::kernels::sph::heat::{HeatParams, ThermalMaterial};
use crate::kernels::sph::params::flags;
use crate::kernels::sph::plastic::PlasticConsts;
use crate::kernels::sph::{SphParams, Stabilisers, TensorOps};
use crate::kernels::{Dim, Real, Vector};
use crate::material::FlowModel;
use crate::neighbour::CellList;
use crate::state::{Field, HostParticles, Particles};

/// Heat physics of a run.
#[derive(Clone, Debug)]
pub struct ThermalSetup {
    /// Thermal constants by body index.
    pub materials: Vec<ThermalMaterial>,
    /// Conduction: None (off), Some(false) Brookshaw, Some(true) PSE.
    pub conduction: Option<bool>,
    pub heat: HeatParams,
}

/// Plasticity of a run.
#[derive(Clone, Debug)]
pub struct PlasticSetup {
    pub model: FlowModel,
    /// Taylor–Quinney coefficient (0: no plastic heating).
    pub taylor_quinney: f64,
}

/// The rigid tool of a cutting run (2D).
#[derive(Clone, Debug)]
pub struct ContactSetup {
    pub params: ContactParams,
    pub motion: ToolMotion,
    /// Index of the tool particles' velocity in the prescribed-velocity table (rewritten during a start-up ramp).
    pub tool_velocity_index: Option<usize>,
    /// Record the Usui wear rate.
    pub wear: bool,
}

/// Everything a solver needs, in the run's precision (built from a scene by `run::setup`).
pub struct Setup<R: Real, D: TensorOps<R>> {
    pub particles: HostParticles<R, D>,
    pub params: SphParams<R>,
    pub stabilisers: params::StabiliserSettings,
    pub bc_velocities: Vec<D::Vec<R>>,
    pub grid: GridParams,
    pub dt: f64,
    pub c0: f64,
    pub h: f64,
    /// Shear modulus G [Pa] (f64 for the return map).
    pub shear: f64,
    /// Initial temperature of each particle; present when the run models heat or plasticity.
    pub temperature: Option<Vec<f64>>,
    pub thermal: Option<ThermalSetup>,
    pub plastic: Option<PlasticSetup>,
    pub contact: Option<ContactSetup>,
    /// Input that runs but whose result is not meaningful (`scene::degenerate_input_warnings`).
    pub warnings: Vec<String>,
}

struct ThermalState<B: Backend> {
    temp0: Option<Field<B, f64>>,
    temp_t: Option<B::Buf<f64>>,
    materials: B::Buf<ThermalMaterial>,
    heat: B::Buf<HeatParams>,
    conduction: Option<bool>,
    /// The cell list's grid with the ±3 stencil PSE needs.
    grid_pse: B::Buf<GridParams>,
}

struct PlasticState<B: Backend> {
    eps: Field<B, f64>,
    rate: Field<B, f64>,
    model: FlowModel,
    model_buf: B::Buf<u8>,
    taylor_quinney: f64,
}

struct ContactState<B: Backend, R: Real, D: Dim> {
    params: B::Buf<ContactParams>,
    motion: ToolMotion,
    normal: Field<B, D::Vec<R>>,
    friction: Field<B, D::Vec<R>>,
    /// σ_y after the plastic update (CURRENT friction cap only; rewritten every step, never reordered).
    yield_stress: Option<B::Buf<f64>>,
    wear: Option<B::Buf<f64>>,
    tool_velocity_index: Option<usize>,
    /// Friction heating is on.
    heating: bool,
    /// The run's time step, which scales the contact stiffness (a step shortened to land on an output time does
    /// not stiffen it).
    nominal_dt: f64,
    /// Host copy of the prescribed-velocity table, for the ramp's rewrites.
    bc_table: Vec<D::Vec<R>>,
}

/// The tool's force on the workpiece and its contact statistics at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactSample {
    /// Σ (f_c + f_t) over the particles: the force of the tool on the workpiece [N per m of depth in 2D].
    pub force: [f64; 2],
    /// Particles in contact.
    pub contacts: usize,
    /// Mean Usui wear rate over the contacting particles [m/s] (NaN when wear is off or nothing touches).
    pub wear_rate: f64,
}

/// Start-of-step copies y0 (reordered with the state each step).
struct Start<B: Backend, R: Real, D: Dim> {
    pos: Field<B, D::Vec<R>>,
    vel: Field<B, D::Vec<R>>,
    rho: Field<B, R>,
    stress: Field<B, D::Sym<R>>,
}

/// Rates ẏ (in the order of the last interaction).
pub struct Rates<B: Backend, R: Real, D: Dim> {
    pub pos: B::Buf<D::Vec<R>>,
    pub vel: B::Buf<D::Vec<R>>,
    pub rho: B::Buf<R>,
    pub stress: B::Buf<D::Sym<R>>,
}

pub struct Solver<B: Backend, R: Real, D: TensorOps<R>> {
    pub particles: Particles<B, R, D>,
    pub rates: Rates<B, R, D>,
    start: Start<B, R, D>,
    sig: B::Buf<D::Sym<R>>,
    art: Option<B::Buf<D::Sym<R>>>,
    sound: Option<B::Buf<R>>,
    pub cells: CellList<B>,
    params: B::Buf<SphParams<R>>,
    pub host_params: SphParams<R>,
    bc_vel: B::Buf<D::Vec<R>>,
    /// Temperature (present with heat or plasticity).
    temp: Option<Field<B, f64>>,
    thermal: Option<ThermalState<B>>,
    plastic: Option<PlasticState<B>>,
    contact: Option<ContactState<B, R, D>>,
    /// Masses for the mechanics where they differ from the particles' masses: zero for thermal-only particles.
    mech_mass: Option<Field<B, R>>,
    shear: f64,
    pub stab: Stabilisers,
    pub n: usize,
    pub time: f64,
    pub steps: u64,
}

impl<B: Backend, R: Real, D: TensorOps<R>> Solver<B, R, D> {
    /// Uploads the particles and allocates what the chosen physics needs.
    pub fn new(b: &B, setup: &Setup<R, D>) -> Result<Self> {
        let particles = &setup.particles;
        let n = particles.len();
        let stab = setup.stabilisers.switches();
        let zeros_v = vec![D::Vec::<R>::default(); n];
        let zeros_r = vec![R::ZERO; n];
        let zeros_s = vec![D::Sym::<R>::default(); n];
        let zeros_f = vec![0.0f64; n];
        let bc_vel = &setup.bc_velocities;
        let table: Vec<D::Vec<R>> = if bc_vel.is_empty() { vec![Default::default()] } else { bc_vel.to_vec() };
        let temp = match &setup.temperature {
            Some(t) => Some(Field::upload(b, t, "temperature")?),
            None => None,
        };
        let thermal = match &setup.thermal {
            Some(t) => {
                let mut g = setup.grid;
                g.stencil = 3;
                let conducting = t.conduction.is_some();
                Some(ThermalState {
                    temp0: if conducting { Some(Field::upload(b, &zeros_f, "temperature")?) } else { None },
                    temp_t: if conducting { Some(b.alloc(n, "temperature rate")?) } else { None },
                    materials: b.upload(&t.materials, "thermal materials")?,
                    heat: b.upload(&[t.heat], "heat parameters")?,
                    conduction: t.conduction,
                    grid_pse: b.upload(&[g], "grid")?,
                })
            }
            None => None,
        };
        let plastic = match &setup.plastic {
            Some(p) => Some(PlasticState {
                eps: Field::upload(b, &zeros_f, "plastic strain")?,
                rate: Field::upload(b, &zeros_f, "plastic strain rate")?,
                model_buf: b.upload(p.model.param_bytes(), "flow-stress parameters")?,
                model: p.model,
                taylor_quinney: p.taylor_quinney,
            }),
            None => None,
        };
        let contact = match &setup.contact {
            Some(c) => {
                if D::D != 2 {
                    return Err(crate::Error::Scene("the parametric tool is 2D only".into()));
                }
                let current = c.params.cap_mode == cap::CURRENT;
                if current && setup.plastic.is_none() {
                    return Err(crate::Error::Scene("the current-yield friction cap needs plasticity".into()));
                }
                if c.params.heat_fraction > 0.0 && (setup.thermal.is_none() || setup.temperature.is_none()) {
                    return Err(crate::Error::Scene("friction heating needs the thermal model".into()));
                }
                Some(ContactState {
                    params: b.upload(&[c.params], "contact parameters")?,
                    motion: c.motion,
                    normal: Field::upload(b, &zeros_v, "contact forces")?,
                    friction: Field::upload(b, &zeros_v, "friction forces")?,
                    yield_stress: if current { Some(b.alloc(n, "yield stress")?) } else { None },
                    wear: if c.wear { Some(b.alloc(n, "wear rate")?) } else { None },
                    tool_velocity_index: c.tool_velocity_index,
                    heating: c.params.heat_fraction > 0.0,
                    nominal_dt: setup.dt,
                    bc_table: table.clone(),
                })
            }
            None => None,
        };
        let mech_mass = if particles.flags.iter().any(|f| f & flags::THERMAL_ONLY != 0) {
            let m: Vec<R> = particles
                .mass
                .iter()
                .zip(&particles.flags)
                .map(|(&m, &f)| if f & flags::THERMAL_ONLY != 0 { R::ZERO } else { m })
                .collect();
            Some(Field::upload(b, &m, "mechanical mass")?)
        } else {
            None
        };
        if (plastic.is_some() || thermal.is_some()) && temp.is_none() {
            return Err(crate::Error::Scene("plasticity and heat need a temperature field".into()));
        }
        Ok(Solver {
            particles: Particles::upload(b, particles)?,
            rates: Rates {
                pos: b.alloc(n, "rates")?,
                vel: b.alloc(n, "rates")?,
                rho: b.alloc(n, "rates")?,
                stress: b.alloc(n, "rates")?,
            },
            start: Start {
                pos: Field::upload(b, &zeros_v, "start-of-step state")?,
                vel: Field::upload(b, &zeros_v, "start-of-step state")?,
                rho: Field::upload(b, &zeros_r, "start-of-step state")?,
                stress: Field::upload(b, &zeros_s, "start-of-step state")?,
            },
            sig: b.alloc(n, "stress over density squared")?,
            art: if stab.stress { Some(b.alloc(n, "artificial stress")?) } else { None },
            sound: if stab.viscosity { Some(b.alloc(n, "sound speed")?) } else { None },
            cells: CellList::new(b, setup.grid, n)?,
            params: b.upload(&[setup.params], "SPH parameters")?,
            host_params: setup.params,
            bc_vel: b.upload(&table, "boundary velocities")?,
            temp,
            thermal,
            plastic,
            contact,
            mech_mass,
            shear: setup.shear,
            stab,
            n,
            time: 0.0,
            steps: 0,
        })
    }

    /// One step of length `dt`.
    pub fn step(&mut self, b: &B, dt: f64) -> Result<()> {
        let n = self.n;
        if let Some(c) = self.contact.as_mut()
            && let Some(k) = c.tool_velocity_index
            && c.motion.ramp > 0.0
            && self.time < c.motion.ramp
        {
            // The tool particles follow the ramp: their prescribed velocity at this step's midpoint.
            let v = c.motion.velocity_at(self.time + 0.5 * dt);
            c.bc_table[k] = D::Vec::<R>::new([R::from_f64(v[0]), R::from_f64(v[1]), R::ZERO]);
            b.write(&mut self.bc_vel, &c.bc_table)?;
        }
        let p = &mut self.particles;
        let s = &mut self.start;
        let r = &self.rates;
        b.sph_predict::<R, D>(
            n,
            R::from_f64(0.5 * dt),
            FieldsMut { pos: &mut p.pos.cur, vel: &mut p.vel.cur, rho: &mut p.rho.cur, stress: &mut p.stress.cur },
            FieldsMut { pos: &mut s.pos.cur, vel: &mut s.vel.cur, rho: &mut s.rho.cur, stress: &mut s.stress.cur },
            FieldsRef { pos: &r.pos, vel: &r.vel, rho: &r.rho, stress: &r.stress },
        )?;
        if let (Some(t), Some(th)) = (self.temp.as_mut(), self.thermal.as_mut())
            && let (Some(t0), Some(tt)) = (th.temp0.as_mut(), th.temp_t.as_ref())
        {
            b.scalar_predict(n, 0.5 * dt, &mut t.cur, &mut t0.cur, tt)?;
        }
        self.cells.build::<R, D>(b, &p.pos.cur)?;
        let perm = &self.cells.perm;
        p.reorder(b, perm)?;
        s.pos.reorder(b, n, perm)?;
        s.vel.reorder(b, n, perm)?;
        s.rho.reorder(b, n, perm)?;
        s.stress.reorder(b, n, perm)?;
        if let Some(t) = self.temp.as_mut() {
            t.reorder(b, n, perm)?;
        }
        if let Some(t0) = self.thermal.as_mut().and_then(|th| th.temp0.as_mut()) {
            t0.reorder(b, n, perm)?;
        }
        if let Some(pl) = self.plastic.as_mut() {
            pl.eps.reorder(b, n, perm)?;
            pl.rate.reorder(b, n, perm)?;
        }
        if let Some(c) = self.contact.as_mut() {
            c.normal.reorder(b, n, perm)?;
            c.friction.reorder(b, n, perm)?;
        }
        if let Some(m) = self.mech_mass.as_mut() {
            m.reorder(b, n, perm)?;
        }
        b.sph_prepare::<R, D>(
            n,
            self.stab,
            &self.params,
            &p.rho.cur,
            &p.stress.cur,
            &mut self.sig,
            self.art.as_mut(),
            self.sound.as_mut(),
            if self.host_params.expansion != R::ZERO { self.temp.as_ref().map(|t| &t.cur) } else { None },
        )?;
        let input = SphInputs::<B, R, D> {
            pos: &p.pos.cur,
            vel: &p.vel.cur,
            rho: &p.rho.cur,
            mass: self.mech_mass.as_ref().map_or(&p.mass.cur, |m| &m.cur),
            stress: &p.stress.cur,
            sig: &self.sig,
            art: self.art.as_ref(),
            sound: self.sound.as_ref(),
            flags: &p.flags.cur,
            bc_vel: &self.bc_vel,
            contact: self.contact.as_ref().map(|c| (&c.normal.cur, &c.friction.cur)),
        };
        let r = &mut self.rates;
        b.sph_rates::<R, D>(
            n,
            self.stab,
            &self.params,
            &self.cells.grid_buf,
            &self.cells.starts,
            &input,
            FieldsMut { pos: &mut r.pos, vel: &mut r.vel, rho: &mut r.rho, stress: &mut r.stress },
        )?;
        if let (Some(t), Some(th)) = (self.temp.as_ref(), self.thermal.as_mut())
            && let (Some(pse), Some(tt)) = (th.conduction, th.temp_t.as_mut())
        {
            let grid = if pse { &th.grid_pse } else { &self.cells.grid_buf };
            let hin = crate::backend::HeatInputs::<B, R, D> {
                pos: &p.pos.cur,
                rho: &p.rho.cur,
                mass: &p.mass.cur,
                temp: &t.cur,
                flags: &p.flags.cur,
                materials: &th.materials,
            };
            b.heat_rates::<R, D>(n, pse, &th.heat, &self.params, grid, &self.cells.starts, &hin, tt)?;
        }
        b.sph_correct::<R, D>(
            n,
            R::from_f64(dt),
            FieldsMut { pos: &mut p.pos.cur, vel: &mut p.vel.cur, rho: &mut p.rho.cur, stress: &mut p.stress.cur },
            FieldsRef { pos: &s.pos.cur, vel: &s.vel.cur, rho: &s.rho.cur, stress: &s.stress.cur },
            FieldsRef { pos: &r.pos, vel: &r.vel, rho: &r.rho, stress: &r.stress },
        )?;
        if let (Some(t), Some(th)) = (self.temp.as_mut(), self.thermal.as_ref())
            && let (Some(t0), Some(tt)) = (th.temp0.as_ref(), th.temp_t.as_ref())
        {
            b.scalar_correct(n, dt, &mut t.cur, &t0.cur, tt)?;
        }
        if let (Some(pl), Some(t)) = (self.plastic.as_mut(), self.temp.as_mut()) {
            let consts = PlasticConsts { shear: self.shear, dt, taylor_quinney: pl.taylor_quinney, _pad: 0.0 };
            b.plastic_step::<R, D>(
                n,
                &pl.model,
                &pl.model_buf,
                consts,
                crate::backend::PlasticInputs {
                    stress: &mut p.stress.cur,
                    rho: &p.rho.cur,
                    eps: &mut pl.eps.cur,
                    rate: &mut pl.rate.cur,
                    temp: &mut t.cur,
                    flags: &p.flags.cur,
                    materials: self.thermal.as_ref().map(|th| &th.materials),
                    yield_stress: self.contact.as_mut().and_then(|c| c.yield_stress.as_mut()),
                },
            )?;
        }
        if let Some(c) = self.contact.as_mut() {
            let t1 = self.time + dt;
            let tool = ToolState {
                offset: c.motion.offset_at(t1),
                velocity: c.motion.velocity_at(t1),
                dt: dt.max(c.nominal_dt),
                step: dt,
            };
            let heating = c.heating;
            b.contact::<R, D>(
                n,
                &c.params,
                tool,
                ContactInputs {
                    pos: &p.pos.cur,
                    vel: &p.vel.cur,
                    mass: &p.mass.cur,
                    rho: &p.rho.cur,
                    flags: &p.flags.cur,
                    normal: &mut c.normal.cur,
                    friction: &mut c.friction.cur,
                    temp: self.temp.as_mut().map(|t| &mut t.cur),
                    materials: if heating { self.thermal.as_ref().map(|th| &th.materials) } else { None },
                    yield_stress: c.yield_stress.as_ref(),
                    wear: c.wear.as_mut(),
                },
            )?;
        }
        self.time += dt;
        self.steps += 1;
        Ok(())
    }

    /// The tool's force on the workpiece now, summed in f64 in particle order (deterministic, equal on every
    /// backend); None without a tool.
    pub fn contact_sample(&self, b: &B) -> Result<Option<ContactSample>> {
        let Some(c) = &self.contact else { return Ok(None) };
        let (fc, ft) = (c.normal.read(b)?, c.friction.read(b)?);
        let wear = match &c.wear {
            Some(w) => Some(b.read(w)?),
            None => None,
        };
        let mut s = ContactSample::default();
        let mut wear_sum = 0.0;
        for i in 0..self.n {
            let f = [fc[i].get(0).to_f64() + ft[i].get(0).to_f64(), fc[i].get(1).to_f64() + ft[i].get(1).to_f64()];
            s.force[0] += f[0];
            s.force[1] += f[1];
            if fc[i].get(0) != R::ZERO || fc[i].get(1) != R::ZERO {
                s.contacts += 1;
                if let Some(w) = &wear {
                    wear_sum += w[i];
                }
            }
        }
        s.wear_rate = if wear.is_some() && s.contacts > 0 { wear_sum / s.contacts as f64 } else { f64::NAN };
        Ok(Some(s))
    }

    /// Sets the run's time step, which scales the contact stiffness (after a CFL reduction).
    pub fn set_nominal_dt(&mut self, dt: f64) {
        if let Some(c) = self.contact.as_mut() {
            c.nominal_dt = dt;
        }
    }

    /// Host copies of the positions and flags (state order).
    #[allow(clippy::type_complexity)]
    pub fn positions(&self, b: &B) -> Result<(Vec<D::Vec<R>>, Vec<u32>)> {
        Ok((self.particles.pos.read(b)?, self.particles.flags.read(b)?))
    }

    /// Where the tool's frame origin is at the current time, with a tool.
    pub fn tool_offset(&self) -> Option<[f64; 2]> {
        self.contact.as_ref().map(|c| c.motion.offset_at(self.time))
    }

    /// A host copy of the particle state (in the current sorted order).
    pub fn download(&self, b: &B) -> Result<HostParticles<R, D>> {
        self.particles.download(b)
    }

    /// Host copies of the temperature, plastic strain and plastic strain rate (in the state's order), where modelled.
    #[allow(clippy::type_complexity)]
    pub fn download_internal(&self, b: &B) -> Result<(Option<Vec<f64>>, Option<Vec<f64>>, Option<Vec<f64>>)> {
        let t = match &self.temp {
            Some(t) => Some(t.read(b)?),
            None => None,
        };
        let (e, r) = match &self.plastic {
            Some(p) => (Some(p.eps.read(b)?), Some(p.rate.read(b)?)),
            None => (None, None),
        };
        Ok((t, e, r))
    }

    /// Host copies of the rates of the last step (x, v, ρ, S), in the state's order.
    #[allow(clippy::type_complexity)]
    pub fn download_rates(&self, b: &B) -> Result<(Vec<D::Vec<R>>, Vec<D::Vec<R>>, Vec<R>, Vec<D::Sym<R>>)> {
        Ok((b.read(&self.rates.pos)?, b.read(&self.rates.vel)?, b.read(&self.rates.rho)?, b.read(&self.rates.stress)?))
    }
}

/// Named raw copies of every buffer that carries state from one step to the next (the particle state, the
/// start-of-step copies, the rates the next predictor uses, temperature and plastic fields). Scratch buffers
/// (pre-pass outputs, cell list) are rebuilt every step and are not included.
pub type StateBlobs = Vec<(String, Vec<u8>)>;

fn dump<B: Backend, T: crate::backend::Element>(
    b: &B,
    name: &str,
    buf: &B::Buf<T>,
    out: &mut StateBlobs,
) -> Result<()> {
    out.push((name.to_string(), bytemuck::cast_slice::<T, u8>(&b.read(buf)?).to_vec()));
    Ok(())
}

impl<B: Backend, R: Real, D: TensorOps<R>> Solver<B, R, D> {
    /// Copies of every stateful buffer, for a checkpoint.
    pub fn save_state(&self, b: &B) -> Result<StateBlobs> {
        let mut o = Vec::new();
        self.particles.save(b, &mut o)?;
        dump(b, "pos0", &self.start.pos.cur, &mut o)?;
        dump(b, "vel0", &self.start.vel.cur, &mut o)?;
        dump(b, "rho0", &self.start.rho.cur, &mut o)?;
        dump(b, "stress0", &self.start.stress.cur, &mut o)?;
        dump(b, "pos_t", &self.rates.pos, &mut o)?;
        dump(b, "vel_t", &self.rates.vel, &mut o)?;
        dump(b, "rho_t", &self.rates.rho, &mut o)?;
        dump(b, "stress_t", &self.rates.stress, &mut o)?;
        if let Some(t) = &self.temp {
            dump(b, "temp", &t.cur, &mut o)?;
        }
        if let Some(th) = &self.thermal {
            if let Some(t0) = &th.temp0 {
                dump(b, "temp0", &t0.cur, &mut o)?;
            }
            if let Some(tt) = &th.temp_t {
                dump(b, "temp_t", tt, &mut o)?;
            }
        }
        if let Some(pl) = &self.plastic {
            dump(b, "eps", &pl.eps.cur, &mut o)?;
            dump(b, "eps_rate", &pl.rate.cur, &mut o)?;
        }
        if let Some(c) = &self.contact {
            dump(b, "contact_normal", &c.normal.cur, &mut o)?;
            dump(b, "contact_friction", &c.friction.cur, &mut o)?;
        }
        if let Some(m) = &self.mech_mass {
            dump(b, "mech_mass", &m.cur, &mut o)?;
        }
        Ok(o)
    }

    /// Restores the buffers saved by [`Solver::save_state`] (the solver must have been built from the same scene).
    pub fn load_state(&mut self, b: &B, s: &StateBlobs) -> Result<()> {
        self.particles.load(b, s)?;
        crate::state::load_blob(b, "pos0", &mut self.start.pos.cur, s)?;
        crate::state::load_blob(b, "vel0", &mut self.start.vel.cur, s)?;
        crate::state::load_blob(b, "rho0", &mut self.start.rho.cur, s)?;
        crate::state::load_blob(b, "stress0", &mut self.start.stress.cur, s)?;
        crate::state::load_blob(b, "pos_t", &mut self.rates.pos, s)?;
        crate::state::load_blob(b, "vel_t", &mut self.rates.vel, s)?;
        crate::state::load_blob(b, "rho_t", &mut self.rates.rho, s)?;
        crate::state::load_blob(b, "stress_t", &mut self.rates.stress, s)?;
        if let Some(t) = &mut self.temp {
            crate::state::load_blob(b, "temp", &mut t.cur, s)?;
        }
        if let Some(th) = &mut self.thermal {
            if let Some(t0) = &mut th.temp0 {
                crate::state::load_blob(b, "temp0", &mut t0.cur, s)?;
            }
            if let Some(tt) = &mut th.temp_t {
                crate::state::load_blob(b, "temp_t", tt, s)?;
            }
        }
        if let Some(pl) = &mut self.plastic {
            crate::state::load_blob(b, "eps", &mut pl.eps.cur, s)?;
            crate::state::load_blob(b, "eps_rate", &mut pl.rate.cur, s)?;
        }
        if let Some(c) = &mut self.contact {
            crate::state::load_blob(b, "contact_normal", &mut c.normal.cur, s)?;
            crate::state::load_blob(b, "contact_friction", &mut c.friction.cur, s)?;
            // The ramp's table entry is rewritten by the next step while the ramp lasts; after it, it is final.
            if let Some(k) = c.tool_velocity_index {
                let v = c.motion.velocity_at(self.time);
                c.bc_table[k] = D::Vec::<R>::new([R::from_f64(v[0]), R::from_f64(v[1]), R::ZERO]);
                b.write(&mut self.bc_vel, &c.bc_table)?;
            }
        }
        if let Some(m) = &mut self.mech_mass {
            crate::state::load_blob(b, "mech_mass", &mut m.cur, s)?;
        }
        Ok(())
    }
}
