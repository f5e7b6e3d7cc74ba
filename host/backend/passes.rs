//! The passes, written once for every backend: each builds its argument struct (`kernels::pass`, through
//! [`super::args`], which checks every buffer's length), checks what it can of the buffers' contents (where the
//! backend's memory is the host's: the cell starts against the grid, the bodies against the materials), picks the
//! variant and hands the struct to the backend's generic [`Backend::launch`]. The variant's marker type names its
//! entry in the pass table (`kernels::pass::table`), so the dispatch over stabilisers and flow models below is
//! checked against the table when it compiles.

use super::args::{self, PrepareBufs, check_len};
use super::tool::{DeviceShapes, DeviceTools};
use super::{
    Backend, BondBufs, Buffer, ContactInputs, Count, FieldsMut, FusedContact, FusedHeat, FusedPrepare, HeatInputs,
    PlasticInputs, PlasticPass, PrepassBufs, PrepassDamageBufs, ScalarsAt, ScalarsMut, SkinTest, SphInputs, StepFields,
    ToolStatesAt,
};
use crate::kernels::contact::{MeshTool, Tool2d};
use crate::kernels::neighbour::GridParams;
use crate::kernels::pass::{
    Bond, BondIndex, BondOpen, Contact, CorrectionPass, Density, Finish, FinishPlastic, Hash, Heat, NeighbourList,
    Plastic, Predict, Prepare, RatesPass, Verlet,
};
use crate::kernels::sph::heat::HeatParams;
use crate::kernels::sph::params::flags::BODY_SHIFT;
use crate::kernels::sph::plastic::PlasticConsts;
use crate::kernels::sph::{CubicSpline, SphParams, Stabilisers, TensorOps};
use crate::kernels::{Dim, Dim3, Real};
use crate::material::FlowModel;
use crate::{Error, Result};

/// Runs `$body` with `$m` bound to the concrete flow-stress model of `$model` and `$t` naming its type: the host's
/// one map from `FlowModel` to the kernel types (whose entries the pass table lists).
macro_rules! with_model {
    ($model:expr, $t:ident, $m:ident => $body:expr) => {{
        use crate::kernels::material as km;
        match $model {
            FlowModel::JohnsonCook($m) => {
                type $t = km::JohnsonCook;
                $body
            }
            FlowModel::Calamaz2008($m) => {
                type $t = km::Calamaz2008;
                $body
            }
            FlowModel::Calamaz2010($m) => {
                type $t = km::Calamaz2010;
                $body
            }
            FlowModel::Calamaz2011($m) => {
                type $t = km::Calamaz2011;
                $body
            }
            FlowModel::SimaOzel1($m) => {
                type $t = km::SimaOzel1;
                $body
            }
            FlowModel::SimaOzel2($m) => {
                type $t = km::SimaOzel2;
                $body
            }
            FlowModel::SimaOzel3($m) => {
                type $t = km::SimaOzel3;
                $body
            }
            FlowModel::Scgl($m) => {
                type $t = km::Scgl;
                $body
            }
            FlowModel::Bilinear($m) => {
                type $t = km::Bilinear;
                $body
            }
        }
    }};
}

/// Runs `$body` with each `$c` a `const bool` equal to its runtime `$e`: one monomorphised copy per combination
/// (the variants of the table's stabiliser entries).
macro_rules! with_bools {
    (; $body:block) => {
        $body
    };
    ($c:ident = $e:expr $(, $rc:ident = $re:expr)* ; $body:block) => {
        if $e {
            const $c: bool = true;
            with_bools!($($rc = $re),* ; $body)
        } else {
            const $c: bool = false;
            with_bools!($($rc = $re),* ; $body)
        }
    };
}

/// The grid a buffer holds, where the backend's memory is the host's.
fn host_grid<B: Backend>(b: &B, grid: &B::Buf<GridParams>) -> Option<GridParams> {
    b.host_slice(grid).and_then(|g| g.first().copied())
}

/// The cell starts (and the Verlet list's layout) against the grid, where the host can read it.
fn check_cells<B: Backend>(
    b: &B,
    op: &'static str,
    n: usize,
    grid: &B::Buf<GridParams>,
    starts: &B::Buf<u32>,
    list: Option<&B::Buf<u32>>,
) -> Result<()> {
    check_len(op, 1, grid.len())?;
    let Some(g) = host_grid(b, grid) else { return Ok(()) };
    check_len(op, g.n_cells as usize + 2, starts.len())?;
    if let Some(l) = list {
        let stride = g.list_stride as usize;
        if g.list_capacity == 0 || stride < n {
            return Err(Error::Length { op, expected: n, got: stride });
        }
        check_len(op, g.list_words(), l.len())?;
    }
    Ok(())
}

/// A per-body table of `len` entries against every body index in `flags[..n]`, where the host can read them.
fn check_bodies<B: Backend>(b: &B, op: &'static str, n: usize, flags: &B::Buf<u32>, len: usize) -> Result<()> {
    let Some(f) = b.host_slice(flags) else { return Ok(()) };
    let bodies = f[..n.min(f.len())].iter().map(|f| (f >> BODY_SHIFT) as usize + 1).max();
    check_len(op, bodies.unwrap_or(0), len)
}

/// Lanes per particle: a power of two up to 8 (they combine within a warp on the GPU, in the same order on the
/// CPU).
fn check_lanes(lanes: u32) -> Result<()> {
    if matches!(lanes, 1 | 2 | 4 | 8) {
        Ok(())
    } else {
        Err(Error::Length { op: "lanes per particle (1, 2, 4 or 8)", expected: 8, got: lanes as usize })
    }
}

/// The passes of every backend ([`Backend`] gives memory and the generic launch; these build the arguments).
pub trait Passes: Backend {
    /// keys[i] = cell key of pos[i] (`GridParams::key`), for i < n.
    fn hash<R: Real, D: Dim>(
        &self,
        n: usize,
        pos: &Self::Buf<D::Vec<R>>,
        grid: &Self::Buf<GridParams>,
        keys: &mut Self::Buf<u32>,
    ) -> Result<()> {
        let a = args::hash_args::<_, R, D>(self, n, pos, None, grid, None, keys)?;
        // SAFETY: `hash_args` checked every length the pass touches.
        unsafe { self.launch::<Hash<R, D>>(&a) }
    }

    /// Neighbour lists (j ≠ i, |x_ij|² < support2) of sorted particles in CSR form: counts[i] always, and the
    /// indices at list[offsets[i]..] when `offsets` is given (the exclusive scan of a counting pass).
    #[allow(clippy::too_many_arguments)]
    fn neighbour_list<'c, R: Real, D: Dim>(
        &self,
        n: impl Into<Count<'c, Self>>,
        pos: &Self::Buf<D::Vec<R>>,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        support2: R,
        offsets: Option<&Self::Buf<u32>>,
        counts: &mut Self::Buf<u32>,
        list: &mut Self::Buf<u32>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let n = count.n;
        check_cells(self, "neighbour_list starts", n, grid, starts, None)?;
        if let Some(off) = offsets.and_then(|o| self.host_slice(o)) {
            check_len("neighbour_list offsets", n + 1, off.len())?;
            check_len("neighbour_list list", off[n] as usize, list.len())?;
        }
        let a = args::neighbour_list_args::<_, R, D>(self, count, pos, grid, starts, support2, offsets, counts, list)?;
        // SAFETY: the builder checked the lengths, the rows against the list above where the host can read them;
        // row i is list[off[i] .. off[i + 1]], disjoint from every other row.
        unsafe { self.launch::<NeighbourList<R, D>>(&a) }
    }

    /// ρ_i = Σ_j m_j W(|x_ij|) over sorted particles (`sph::density::density_sum`).
    #[allow(clippy::too_many_arguments)]
    fn density<'c, R: Real, D: Dim>(
        &self,
        n: impl Into<Count<'c, Self>>,
        pos: &Self::Buf<D::Vec<R>>,
        mass: &Self::Buf<R>,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        kernel: &Self::Buf<CubicSpline<R>>,
        rho: &mut Self::Buf<R>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let n = count.n;
        check_cells(self, "density starts", n, grid, starts, None)?;
        let a = args::density_args::<_, R, D>(self, count, pos, mass, grid, starts, kernel, rho)?;
        // SAFETY: the builder checked the lengths; pos/mass are the sorted particles of this cell list.
        unsafe { self.launch::<Density<R, D>>(&a) }
    }

    /// SPH pre-pass (`sph::interact::prepare`): sig = σ/ρ², art = artificial stress (if on), sound = √(K/ρ)
    /// (if the viscosity is on; times the Balsara factor of `out.av_switch` where given), vol = m/ρ with `mass` the
    /// particles' full masses (the thermal-only ones included: they conduct); `temp` is given when the EOS has
    /// thermal expansion. With `gate` it runs only when the step's rebuild flag is set (the predictor ran the
    /// pre-pass; a rebuild's reorder needs it again).
    #[allow(clippy::too_many_arguments)]
    fn sph_prepare<'c, R: Real, D: TensorOps<R>>(
        &self,
        n: impl Into<Count<'c, Self>>,
        stab: Stabilisers,
        params: &Self::Buf<SphParams<R>>,
        rho: &Self::Buf<R>,
        mass: &Self::Buf<R>,
        stress: &Self::Buf<D::Sym<R>>,
        out: PrepassBufs<'_, Self, R, D>,
        temp: Option<&Self::Buf<f64>>,
        gate: Option<ScalarsAt<'_, Self>>,
        damage: Option<PrepassDamageBufs<'_, Self>>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let dmg = damage.is_some();
        let q = PrepareBufs::<_, R, D> { params, rho, mass, stress, out, temp, damage };
        let a = args::prepare_args(self, count, stab, q, gate.as_ref())?;
        with_bools!(AV = stab.viscosity, AS = stab.stress, DMG = dmg; {
            // SAFETY: the builder checked the lengths and that the stabilisers' and the damage's buffers exist
            // where they are on.
            unsafe { self.launch::<Prepare<R, D, AV, AS, DMG>>(&a) }
        })
    }

    /// SPH pair interaction (`sph::interact::rates`): the rates of every sorted particle, each summed by `lanes`
    /// lanes (1, 2, 4 or 8; the sums' order depends on it, equally on every backend). With `heat`, the same
    /// neighbour walk also sums the Brookshaw conduction (`sph::interact::rates_heat`), equal bit for bit to
    /// [`Passes::heat_rates`] on this cell list. With `list` (built by [`Passes::verlet_build`] on this cell
    /// list) the pair loops read it instead of walking the stencil. With `av_switch` (the viscosity on) each
    /// particle's Balsara factor of its velocity gradient is written there (`sph::interact::balsara`).
    #[allow(clippy::too_many_arguments)]
    fn sph_rates<'c, R: Real, D: TensorOps<R>>(
        &self,
        n: impl Into<Count<'c, Self>>,
        lanes: u32,
        stab: Stabilisers,
        params: &SphParams<R>,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        list: Option<&Self::Buf<u32>>,
        input: &SphInputs<'_, Self, R, D>,
        out: FieldsMut<'_, Self, R, D>,
        dissipation: Option<&mut Self::Buf<R>>,
        av_switch: Option<&mut Self::Buf<R>>,
        heat: Option<FusedHeat<'_, Self, R, D>>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let n = count.n;
        check_lanes(lanes)?;
        check_cells(self, "sph_rates cells", n, grid, starts, list)?;
        if let Some(h) = &heat {
            check_bodies(self, "sph_rates (fused conduction)", n, h.input.flags, h.input.materials.len())?;
        }
        let (fused, dmg, cs, cut) = (heat.is_some(), input.mask.is_some(), input.correction.is_some(), input.cut);
        let a = args::rates_args(
            self,
            count,
            lanes,
            stab,
            params,
            grid,
            starts,
            list,
            input,
            out,
            dissipation,
            av_switch,
            heat,
        )?;
        if dmg && cs {
            return Err(Error::Length { op: "sph_rates (CSPM has no damage entries)", expected: 0, got: 1 });
        }
        if cut && (dmg || fused) {
            return Err(Error::Length {
                op: "sph_rates (the cohesive path has no damage or conduction entries)",
                expected: 0,
                got: 1,
            });
        }
        if cut {
            return with_bools!(AV = stab.viscosity, AS = stab.stress, XS = stab.xsph, CS = cs; {
                // SAFETY: as below; the flags hold n sorted particles.
                unsafe { self.launch::<RatesPass<R, D, AV, AS, XS, false, false, CS, true>>(&a) }
            });
        }
        with_bools!(AV = stab.viscosity, AS = stab.stress, XS = stab.xsph, HEAT = fused; {
            // SAFETY: the builder checked that every array holds n sorted particles (the mask where `DMG`, the
            // correction where `CS`), the cells and the list are checked above against the grid, and each
            // particle's rates are written by its own thread only.
            unsafe {
                if dmg {
                    self.launch::<RatesPass<R, D, AV, AS, XS, HEAT, true, false, false>>(&a)
                } else if cs {
                    self.launch::<RatesPass<R, D, AV, AS, XS, HEAT, false, true, false>>(&a)
                } else {
                    self.launch::<RatesPass<R, D, AV, AS, XS, HEAT, false, false, false>>(&a)
                }
            }
        })
    }

    /// The cohesive path's bonds (`sph::bond`) of `n` sorted particles after the pair interaction: the map from
    /// id to sorted index, then each bond's traction added to its two particles' accelerations `vel_t`, then under
    /// `coupling = "continuum"` the columns of the bonds past their onset opened.
    fn bonds<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        k: BondBufs<'_, Self, R, D>,
        vel_t: &mut Self::Buf<D::Vec<R>>,
    ) -> Result<()> {
        let ids = k.id.len();
        check_len("bond index (one entry per id)", n, ids)?;
        if let Some(id) = self.host_slice(k.id)
            && id[..n].iter().any(|&i| i as usize >= k.index.len())
        {
            return Err(Error::Length { op: "bond ids (below the index's length)", expected: k.index.len(), got: ids });
        }
        // Only the opening pass reads the columns.
        let continuum = k.params.coupling == crate::kernels::sph::bond::CONTINUUM;
        if continuum
            && let Some(column) = self.host_slice(k.column)
            && column[..n].iter().any(|&c| c != crate::kernels::sph::bond::NONE && c as usize >= k.index.len())
        {
            return Err(Error::Length {
                op: "bond columns (below the index's length)",
                expected: k.index.len(),
                got: n,
            });
        }
        let (map, a, open) = args::bond_args(self, n, k, vel_t)?;
        // SAFETY: the builder checked the lengths and (on the CPU) that every id and column indexes the map; each id
        // is one particle's, so each map entry is written once; a bond's owner is the only writer of its own and its
        // partner's acceleration (the set-up pairs each particle at most once); the opening pass writes each
        // particle's own flags, after the bond pass has written the onsets it reads.
        unsafe {
            self.launch::<BondIndex<R, D>>(&map)?;
            self.launch::<Bond<R, D>>(&a)?;
            if continuum {
                self.launch::<BondOpen<R, D>>(&open)?;
            }
            Ok(())
        }
    }

    /// The CSPM kernel-gradient correction (`sph::correction`): B_i⁻¹ of every sorted particle into `out` (the
    /// identity where det B ≤ `min_det`, and with `path_only` where no neighbour lies across the cohesive path),
    /// from the positions, mechanical masses, pre-pass volumes and flags of `input`, each summed by `lanes` lanes as
    /// the pair interaction's; [`Passes::sph_rates`] with `input.correction` then applies it.
    #[allow(clippy::too_many_arguments)]
    fn sph_correction<'c, R: Real, D: TensorOps<R>>(
        &self,
        n: impl Into<Count<'c, Self>>,
        lanes: u32,
        params: &SphParams<R>,
        min_det: R,
        path_only: bool,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        list: Option<&Self::Buf<u32>>,
        input: &SphInputs<'_, Self, R, D>,
        out: &mut Self::Buf<D::Sym<R>>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let n = count.n;
        check_lanes(lanes)?;
        check_cells(self, "sph_correction cells", n, grid, starts, list)?;
        let a =
            args::correction_args(self, count, lanes, params, (min_det, path_only), grid, starts, list, input, out)?;
        // SAFETY: the builder checked the lengths, the cells and the list are checked above; each particle's
        // correction is written by its own thread only.
        unsafe { self.launch::<CorrectionPass<R, D>>(&a) }
    }

    /// Conduction rates Ṫ (`sph::heat::heat_rate`), Brookshaw or (`pse`) PSE; `grid` has stencil 2 for
    /// Brookshaw and 3 for PSE; `list` the Verlet list of `grid` (Brookshaw only: PSE reaches farther).
    #[allow(clippy::too_many_arguments)]
    fn heat_rates<'c, R: Real, D: Dim>(
        &self,
        n: impl Into<Count<'c, Self>>,
        lanes: u32,
        pse: bool,
        hp: &HeatParams,
        params: &SphParams<R>,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        list: Option<&Self::Buf<u32>>,
        input: &HeatInputs<'_, Self, R, D>,
        temp_t: &mut Self::Buf<f64>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let n = count.n;
        check_lanes(lanes)?;
        check_cells(self, "heat_rates cells", n, grid, starts, list)?;
        check_bodies(self, "heat_rates materials", n, input.flags, input.materials.len())?;
        let a = args::heat_args(self, count, lanes, pse, hp, params, grid, starts, list, input, temp_t)?;
        with_bools!(PSE = pse; {
            // SAFETY: the builder checked the lengths, the cells and bodies are checked above.
            unsafe { self.launch::<Heat<R, D, PSE>>(&a) }
        })
    }

    /// The predictor (`sph::step::predict_particle`): y0 ← y, y ← y0 + ½Δt ẏ (x, v, ρ, S and, with conduction,
    /// T), with the skin test of each predicted position: a particle farther than the grid's skin from where the
    /// cell list binned it (`GridParams::beyond_skin`) sets the step's rebuild flag.
    /// With `prepare`, each particle's pre-pass follows its prediction in the same pass
    /// (`sph::interact::prepare_particle`; the same results as [`Passes::sph_prepare`] after the predictor).
    fn step_predict<'c, R: Real, D: TensorOps<R>>(
        &self,
        n: impl Into<Count<'c, Self>>,
        s: ScalarsMut<'_, Self>,
        f: StepFields<'_, Self, R, D>,
        skin: SkinTest<'_, Self, R, D>,
        prepare: Option<FusedPrepare<'_, Self, R, D>>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let dmg = prepare.as_ref().is_some_and(|q| q.damage.is_some());
        let a = args::predict_args(self, count, s, f, skin, prepare)?;
        with_bools!(DMG = dmg; {
            // SAFETY: the builder checked the lengths (the damage's where `DMG`) and the scalars' index.
            unsafe { self.launch::<Predict<R, D, DMG>>(&a) }
        })
    }

    /// The Verlet list (`neighbour::verlet::verlet_row`) of the n sorted particles at `pos` on the cell list
    /// `grid`/`starts`, into `list` (`GridParams::list_words` entries); with a gate, only when that step rebuilds.
    fn verlet_build<'c, R: Real, D: Dim>(
        &self,
        n: impl Into<Count<'c, Self>>,
        gate: Option<ScalarsAt<'_, Self>>,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        pos: &Self::Buf<D::Vec<R>>,
        list: &mut Self::Buf<u32>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let n = count.n;
        check_cells(self, "verlet_build cells", n, grid, starts, Some(list))?;
        let a = args::verlet_args::<_, R, D>(self, count, gate.as_ref(), grid, starts, pos, list)?;
        // SAFETY: the builder checked the lengths, the list's layout is checked above where the host can read the
        // grid (the caller sizes it from the grid it uploads); thread i writes only row i.
        unsafe { self.launch::<Verlet<R, D>>(&a) }
    }

    /// The fused corrector (`sph::step::correct_particle`) y ← y0 + Δt ẏ, followed by the plastic update of the
    /// same particle when `plastic` is given (`sph::plastic::plastic_particle`), and then by the tool's contact
    /// pass of the same particle when `contact` is given (`contact::penalty::contact_particle`, 2D; needs
    /// `plastic`): the same results as [`Passes::contact`] after the corrector, without a pass of its own.
    fn step_finish<'c, R: Real, D: TensorOps<R>>(
        &self,
        n: impl Into<Count<'c, Self>>,
        s: ScalarsAt<'_, Self>,
        f: StepFields<'_, Self, R, D>,
        plastic: Option<PlasticPass<'_, Self, R>>,
        contact: Option<FusedContact<'_, Self, R, D>>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let n = count.n;
        if contact.is_some() && (plastic.is_none() || D::D != 2) {
            return Err(Error::Length {
                op: "step_finish (the fused contact needs plasticity, 2D)",
                expected: 2,
                got: D::D,
            });
        }
        let Some(p) = plastic else {
            let a = args::finish_args(self, count, &s, f)?;
            // SAFETY: the builder checked the lengths.
            return unsafe { self.launch::<Finish<R, D>>(&a) };
        };
        check_len("flags", n, p.flags.len())?;
        if p.taylor_quinney > 0.0 {
            check_bodies(self, "step_finish materials", n, p.flags, p.materials.map_or(0, |m| m.len()))?;
        }
        if let Some(m) = contact.as_ref().and_then(|c| c.materials) {
            check_bodies(self, "contact materials", n, p.flags, m.len())?;
        }
        let (model, dmg) = (p.model, p.damage.is_some());
        with_model!(model, M, m => {
            let a = args::finish_plastic_args::<_, R, D, M>(self, count, &s, f, p, *m, contact)?;
            with_bools!(DMG = dmg; {
                // SAFETY: the builder checked the lengths (the damage's where `DMG`), the bodies are checked above.
                unsafe { self.launch::<FinishPlastic<R, D, M, DMG>>(&a) }
            })
        })
    }

    /// The plastic update of every particle (`sph::plastic::plastic_particle`) with the flow-stress `model` (its
    /// parameters go to the GPU by value, with the launch).
    fn plastic_step<'c, R: Real, D: TensorOps<R>>(
        &self,
        n: impl Into<Count<'c, Self>>,
        model: &FlowModel,
        c: PlasticConsts,
        a: PlasticInputs<'_, Self, R, D>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let n = count.n;
        check_len("flags", n, a.flags.len())?;
        if c.taylor_quinney > 0.0 {
            check_bodies(self, "plastic_step materials", n, a.flags, a.materials.map_or(0, |m| m.len()))?;
        }
        let dmg = a.damage.is_some();
        with_model!(model, M, m => {
            let a = args::plastic_args::<_, R, D, M>(self, count, *m, c, a)?;
            with_bools!(DMG = dmg; {
                // SAFETY: the builder checked the lengths (the damage's where `DMG`), the bodies are checked above.
                unsafe { self.launch::<Plastic<R, D, M, DMG>>(&a) }
            })
        })
    }

    /// The contact pass with the rigid tools (`contact::penalty::contact_particle`): parametric tools in 2D or 3D,
    /// mesh tools in 3D; `owner` (several tools only) keeps the tool each particle's friction history belongs to.
    fn contact<'c, R: Real, D: Dim>(
        &self,
        n: impl Into<Count<'c, Self>>,
        tools: &DeviceTools<Self>,
        states: ToolStatesAt<'_, Self>,
        owner: Option<&mut Self::Buf<u32>>,
        a: ContactInputs<'_, Self, R, D>,
    ) -> Result<()> {
        let count: Count<'c, Self> = n.into();
        let n = count.n;
        check_len("flags", n, a.flags.len())?;
        if let Some(m) = a.materials {
            check_bodies(self, "contact materials", n, a.flags, m.len())?;
        }
        match &tools.shapes {
            DeviceShapes::Prism(t) => {
                check_len("tool shapes", tools.count(), t.len())?;
                let t = self.address(t) as *const Tool2d;
                let a = args::contact_args::<_, R, D, D, _>(self, count, tools, t, &states, owner, a)?;
                // SAFETY: the builder checked the lengths, the bodies are checked above.
                unsafe { self.launch::<Contact<R, D, *const Tool2d>>(&a) }
            }
            DeviceShapes::Mesh { meshes, views } => {
                check_len("mesh tools", tools.count(), meshes.len())?;
                check_len("mesh tool views", tools.count() * size_of::<MeshTool>() / 8, views.len())?;
                let t = self.address(views) as *const MeshTool<'static>;
                let a = args::contact_args::<_, R, D, Dim3, _>(self, count, tools, t, &states, owner, a)?;
                // SAFETY: the builder checked the lengths and that the scene is 3D; the meshes' buffers, which
                // the views point into, are live.
                unsafe { self.launch::<Contact<R, Dim3, *const MeshTool<'static>>>(&a) }
            }
        }
    }
}

impl<B: Backend> Passes for B {}
