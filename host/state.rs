//! Particle state as a structure of arrays: one buffer per field, in the run's dimension and precision, on the
//! host (`HostParticles`) or in a backend's memory (`Particles`), moved between the two with bytemuck.
//! Fields follow roethlin-solver.md §5.1; physics-specific fields join as their issues land, each allocated only
//! when its physics is on.

use crate::Result;
use crate::backend::{Backend, Element, ScalarsAt};
use crate::kernels::neighbour::GatherField;
use crate::kernels::{Dim, Real};

/// A field in backend memory with a spare buffer: a reorder gathers into the spare (Green's double-buffering,
/// roethlin-solver.md §6.4), then swaps (`Field::reorder`) or, inside the step loop, copies back
/// (`Field::stage`), which keeps the addresses a captured step was recorded with.
pub struct Field<B: Backend, T: Element> {
    pub cur: B::Buf<T>,
    spare: B::Buf<T>,
}

impl<B: Backend, T: Element> Field<B, T> {
    pub fn upload(b: &B, data: &[T], what: &'static str) -> Result<Self> {
        Ok(Field { cur: b.upload(data, what)?, spare: b.alloc(data.len(), what)? })
    }

    /// cur ← cur[perm], through the spare buffer.
    pub fn reorder(&mut self, b: &B, n: usize, perm: &B::Buf<u32>) -> Result<()> {
        b.gather(n, perm, &self.cur, &mut self.spare)?;
        std::mem::swap(&mut self.cur, &mut self.spare);
        Ok(())
    }

    /// Adds this field to a batch reordered in place (`ReorderBatch::run`): gathered into the spare buffer, then
    /// copied back, so that `cur` keeps its address and a captured step stays valid whether or not it rebuilds.
    pub fn stage(&mut self, b: &B, batch: &mut ReorderBatch) {
        let (cur, spare) = (b.address(&self.cur), b.address_mut(&mut self.spare));
        let bytes = size_of::<T>() as u32;
        batch.push(GatherField { src: cur, dst: spare, bytes, _pad: 0 }, true);
    }

    pub fn read(&self, b: &B) -> Result<Vec<T>> {
        b.read(&self.cur)
    }
}

/// Most fields one reorder launch moves (the table goes to the device as long as the batch, so the cap is the
/// host's: tests/fields.rs checks that every reordered field the registry can hold at once fits).
pub const MAX_REORDER: usize = 40;

/// Fields staged for one fused in-place reorder (fixed capacity: the step loop allocates nothing): one launch
/// gathers every field into its spare buffer, a second copies the spares back.
pub struct ReorderBatch {
    gather: [GatherField; MAX_REORDER],
    copy: [GatherField; MAX_REORDER],
    len: usize,
    copies: usize,
}

impl Default for ReorderBatch {
    fn default() -> Self {
        ReorderBatch {
            gather: [GatherField::default(); MAX_REORDER],
            copy: [GatherField::default(); MAX_REORDER],
            len: 0,
            copies: 0,
        }
    }
}

impl ReorderBatch {
    /// Stages the gather `f` (and, with `copy_back`, the copy of its destination back to its source).
    fn push(&mut self, f: GatherField, copy_back: bool) {
        if self.len < MAX_REORDER {
            self.gather[self.len] = f;
        }
        self.len += 1;
        if copy_back {
            if self.copies < MAX_REORDER {
                self.copy[self.copies] = GatherField { src: f.dst, dst: f.src, ..f };
            }
            self.copies += 1;
        }
    }

    /// Stages the gather of `src` into `dst` without a copy back: `dst` receives the reordered `src` (the
    /// positions where the cell list binned each particle).
    pub fn snapshot<B: Backend, T: Element>(&mut self, b: &B, src: &B::Buf<T>, dst: &mut B::Buf<T>) {
        let bytes = size_of::<T>() as u32;
        self.push(GatherField { src: b.address(src), dst: b.address_mut(dst), bytes, _pad: 0 }, false);
    }

    /// Reorders every staged field through `perm` in place, when the step `gate` rebuilds (two launches), and
    /// empties the batch.
    pub fn run<B: Backend>(&mut self, b: &B, n: usize, perm: &B::Buf<u32>, gate: ScalarsAt<'_, B>) -> Result<()> {
        let (len, copies) = (std::mem::take(&mut self.len), std::mem::take(&mut self.copies));
        let too_many = |got| crate::Error::Length { op: "reorder batch (too many fields)", expected: MAX_REORDER, got };
        let gather = self.gather.get(..len).ok_or(too_many(len))?;
        let copy = self.copy.get(..copies).ok_or(too_many(copies))?;
        // SAFETY: every entry was staged from two distinct live buffers of at least n elements (a Field's pair,
        // or a snapshot's source and destination); the copies run after the gathers complete.
        unsafe {
            b.gather_fields(n, Some(perm), gather, Some(gate))?;
            b.gather_fields(n, None, copy, Some(gate))
        }
    }
}

/// Writes the saved bytes named `name` into `buf`, refusing a missing field or a length that does not fit.
pub fn load_blob<B: Backend, T: Element>(
    b: &B,
    name: &str,
    buf: &mut B::Buf<T>,
    blobs: &[(String, Vec<u8>)],
) -> Result<()> {
    use crate::backend::Buffer;
    let bytes = blobs
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, v)| v)
        .ok_or_else(|| crate::Error::Checkpoint(format!("field '{name}' missing")))?;
    if bytes.len() != buf.len() * size_of::<T>() {
        return Err(crate::Error::Checkpoint(format!(
            "field '{name}' has {} bytes, the scene needs {}",
            bytes.len(),
            buf.len() * size_of::<T>()
        )));
    }
    let v: Vec<T> = bytemuck::pod_collect_to_vec(bytes);
    b.write(buf, &v)
}

/// Declares the particle fields once; upload, download and reorder are generated from the list. The solver's
/// in-place reorder and checkpoint go through its field registry (`solver::fields`), which lists these fields
/// with every other per-particle buffer.
macro_rules! particle_fields {
    ($( $(#[$doc:meta])* $name:ident : $t:ty ),* $(,)?) => {
        /// Particle state on the host.
        #[derive(Clone, Debug, Default)]
        pub struct HostParticles<R: Real, D: Dim> {
            $( $(#[$doc])* pub $name: Vec<$t>, )*
        }

        /// Particle state in a backend's memory.
        pub struct Particles<B: Backend, R: Real, D: Dim> {
            pub n: usize,
            $( $(#[$doc])* pub $name: Field<B, $t>, )*
        }

        impl<R: Real, D: Dim> HostParticles<R, D> {
            /// The fields' names, as declared (each is also an entry of the solver's field registry).
            pub const FIELD_NAMES: &[&str] = &[$( stringify!($name) ),*];

            /// Number of particles; every field has this length.
            pub fn len(&self) -> usize {
                self.id.len()
            }
            pub fn is_empty(&self) -> bool {
                self.id.is_empty()
            }
            /// Checks that every field has the same length.
            pub fn check(&self) -> std::result::Result<(), String> {
                let n = self.len();
                $( if self.$name.len() != n {
                    return Err(format!("field {} has {} entries, expected {n}", stringify!($name), self.$name.len()));
                } )*
                Ok(())
            }
            /// Bitwise equality of every field (NaN payloads included): the GPU-against-CPU criterion.
            pub fn bitwise_eq(&self, o: &Self) -> bool {
                true $( && bytemuck::cast_slice::<_, u8>(&self.$name) == bytemuck::cast_slice::<_, u8>(&o.$name) )*
            }
            /// Bytes of state per particle.
            pub fn bytes_per_particle() -> usize {
                0 $( + size_of::<$t>() )*
            }
        }

        impl<B: Backend, R: Real, D: Dim> Particles<B, R, D> {
            pub fn upload(b: &B, h: &HostParticles<R, D>) -> Result<Self> {
                h.check().map_err(crate::Error::Grid)?;
                Ok(Particles { n: h.len(), $( $name: Field::upload(b, &h.$name, stringify!($name))?, )* })
            }

            pub fn download(&self, b: &B) -> Result<HostParticles<R, D>> {
                Ok(HostParticles { $( $name: self.$name.read(b)?, )* })
            }

            /// Reorders every field through one permutation (`CellList::perm`).
            pub fn reorder(&mut self, b: &B, perm: &B::Buf<u32>) -> Result<()> {
                $( self.$name.reorder(b, self.n, perm)?; )*
                Ok(())
            }
        }
    };
}

particle_fields! {
    /// Index of the particle in the scene as built; follows the particle through every reorder.
    id: u32,
    /// Bit flags (fixed, tool, material index; defined with the solver).
    flags: u32,
    pos: D::Vec<R>,
    vel: D::Vec<R>,
    mass: R,
    rho: R,
    /// Deviatoric stress S: 2D (xx, xy, yy, zz), 3D (xx, xy, xz, yy, yz, zz).
    stress: D::Sym<R>,
}

impl<R: Real, D: Dim> HostParticles<R, D> {
    /// Particles at `pos` with the given mass and density, at rest and stress-free; ids in order.
    pub fn at_rest(pos: Vec<D::Vec<R>>, mass: R, rho: R) -> Self {
        let n = pos.len();
        HostParticles {
            id: (0..n as u32).collect(),
            flags: vec![0; n],
            vel: vec![Default::default(); n],
            mass: vec![mass; n],
            rho: vec![rho; n],
            stress: vec![Default::default(); n],
            pos,
        }
    }
}
