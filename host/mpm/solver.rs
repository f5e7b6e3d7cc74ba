//! The MPM state on a backend and its step (docs/mpm.md): the particles' and nodes' buffers, the cell list on the
//! grid's cells, and the passes of `kernels::mpm::step` launched in order. The host computes only the
//! step's tool and grip motion; every per-particle, per-node and per-crack-point number comes from the kernels.

use super::setup::{MpmSetup, Ramp};
use crate::backend::Backend;
use crate::kernels::cohesive::{CrackState, FAILED};
use crate::kernels::mpm::grid::{MpmParams, MpmStep};
use crate::kernels::mpm::step::{Cells, Crack, KE_TILE, Nodes, Particles};
use crate::kernels::neighbour::GridParams;
use crate::kernels::pass::mpm::{
    CrackArgs, CrackPass, FeedbackArgs, FeedbackPass, G2p, G2pArgs, KeArgs, KePass, NodesArgs, NodesPass, P2g, P2gArgs,
};
use crate::kernels::{Dim2, Real, SymTensor, Vector};
use crate::neighbour::CellList;
use crate::solver::StateBlobs;
use crate::state::load_blob;
use crate::{Error, Result};

/// The particles' buffers.
pub struct ParticleBufs<B: Backend, R: Real> {
    pub pos: B::Buf<R::V2>,
    pub ref_pos: B::Buf<R::V2>,
    pub vel: B::Buf<R::V2>,
    pub be: B::Buf<R::S2>,
    pub jac: B::Buf<R>,
    pub eps: B::Buf<R>,
    pub stress: B::Buf<R::S2>,
    pub mass: B::Buf<R>,
    pub vol0: B::Buf<R>,
    pub kind: B::Buf<u32>,
    pub fext: B::Buf<R::V2>,
    /// The deformation gradient F (xx, xy, yx, yy).
    pub def: B::Buf<[R; 4]>,
}

/// The nodes' buffers (two specimen fields per node where `kernels::mpm::step::Nodes` says so).
pub struct NodeBufs<B: Backend, R: Real> {
    pub mass: B::Buf<R>,
    pub mom: B::Buf<R::V2>,
    pub force: B::Buf<R::V2>,
    pub vol: B::Buf<R>,
    pub tool_vol: B::Buf<R>,
    pub vel: B::Buf<R::V2>,
    pub acc: B::Buf<R::V2>,
    pub vel1: B::Buf<R::V2>,
    pub imp_tool: B::Buf<[f64; 2]>,
    pub imp_grip: B::Buf<[f64; 2]>,
    pub work_grip: B::Buf<f64>,
    pub ke: B::Buf<f64>,
    pub ke_tiles: B::Buf<f64>,
    pub damping: B::Buf<f64>,
}

/// The crack points' buffers.
pub struct CrackBufs<B: Backend, R: Real> {
    pub state: B::Buf<CrackState<R>>,
    pub pair: B::Buf<[u32; 2]>,
}

/// The stateful buffers of [`MpmSolver`], each once: `$m!(name, path)` for each.
macro_rules! mpm_state {
    ($m:ident) => {
        $m!("pos", parts.pos);
        $m!("vel", parts.vel);
        $m!("be", parts.be);
        $m!("jac", parts.jac);
        $m!("eps", parts.eps);
        $m!("stress", parts.stress);
        $m!("fext", parts.fext);
        $m!("def", parts.def);
        $m!("crack_state", crack.state);
        $m!("imp_tool", nodes.imp_tool);
        $m!("imp_grip", nodes.imp_grip);
        $m!("work_grip", nodes.work_grip);
        $m!("damping", nodes.damping);
    };
}

/// Steps in a captured batch ([`MpmSolver::advance`]).
pub const BATCH: usize = 50;

/// An MPM run's state.
pub struct MpmSolver<B: Backend, R: Real> {
    pub params: MpmParams,
    pub tool: Option<(Ramp, [f64; 2])>,
    pub grip: Option<Ramp>,
    pub parts: ParticleBufs<B, R>,
    pub nodes: NodeBufs<B, R>,
    pub crack: CrackBufs<B, R>,
    /// flags[0]: a particle went non-finite; flags[1]: one left the grid.
    pub flags: B::Buf<u32>,
    pub cells: CellList<B>,
    /// The motions of the steps of a batch, one entry each (`MpmStep`), written before the batch runs.
    steps_table: B::Buf<MpmStep>,
    /// The captured batches of [`BATCH`] steps (CUDA graphs), made at the first batch of each kind: without and
    /// with the start-up damping's passes ([`MpmSolver::damping_live`]); `graphs` false
    /// (`SWARF_NO_GRAPHS=1`): steps one by one.
    graph: [Option<B::Graph>; 2],
    graphs: bool,
    /// Whether a step has run plainly (so that every kernel a batch launches is loaded).
    warm: bool,
    pub dt: f64,
    /// The PIC fraction 1 − β.
    pub pic: f64,
    /// The start-up damping's gain during the ramp (`MpmSetup::feedback`) and the ramp's end [s] (0: none).
    feedback: f64,
    ramp_end: f64,
    pub time: f64,
    pub steps: u64,
    n: usize,
    n_nodes: usize,
}

fn narrow2<R: Real>(x: [f64; 2]) -> R::V2 {
    <R::V2 as Vector<R>>::new([R::from_f64(x[0]), R::from_f64(x[1]), R::ZERO])
}

impl<B: Backend, R: Real> MpmSolver<B, R> {
    /// Allocates and uploads the state of `s`, PIC fraction `pic`.
    pub fn new(b: &B, s: &MpmSetup, pic: f64) -> Result<Self> {
        let p = &s.params;
        let n = s.points.pos.len();
        let n_nodes = p.nodes[0] as usize * p.nodes[1] as usize;
        let pos: Vec<R::V2> = s.points.pos.iter().map(|&x| narrow2::<R>(x)).collect();
        let mut identity = R::S2::default();
        identity.components_mut().copy_from_slice(&[R::ONE, R::ZERO, R::ONE, R::ONE]);
        let r = |v: &[f64]| v.iter().map(|&x| R::from_f64(x)).collect::<Vec<R>>();
        let parts = ParticleBufs {
            pos: b.upload(&pos, "mpm positions")?,
            ref_pos: b.upload(&pos, "mpm reference positions")?,
            vel: b.alloc(n, "mpm velocities")?,
            be: b.upload(&vec![identity; n], "mpm B_e")?,
            jac: b.upload(&vec![R::ONE; n], "mpm J")?,
            eps: b.alloc(n, "mpm plastic strain")?,
            stress: b.alloc(n, "mpm stress")?,
            mass: b.upload(&r(&s.points.mass), "mpm masses")?,
            vol0: b.upload(&r(&s.points.vol), "mpm volumes")?,
            kind: b.upload(&s.points.kind, "mpm kinds")?,
            fext: b.alloc(n, "mpm cohesive forces")?,
            def: b.upload(&vec![[R::ONE, R::ZERO, R::ZERO, R::ONE]; n], "mpm deformation gradients")?,
        };
        let nodes = NodeBufs {
            mass: b.alloc(2 * n_nodes, "mpm node mass")?,
            mom: b.alloc(2 * n_nodes, "mpm node momentum")?,
            force: b.alloc(2 * n_nodes, "mpm node force")?,
            vol: b.alloc(2 * n_nodes, "mpm node volume")?,
            tool_vol: b.alloc(n_nodes, "mpm node tool volume")?,
            vel: b.alloc(2 * n_nodes, "mpm node velocity")?,
            acc: b.alloc(2 * n_nodes, "mpm node acceleration")?,
            vel1: b.alloc(2 * n_nodes, "mpm node end velocity")?,
            imp_tool: b.alloc(n_nodes, "mpm tool impulse")?,
            imp_grip: b.alloc(n_nodes, "mpm grip impulse")?,
            work_grip: b.alloc(n_nodes, "mpm grip work")?,
            ke: b.alloc(n_nodes, "mpm node kinetic energy")?,
            ke_tiles: b.alloc(n_nodes.div_ceil(KE_TILE), "mpm kinetic energy tiles")?,
            damping: b.alloc(1, "mpm start-up damping")?,
        };
        let nc = p.crack_points as usize;
        let state: Vec<CrackState<R>> = (0..nc)
            .map(|k| {
                let failed = p.crack_x(k as u32) < s.starter_end;
                let mut st = [R::ZERO; 4];
                st[FAILED] = if failed { R::ONE } else { R::ZERO };
                st
            })
            .collect();
        let crack =
            CrackBufs { state: b.upload(&state, "mpm crack state")?, pair: b.upload(&s.pairs, "mpm crack pairs")? };
        let cells = CellList::new(b, cell_grid(p)?, n)?;
        let steps_table = b.alloc(BATCH, "mpm step table")?;
        Ok(MpmSolver {
            params: *p,
            tool: s.tool,
            grip: s.grip,
            parts,
            nodes,
            crack,
            flags: b.alloc(2, "mpm flags")?,
            cells,
            steps_table,
            graph: [None, None],
            warm: false,
            graphs: !crate::tuning::Tuning::current()?.no_graphs,
            dt: s.dt,
            pic,
            feedback: s.feedback,
            ramp_end: s.driving_ramp().map_or(0.0, |r| r.ramp),
            time: 0.0,
            steps: 0,
            n,
            n_nodes,
        })
    }

    pub fn particles(&self) -> usize {
        self.n
    }

    pub fn node_count(&self) -> usize {
        self.n_nodes
    }

    /// The motions of the step that starts at t: the tool's velocity at mid-step (exact for the linear ramp), its
    /// displacement at the step's end and its edge at the step's start; the grip's mid-step velocity.
    pub fn step_params(&self, t: f64) -> MpmStep {
        let dt = self.dt;
        let mut s =
            MpmStep { dt, alpha_pic: self.pic / dt, tool_tip: [f64::INFINITY, f64::INFINITY], ..Default::default() };
        if let Some((ramp, tip)) = self.tool {
            s.tool_vel = ramp.velocity(t + 0.5 * dt);
            s.tool_disp = ramp.displacement(t + dt);
            let d = ramp.displacement(t);
            s.tool_tip = [tip[0] + d[0], tip[1] + d[1]];
        }
        if let Some(g) = self.grip {
            s.pull_vel = g.velocity(t + 0.5 * dt);
        }
        // The start-up damping acts while the driving ramp (the tool's, else the grip's) is under way.
        if t + dt <= self.ramp_end {
            s.feedback = self.feedback;
        }
        s
    }

    /// Whether the step that starts at t runs the start-up damping's passes: a step of the ramp, or the first
    /// after it, which resets the damping to 0 (`kernels::mpm::step::feedback`); later steps need not.
    fn damping_live(&self, t: f64) -> bool {
        self.feedback > 0.0 && t <= self.ramp_end
    }

    /// One step.
    pub fn step(&mut self, b: &B) -> Result<()> {
        let s = self.step_params(self.time);
        b.write(&mut self.steps_table, &[s])?;
        self.launch_step(b, 0, self.damping_live(self.time))?;
        self.warm = true;
        self.time += self.dt;
        self.steps += 1;
        Ok(())
    }

    /// `count` steps: batches of [`BATCH`] steps replayed from one captured graph (each batch's motions written
    /// to the step table first), the rest one by one. The same launches with the same arguments as single steps,
    /// so the same bits.
    pub fn advance(&mut self, b: &B, mut count: u64) -> Result<()> {
        // The CUDA backend loads a kernel at its first launch, which a capture may not hold: one plain step first
        // (also in a solver restored from a checkpoint).
        if !self.warm && count > 0 {
            self.step(b)?;
            count -= 1;
        }
        while self.graphs && count >= BATCH as u64 {
            let mut t = self.time;
            let mut table = Vec::with_capacity(BATCH);
            for _ in 0..BATCH {
                table.push(self.step_params(t));
                t += self.dt;
            }
            b.write(&mut self.steps_table, &table)?;
            let live = self.damping_live(self.time);
            match self.graph[live as usize].take() {
                Some(g) => {
                    b.replay(&g)?;
                    self.graph[live as usize] = Some(g);
                }
                None => {
                    let mut run = || -> Result<()> { (0..BATCH).try_for_each(|j| self.launch_step(b, j, live)) };
                    // A backend without graphs ran the steps; a capture only recorded them, so the graph runs now.
                    if let Some(g) = b.capture(&mut run)? {
                        b.replay(&g)?;
                        self.graph[live as usize] = Some(g);
                    }
                }
            }
            for _ in 0..BATCH {
                self.time += self.dt;
            }
            self.steps += BATCH as u64;
            count -= BATCH as u64;
        }
        for _ in 0..count {
            self.step(b)?;
        }
        Ok(())
    }

    /// The launches of one step whose motions are entry `j` of the step table: the cell list, the crack, the node
    /// gather, the node update, the start-up damping's passes (where `damping`), the particle update.
    fn launch_step(&mut self, b: &B, j: usize, damping: bool) -> Result<()> {
        self.cells.build::<R, Dim2>(b, &self.parts.pos)?;
        let step = (b.address(&self.steps_table) as *const MpmStep).wrapping_add(j);
        let (params, parts, nodes, crack) = (self.params, self.particle_ptrs(b), self.node_ptrs(b), self.crack_ptrs(b));
        let cells = Cells {
            starts: b.address(&self.cells.starts) as *const u32,
            perm: b.address(&self.cells.perm) as *const u32,
        };
        let n_nodes = self.n_nodes as u32;
        // SAFETY: every pointer names a buffer of this solver, allocated in `new` with the lengths the passes
        // read (n particles, 2 fields of n_nodes nodes, the crack's points, two flag words, BATCH > j steps).
        unsafe {
            if params.crack_points > 0 {
                b.launch::<CrackPass<R>>(&CrackArgs { n: params.crack_points, _pad: 0, params, parts, crack })?;
            }
            b.launch::<P2g<R>>(&P2gArgs { n: n_nodes, _pad: 0, params, parts, cells, nodes })?;
            b.launch::<NodesPass<R>>(&NodesArgs { n: n_nodes, _pad: 0, params, step, nodes })?;
            if damping {
                let tiles = n_nodes.div_ceil(KE_TILE as u32);
                b.launch::<KePass<R>>(&KeArgs { n: tiles, nodes_n: n_nodes, nodes })?;
                b.launch::<FeedbackPass<R>>(&FeedbackArgs { n: 1, tiles, step, nodes })?;
            }
            let flags = b.address_mut(&mut self.flags) as *mut u32;
            b.launch::<G2p<R>>(&G2pArgs { n: self.n as u32, _pad: 0, params, step, parts, nodes, flags })?;
        }
        Ok(())
    }

    /// Copies of every buffer that carries state from one step to the next, named, for a checkpoint: the
    /// particles' state, the crack points' histories, the tallies and the start-up damping. The nodes' sums, the
    /// cell list and the step table are rebuilt by every step, and the rest is the set-up's.
    pub fn save_state(&self, b: &B) -> Result<StateBlobs> {
        let mut out: StateBlobs = Vec::new();
        macro_rules! save {
            ($name:literal, $($buf:ident).+) => {
                out.push(($name.to_string(), bytemuck::cast_slice::<_, u8>(&b.read(&self.$($buf).+)?).to_vec()));
            };
        }
        mpm_state!(save);
        Ok(out)
    }

    /// Restores the buffers of [`MpmSolver::save_state`] (the solver built from the same scene); the clock is the
    /// caller's.
    pub fn load_state(&mut self, b: &B, blobs: &StateBlobs) -> Result<()> {
        macro_rules! load {
            ($name:literal, $($buf:ident).+) => {
                load_blob(b, $name, &mut self.$($buf).+, blobs)?;
            };
        }
        mpm_state!(load);
        Ok(())
    }

    /// The flags of the steps since the last call (non-finite, escaped), cleared.
    pub fn take_flags(&mut self, b: &B) -> Result<(bool, bool)> {
        let f = b.read(&self.flags)?;
        if f.iter().any(|&x| x != 0) {
            b.fill_zero(&mut self.flags, 2)?;
        }
        Ok((f[0] != 0, f[1] != 0))
    }

    fn particle_ptrs(&mut self, b: &B) -> Particles<R> {
        let p = &mut self.parts;
        Particles {
            pos: b.address_mut(&mut p.pos) as *mut R::V2,
            ref_pos: b.address(&p.ref_pos) as *const R::V2,
            vel: b.address_mut(&mut p.vel) as *mut R::V2,
            be: b.address_mut(&mut p.be) as *mut R::S2,
            jac: b.address_mut(&mut p.jac) as *mut R,
            eps: b.address_mut(&mut p.eps) as *mut R,
            stress: b.address_mut(&mut p.stress) as *mut R::S2,
            mass: b.address(&p.mass) as *const R,
            vol0: b.address(&p.vol0) as *const R,
            kind: b.address(&p.kind) as *const u32,
            fext: b.address_mut(&mut p.fext) as *mut R::V2,
            def: b.address_mut(&mut p.def) as *mut [R; 4],
        }
    }

    fn node_ptrs(&mut self, b: &B) -> Nodes<R> {
        let n = &mut self.nodes;
        Nodes {
            mass: b.address_mut(&mut n.mass) as *mut R,
            mom: b.address_mut(&mut n.mom) as *mut R::V2,
            force: b.address_mut(&mut n.force) as *mut R::V2,
            vol: b.address_mut(&mut n.vol) as *mut R,
            tool_vol: b.address_mut(&mut n.tool_vol) as *mut R,
            vel: b.address_mut(&mut n.vel) as *mut R::V2,
            acc: b.address_mut(&mut n.acc) as *mut R::V2,
            vel1: b.address_mut(&mut n.vel1) as *mut R::V2,
            imp_tool: b.address_mut(&mut n.imp_tool) as *mut [f64; 2],
            imp_grip: b.address_mut(&mut n.imp_grip) as *mut [f64; 2],
            work_grip: b.address_mut(&mut n.work_grip) as *mut f64,
            ke: b.address_mut(&mut n.ke) as *mut f64,
            ke_tiles: b.address_mut(&mut n.ke_tiles) as *mut f64,
            damping: b.address_mut(&mut n.damping) as *mut f64,
        }
    }

    fn crack_ptrs(&mut self, b: &B) -> Crack<R> {
        let c = &mut self.crack;
        Crack { state: b.address_mut(&mut c.state) as *mut CrackState<R>, pair: b.address(&c.pair) as *const [u32; 2] }
    }

    /// The impulses the tool and the grip gave the specimen since t = 0 and the grip's work,
    /// summed over the nodes in node order (the same sums on every backend).
    pub fn tallies(&self, b: &B) -> Result<Tallies> {
        let sum = |v: Vec<[f64; 2]>| v.iter().fold([0.0; 2], |a, x| [a[0] + x[0], a[1] + x[1]]);
        Ok(Tallies {
            tool: sum(b.read(&self.nodes.imp_tool)?),
            grip: sum(b.read(&self.nodes.imp_grip)?),
            work: b.read(&self.nodes.work_grip)?.iter().sum(),
        })
    }
}

/// The running sums of [`MpmSolver::tallies`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tallies {
    /// Σ Δp of the tool's contact on the specimen [N s/m].
    pub tool: [f64; 2],
    /// Σ Δp of the grip [N s/m].
    pub grip: [f64; 2],
    /// Σ Δp·v of the grip [J/m].
    pub work: f64,
}

/// The cell list's grid: the MPM grid's cells, x fastest.
fn cell_grid(p: &MpmParams) -> Result<GridParams> {
    let [cx, cy] = p.cells();
    let n_cells = (cx as u64) * (cy as u64);
    if n_cells == 0 || n_cells >= u32::MAX as u64 / 2 {
        return Err(Error::Grid(format!("{cx} x {cy} MPM cells: expected 1 to 2^31")));
    }
    Ok(GridParams {
        origin: [p.origin[0], p.origin[1], 0.0],
        cell_size: p.dx,
        inv_cell: 1.0 / p.dx,
        skin: 0.0,
        period: 0.0,
        inv_period: 0.0,
        dims: [cx, cy, 1],
        n_cells: n_cells as u32,
        stencil: 1,
        dim: 2,
        list_capacity: 0,
        list_stride: 0,
        list_wide: 0,
        _pad: 0,
    })
}
