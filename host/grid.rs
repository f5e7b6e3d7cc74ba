//! Building the hash grid on the host from a bounding box (the theses' "locked" grid: a fixed box that contains
//! the domain, roethlin-solver.md §6.4). Particles that leave it are clamped into the boundary cells, which keeps
//! the search exact (kernels::neighbour::grid).

use crate::kernels::neighbour::GridParams;
use crate::kernels::{Real, Vector};
use crate::{Error, Result};

/// Largest cell count: keys are u32 and the prefix array holds n_cells + 2 entries.
pub const MAX_CELLS: u64 = (u32::MAX - 2) as u64;

/// A grid over [lo, hi] (the first `dim` components) with the given cell size and stencil half-width.
pub fn grid_with_cell(lo: [f64; 3], hi: [f64; 3], dim: usize, cell: f64, stencil: u32) -> Result<GridParams> {
    if !(dim == 2 || dim == 3) {
        return Err(Error::Grid(format!("dimension must be 2 or 3, got {dim}")));
    }
    if !(cell.is_finite() && cell > 0.0) {
        return Err(Error::Grid(format!("cell size must be positive and finite, got {cell}")));
    }
    if !(1..=3).contains(&stencil) {
        return Err(Error::Grid(format!(
            "stencil must be 1 (cell 2h), 2 (cell h) or 3 (cell h, PSE conduction to 3h), got {stencil}"
        )));
    }
    let mut dims = [1u32; 3];
    let mut total: u64 = 1;
    for k in 0..dim {
        let (a, b) = (lo[k], hi[k]);
        if !(a.is_finite() && b.is_finite() && b >= a) {
            return Err(Error::Grid(format!("bounding box axis {k} is [{a}, {b}]")));
        }
        let n = ((b - a) / cell).floor() as u64 + 1;
        total = total.saturating_mul(n);
        if n > u32::MAX as u64 || total > MAX_CELLS {
            return Err(Error::Grid(format!(
                "{total} cells of size {cell:e} over the box exceed the limit of {MAX_CELLS}; enlarge h or shrink the box"
            )));
        }
        dims[k] = n as u32;
    }
    Ok(GridParams {
        origin: [lo[0], lo[1], if dim == 3 { lo[2] } else { 0.0 }],
        cell_size: cell,
        inv_cell: 1.0 / cell,
        skin: 0.0,
        period: 0.0,
        inv_period: 0.0,
        dims,
        n_cells: total as u32,
        stencil,
        dim: dim as u32,
        list_capacity: 0,
        list_stride: 0,
        list_wide: 0,
        _pad: 0,
    })
}

/// A grid for pairs within `support_radius` (2h for the cubic spline): cell = support/stencil, slightly enlarged
/// (`GridParams::cell_for`).
pub fn grid_for_support(
    lo: [f64; 3],
    hi: [f64; 3],
    dim: usize,
    support_radius: f64,
    stencil: u32,
) -> Result<GridParams> {
    if !(support_radius.is_finite() && support_radius > 0.0) {
        return Err(Error::Grid(format!("support radius must be positive and finite, got {support_radius}")));
    }
    grid_with_cell(lo, hi, dim, GridParams::cell_for(support_radius, stencil.max(1)), stencil)
}

/// The solver's grid: the ±2 stencil over cells sized for the support radius plus the skin s, so that the cell
/// list stays exact until some particle has moved s from where it was binned (`GridParams::beyond_skin`).
pub fn grid_with_skin(lo: [f64; 3], hi: [f64; 3], dim: usize, support_radius: f64, skin: f64) -> Result<GridParams> {
    if !(skin.is_finite() && skin >= 0.0) {
        return Err(Error::Grid(format!("the skin must be finite and non-negative, got {skin}")));
    }
    let mut g = grid_for_support(lo, hi, dim, support_radius + skin, 2)?;
    g.skin = skin;
    Ok(g)
}

/// `g` made periodic in z with period `period` (3D): its cells grow to the smallest size ≥ its own that tiles the
/// period exactly, P / ⌊P / cell⌋ (x and y re-tiled over the same box), and the period needs at least 2s + 1 such
/// cells for the stencil's wrapped rows to be distinct (s: the stencil), which also keeps every pair within the
/// support to one image (P > 2 · support).
pub fn periodic_z(g: &GridParams, hi: [f64; 3], period: f64) -> Result<GridParams> {
    if g.dim != 3 {
        return Err(Error::Grid("a period in z needs a 3D grid".into()));
    }
    let cells = (period / g.cell_size).floor();
    let need = 2 * g.stencil + 1;
    if !(period.is_finite() && cells >= need as f64) {
        return Err(Error::Grid(format!(
            "the period in z, {period:e} m, must hold at least {need} cells of {:e} m (2h + skin over the stencil \
             {}): {:e} m or more",
            g.cell_size,
            g.stencil,
            need as f64 * g.cell_size
        )));
    }
    let cell = period / cells;
    let lo = g.origin;
    let mut p = grid_with_cell(lo, [hi[0], hi[1], lo[2]], 3, cell, g.stencil)?;
    p.dims[2] = cells as u32;
    let total = p.dims.iter().map(|&d| d as u64).product::<u64>();
    if total > MAX_CELLS {
        return Err(Error::Grid(format!("{total} cells exceed the limit of {MAX_CELLS}")));
    }
    p.n_cells = total as u32;
    p.skin = g.skin;
    p.period = period;
    p.inv_period = 1.0 / period;
    p.list_capacity = g.list_capacity;
    p.list_stride = g.list_stride;
    p.list_wide = g.list_wide;
    Ok(p)
}

/// Bounding box of the finite positions (zero box if there are none).
pub fn bounding_box<R: Real, V: Vector<R>>(pos: &[V]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in pos {
        let c: [f64; 3] = std::array::from_fn(|k| p.get(k).to_f64());
        if c.iter().all(|x| x.is_finite()) {
            for k in 0..3 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
    }
    if lo[0] > hi[0] {
        return ([0.0; 3], [0.0; 3]);
    }
    (lo, hi)
}
