//! The cell list: hash, counting sort by cell, cell starts, on any backend. The permutation it produces is the
//! stable sort of the particles by cell key, identical on every backend (docs/neighbour-search.md).

use crate::backend::{Backend, CellBuffers, Count, Passes, ScalarsAt, scan_levels};
use crate::kernels::neighbour::GridParams;
use crate::kernels::{Dim, Real};
use crate::{Error, Result};

pub struct CellList<B: Backend> {
    pub grid: GridParams,
    pub grid_buf: B::Buf<GridParams>,
    /// Cell key of each particle, in the order of the positions hashed.
    pub keys: B::Buf<u32>,
    slots: B::Buf<u32>,
    /// Prefix array: bucket c holds sorted particles starts[c] .. starts[c + 1]; buckets are the n_cells cells
    /// and the void bucket (non-finite positions), so it has n_cells + 2 entries; with blanking the n_cells cells
    /// of the active particles, the n_cells of the blanked ones and the void bucket (2 n_cells + 2 entries), and
    /// starts[n_cells] counts the active particles (`GridParams::key_blanked`).
    pub starts: B::Buf<u32>,
    /// perm[i] = the old index of the particle that sorts to position i.
    pub perm: B::Buf<u32>,
    scan: Vec<B::Buf<u32>>,
    /// rebuilds[0]: how many gated rebuilds ran (`CellList::rebuild`).
    pub rebuilds: B::Buf<u32>,
    /// The Verlet list built on these cells (`kernels::neighbour::verlet`), present when the grid has a list
    /// capacity.
    pub list: Option<B::Buf<u32>>,
    n: usize,
    /// Whether the hash blanks the particles outside the step's blanking box.
    blanking: bool,
}

impl<B: Backend> CellList<B> {
    /// A cell list for n particles; with `grid.list_capacity` > 0 also the Verlet list's buffer, its rows n long.
    pub fn new(b: &B, grid: GridParams, n: usize) -> Result<Self> {
        Self::with_blanking(b, grid, n, false)
    }

    /// [`CellList::new`], with `blanking` the buckets of the blanked particles.
    pub fn with_blanking(b: &B, mut grid: GridParams, n: usize, blanking: bool) -> Result<Self> {
        let buckets = buckets(&grid, blanking) + 1;
        let list = if grid.list_capacity > 0 {
            grid.list_stride = u32::try_from(n).map_err(|_| Error::Grid(format!("{n} particles exceed u32")))?;
            Some(b.alloc(grid.list_words(), "Verlet list")?)
        } else {
            grid.list_stride = 0;
            None
        };
        Ok(CellList {
            list,
            grid,
            grid_buf: b.upload(&[grid], "grid")?,
            keys: b.alloc(n, "cell keys")?,
            slots: b.alloc(n, "cell slots")?,
            starts: if blanking {
                // Before the first build every particle counts as active (the first step's predictor runs them
                // all, as without blanking; their rates are zero, so the ones the build then freezes keep their
                // initial state).
                let mut st = vec![0u32; buckets];
                st[grid.n_cells as usize] =
                    u32::try_from(n).map_err(|_| Error::Grid(format!("{n} particles exceed u32")))?;
                b.upload(&st, "cell starts")?
            } else {
                b.alloc(buckets, "cell starts")?
            },
            perm: b.alloc(n, "permutation")?,
            scan: scan_levels(b, buckets)?,
            rebuilds: b.alloc(1, "rebuild count")?,
            n,
            blanking,
        })
    }

    /// The particles the per-particle passes run over: all, or with blanking the active ones (the count the last
    /// build left in starts[n_cells]).
    pub fn count(&self) -> Count<'_, B> {
        span(self.n, self.blanking, &self.starts, &self.grid)
    }

    /// How many particles the last build left active (sorted first): all n without blanking.
    pub fn active_count(&self, b: &B) -> Result<usize> {
        if !self.blanking {
            return Ok(self.n);
        }
        Ok((b.read_one(&self.starts, self.grid.n_cells as usize)? as usize).min(self.n))
    }

    /// Whether the hash blanks particles.
    pub fn blanking(&self) -> bool {
        self.blanking
    }

    pub fn len(&self) -> usize {
        self.n
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Hashes `pos`, sorts by cell and fills `starts` and `perm`. The caller then reorders every particle field
    /// through `perm` (`state::Particles::reorder`).
    pub fn build<R: Real, D: Dim>(&mut self, b: &B, pos: &B::Buf<D::Vec<R>>) -> Result<()> {
        if self.blanking {
            return Err(Error::Grid("a blanking cell list needs its box".into()));
        }
        self.bin::<R, D>(b, pos, None, None, None)
    }

    /// [`CellList::build`] of a blanking cell list, with the box of the step scalars `blank` and the velocities
    /// `vel` its rest speed reads.
    pub fn build_blanked<R: Real, D: Dim>(
        &mut self,
        b: &B,
        pos: &B::Buf<D::Vec<R>>,
        vel: &B::Buf<D::Vec<R>>,
        blank: ScalarsAt<'_, B>,
    ) -> Result<()> {
        self.bin::<R, D>(b, pos, Some(vel), None, Some(blank))
    }

    /// The counting sort of [`CellList::build`] and [`CellList::rebuild`] (gated, and counted in `rebuilds`).
    fn bin<R: Real, D: Dim>(
        &mut self,
        b: &B,
        pos: &B::Buf<D::Vec<R>>,
        vel: Option<&B::Buf<D::Vec<R>>>,
        gate: Option<ScalarsAt<'_, B>>,
        blank: Option<ScalarsAt<'_, B>>,
    ) -> Result<()> {
        let counted = gate.is_some();
        let cells = CellBuffers {
            grid: &self.grid_buf,
            n_buckets: buckets(&self.grid, self.blanking),
            blank: if self.blanking { blank } else { None },
            keys: &mut self.keys,
            slots: &mut self.slots,
            starts: &mut self.starts,
            perm: &mut self.perm,
            scan: &mut self.scan,
            rebuilds: counted.then_some(&mut self.rebuilds),
        };
        b.bin_cells::<R, D>(self.n, gate, pos, vel, cells)
    }

    /// Builds the Verlet list (when there is one) of the sorted particles at `pos` on these cells: after the
    /// reorder of a rebuild (`gate`: only when the step rebuilds), or after [`CellList::build`] on positions
    /// already in its order (no gate).
    pub fn build_list<R: Real, D: Dim>(
        &mut self,
        b: &B,
        pos: &B::Buf<D::Vec<R>>,
        gate: Option<ScalarsAt<'_, B>>,
    ) -> Result<()> {
        match self.list.as_mut() {
            Some(list) => {
                let count = span(self.n, self.blanking, &self.starts, &self.grid);
                b.verlet_build::<R, D>(count, gate, &self.grid_buf, &self.starts, pos, list)
            }
            None => Ok(()),
        }
    }

    /// The build of [`CellList::build`] inside the step loop, run only when the step's rebuild flag `gate` is set
    /// (by the host, or by the predictor's skin test); every launch is submitted either way, so that a captured
    /// step replays with each step's decision.
    /// `vel`: the velocities, which a blanking list's rest speed reads.
    pub fn rebuild<R: Real, D: Dim>(
        &mut self,
        b: &B,
        pos: &B::Buf<D::Vec<R>>,
        vel: &B::Buf<D::Vec<R>>,
        gate: ScalarsAt<'_, B>,
    ) -> Result<()> {
        // The step's own scalars hold its blanking box.
        self.bin::<R, D>(b, pos, Some(vel), Some(gate), Some(gate))
    }
}

impl<B: Backend> CellList<B> {
    /// Neighbour lists (j ≠ i, |x_ij|² < support2) of the particles at `pos`, sorted by this cell list, in CSR
    /// form: a counting pass, a prefix sum, a filling pass. Returns (counts, offsets (n + 1), list); the indices
    /// are sorted-order indices in gather order. The two passes must agree (checked).
    pub fn csr_neighbours<R: Real, D: Dim>(
        &self,
        b: &B,
        pos: &B::Buf<D::Vec<R>>,
        support2: R,
    ) -> Result<(Vec<u32>, Vec<u32>, Vec<u32>)> {
        let n = self.n;
        let mut counts = b.alloc::<u32>(n, "neighbour counts")?;
        let mut empty = b.alloc::<u32>(0, "neighbour list")?;
        b.neighbour_list::<R, D>(n, pos, &self.grid_buf, &self.starts, support2, None, &mut counts, &mut empty)?;
        let first = b.read(&counts)?;
        let mut off = vec![0u32; n + 1];
        for i in 0..n {
            off[i + 1] = off[i] + first[i];
        }
        let offsets = b.upload(&off, "neighbour offsets")?;
        let mut list = b.alloc::<u32>(off[n] as usize, "neighbour list")?;
        b.neighbour_list::<R, D>(
            n,
            pos,
            &self.grid_buf,
            &self.starts,
            support2,
            Some(&offsets),
            &mut counts,
            &mut list,
        )?;
        let second = b.read(&counts)?;
        if first != second {
            return Err(crate::Error::Grid("the counting and filling passes of the neighbour lists disagree".into()));
        }
        Ok((second, off, b.read(&list)?))
    }
}

/// The particles of a cell list's passes ([`CellList::count`]; a function of its fields, so that a caller holding
/// another field mutably can build it).
fn span<'a, B: Backend>(n: usize, blanking: bool, starts: &'a B::Buf<u32>, grid: &GridParams) -> Count<'a, B> {
    Count { n, active: blanking.then_some((starts, grid.n_cells as usize)) }
}

/// The buckets of a cell list: the grid's cells and the void bucket, with blanking the cells twice
/// (`GridParams::key_blanked`).
pub fn buckets(grid: &GridParams, blanking: bool) -> usize {
    grid.n_cells as usize * if blanking { 2 } else { 1 } + 1
}

/// Whether the Verlet list stores 32-bit offsets (`GridParams::list_wide`): as the scene's `verlet_offsets` says,
/// else in 3D once the particles outnumber the 16-bit offset's reach. A 3D stencil spans two layers of nx·ny cells
/// in the sorted order, so beyond that count whole regions of a large 3D domain would have far rows and walk the
/// stencil (docs/neighbour-search.md, "Wide offsets"); a 2D stencil spans a few cell rows, within reach in any
/// scene narrower than about 10 000 Δx, where the packed list's half traffic pays.
pub fn wide_offsets(bits: Option<u32>, dim: usize, n: usize) -> bool {
    match bits {
        Some(b) => b == 32,
        None => dim == 3 && n > crate::kernels::neighbour::verlet::MAX_OFFSET as usize,
    }
}

/// The Verlet list's capacity per particle for a grid and the lattice spacing Δx: twice the count of a lattice of
/// that spacing within the list radius R, 2 ω_d (R/Δx)^d with ω_2 = π, ω_3 = 4π/3 (the lattices of `cases/` hold
/// about half that), plus 8. A particle with more candidates walks the stencil, so the capacity decides the memory,
/// never the result. 0 (no list) without a positive finite spacing.
pub fn verlet_capacity(grid: &GridParams, dx: f64) -> u32 {
    if !(dx.is_finite() && dx > 0.0) {
        return 0;
    }
    let d = grid.dim.clamp(2, 3) as i32;
    let ratio = grid.list_radius2().sqrt() / dx;
    let omega = if d == 3 { 4.0 / 3.0 * std::f64::consts::PI } else { std::f64::consts::PI };
    let k = 2.0 * omega * ratio.powi(d) + 8.0;
    // Far beyond any lattice: the list would cost more memory than it saves; the stencil serves.
    if k > 4096.0 { 0 } else { k.ceil() as u32 }
}
