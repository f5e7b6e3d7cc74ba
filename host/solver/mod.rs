//! The SPH solver loop, written once against [`Backend`]. One step (roethlin-solver.md §5.2, reordered so that
//! the neighbour search is exact at the positions where the rates are evaluated):
//!
//! 1. predictor: y0 ← y, y ← y0 + ½Δt ẏ (ẏ from the previous step's midpoint; zero at the first step);
//! 2. cell list on the predicted positions; reorder y, y0 and the per-particle constants (mass, id, flags);
//! 3. pre-pass: σ/ρ², artificial stress, sound speed (the last two only when their stabiliser is on);
//! 4. pair interaction: ẏ at the midpoint, with the boundary conditions imposed on the rates;
//! 5. corrector: y ← y0 + Δt ẏ.
//!
//! The rates are not reordered: the predictor consumes them in the order the corrector left, and the interaction
//! rewrites them. Buffers of a stabiliser that is off are not allocated.

pub mod diagnostics;
pub mod params;

use crate::Result;
use crate::backend::{Backend, FieldsMut, FieldsRef, SphInputs};
use crate::kernels::neighbour::GridParams;
use crate::kernels::sph::{SphParams, Stabilisers, TensorOps};
use crate::kernels::{Dim, Real};
use crate::neighbour::CellList;
use crate::state::{Field, HostParticles, Particles};

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
    pub stab: Stabilisers,
    pub n: usize,
    pub time: f64,
    pub steps: u64,
}

impl<B: Backend, R: Real, D: TensorOps<R>> Solver<B, R, D> {
    /// Uploads the particles and allocates what the chosen physics needs. `bc_vel` is the table of prescribed
    /// velocities that the particles' flags index.
    pub fn new(
        b: &B,
        particles: &HostParticles<R, D>,
        params: SphParams<R>,
        stab: Stabilisers,
        grid: GridParams,
        bc_vel: &[D::Vec<R>],
    ) -> Result<Self> {
        let n = particles.len();
        let zeros_v = vec![D::Vec::<R>::default(); n];
        let zeros_r = vec![R::ZERO; n];
        let zeros_s = vec![D::Sym::<R>::default(); n];
        let table: Vec<D::Vec<R>> = if bc_vel.is_empty() { vec![Default::default()] } else { bc_vel.to_vec() };
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
            cells: CellList::new(b, grid, n)?,
            params: b.upload(&[params], "SPH parameters")?,
            host_params: params,
            bc_vel: b.upload(&table, "boundary velocities")?,
            stab,
            n,
            time: 0.0,
            steps: 0,
        })
    }

    /// One step of length `dt`.
    pub fn step(&mut self, b: &B, dt: f64) -> Result<()> {
        let n = self.n;
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
        self.cells.build::<R, D>(b, &p.pos.cur)?;
        let perm = &self.cells.perm;
        p.reorder(b, perm)?;
        s.pos.reorder(b, n, perm)?;
        s.vel.reorder(b, n, perm)?;
        s.rho.reorder(b, n, perm)?;
        s.stress.reorder(b, n, perm)?;
        b.sph_prepare::<R, D>(
            n,
            self.stab,
            &self.params,
            &p.rho.cur,
            &p.stress.cur,
            &mut self.sig,
            self.art.as_mut(),
            self.sound.as_mut(),
        )?;
        let input = SphInputs::<B, R, D> {
            pos: &p.pos.cur,
            vel: &p.vel.cur,
            rho: &p.rho.cur,
            mass: &p.mass.cur,
            stress: &p.stress.cur,
            sig: &self.sig,
            art: self.art.as_ref(),
            sound: self.sound.as_ref(),
            flags: &p.flags.cur,
            bc_vel: &self.bc_vel,
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
        b.sph_correct::<R, D>(
            n,
            R::from_f64(dt),
            FieldsMut { pos: &mut p.pos.cur, vel: &mut p.vel.cur, rho: &mut p.rho.cur, stress: &mut p.stress.cur },
            FieldsRef { pos: &s.pos.cur, vel: &s.vel.cur, rho: &s.rho.cur, stress: &s.stress.cur },
            FieldsRef { pos: &r.pos, vel: &r.vel, rho: &r.rho, stress: &r.stress },
        )?;
        self.time += dt;
        self.steps += 1;
        Ok(())
    }

    /// A host copy of the particle state (in the current sorted order).
    pub fn download(&self, b: &B) -> Result<HostParticles<R, D>> {
        self.particles.download(b)
    }

    /// Host copies of the rates of the last step (x, v, ρ, S), in the state's order.
    #[allow(clippy::type_complexity)]
    pub fn download_rates(&self, b: &B) -> Result<(Vec<D::Vec<R>>, Vec<D::Vec<R>>, Vec<R>, Vec<D::Sym<R>>)> {
        Ok((b.read(&self.rates.pos)?, b.read(&self.rates.vel)?, b.read(&self.rates.rho)?, b.read(&self.rates.stress)?))
    }
}
