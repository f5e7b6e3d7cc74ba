//! Particle state as a structure of arrays: one buffer per field, in the run's dimension and precision, on the
//! host (`HostParticles`) or in a backend's memory (`Particles`), moved between the two with bytemuck.
//! Fields follow roethlin-solver.md §5.1; physics-specific fields join as their issues land, each allocated only
//! when its physics is on.

use crate::Result;
use crate::backend::{Backend, Element};
use crate::kernels::neighbour::GatherField;
use crate::kernels::{Dim, Real};

/// A field in backend memory with a spare buffer, so that a reorder is one gather and a swap (Green's
/// double-buffering, roethlin-solver.md §6.4: fastest while memory allows).
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

    /// Adds this field to a batch reordered by one launch (`ReorderBatch::run`) and swaps its buffers now: the
    /// batch keeps the addresses, so `cur` names the reordered copy once the batch has run.
    pub fn stage(&mut self, b: &B, batch: &mut ReorderBatch) {
        batch.push(GatherField {
            src: b.address(&self.cur),
            dst: b.address_mut(&mut self.spare),
            bytes: size_of::<T>() as u32,
            _pad: 0,
        });
        std::mem::swap(&mut self.cur, &mut self.spare);
    }

    pub fn read(&self, b: &B) -> Result<Vec<T>> {
        b.read(&self.cur)
    }

    /// Overwrites the field with the bytes saved under `name` (a checkpoint), checking their length.
    pub fn load(&mut self, b: &B, name: &str, blobs: &[(String, Vec<u8>)]) -> Result<()> {
        load_blob(b, name, &mut self.cur, blobs)
    }
}

/// Most fields one reorder launch moves.
pub const MAX_REORDER: usize = 32;

/// Fields staged for one fused reorder (fixed capacity: the step loop allocates nothing).
pub struct ReorderBatch {
    fields: [GatherField; MAX_REORDER],
    len: usize,
}

impl Default for ReorderBatch {
    fn default() -> Self {
        ReorderBatch { fields: [GatherField::default(); MAX_REORDER], len: 0 }
    }
}

impl ReorderBatch {
    fn push(&mut self, f: GatherField) {
        if self.len < MAX_REORDER {
            self.fields[self.len] = f;
        }
        self.len += 1;
    }

    /// Gathers every staged field through `perm` in one launch and empties the batch.
    pub fn run<B: Backend>(&mut self, b: &B, n: usize, perm: &B::Buf<u32>) -> Result<()> {
        let len = std::mem::take(&mut self.len);
        let fields = self.fields.get(..len).ok_or(crate::Error::Length {
            op: "reorder batch (too many fields)",
            expected: MAX_REORDER,
            got: len,
        })?;
        // SAFETY: every entry was staged from a Field's two distinct live buffers of at least n elements.
        unsafe { b.gather_fields(n, perm, fields) }
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

/// Declares the particle fields once; upload, download and reorder are generated from the list, so a field
/// cannot be left out of the reorder.
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

            /// Stages every field for a fused reorder ([`Field::stage`]).
            pub fn stage(&mut self, b: &B, batch: &mut ReorderBatch) {
                $( self.$name.stage(b, batch); )*
            }

            /// Raw copies of every field, named as declared (for checkpoints).
            pub fn save(&self, b: &B, out: &mut Vec<(String, Vec<u8>)>) -> Result<()> {
                $( out.push((stringify!($name).to_string(), bytemuck::cast_slice::<_, u8>(&self.$name.read(b)?).to_vec())); )*
                Ok(())
            }

            /// Restores every field from [`Particles::save`]'s copies.
            pub fn load(&mut self, b: &B, blobs: &[(String, Vec<u8>)]) -> Result<()> {
                $( self.$name.load(b, stringify!($name), blobs)?; )*
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
