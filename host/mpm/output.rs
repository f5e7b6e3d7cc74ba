//! What an MPM run reads back: the particles' state in f64, its energies, the crack's points, and the frame it
//! writes (VTU).

use super::solver::MpmSolver;
use crate::Result;
use crate::backend::Backend;
use crate::kernels::mpm::grid::TOOL;
use crate::kernels::mpm::hyperelastic::{NeoHookeanJ2, strain_energy};
use crate::kernels::{Real, SymTensor, Vector};
use crate::output::vtu::{Array, Frame, Values};

/// The particles' state, widened to f64, in id order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Snapshot {
    pub pos: Vec<[f64; 2]>,
    pub vel: Vec<[f64; 2]>,
    /// Cauchy stress and B̄_e, (xx, xy, yy, zz).
    pub stress: Vec<[f64; 4]>,
    pub be: Vec<[f64; 4]>,
    pub jac: Vec<f64>,
    /// The deformation gradient F (xx, xy, yx, yy).
    pub def: Vec<[f64; 4]>,
    pub eps: Vec<f64>,
    pub kind: Vec<u32>,
    pub mass: Vec<f64>,
    pub vol0: Vec<f64>,
}

fn wide2<R: Real>(v: Vec<R::V2>) -> Vec<[f64; 2]> {
    v.iter().map(|x| [x.get(0).to_f64(), x.get(1).to_f64()]).collect()
}

fn wide4<R: Real>(v: Vec<R::S2>) -> Vec<[f64; 4]> {
    v.iter()
        .map(|s| {
            let c = s.components();
            [c[0].to_f64(), c[1].to_f64(), c[2].to_f64(), c[3].to_f64()]
        })
        .collect()
}

fn wide<R: Real>(v: Vec<R>) -> Vec<f64> {
    v.iter().map(|x| x.to_f64()).collect()
}

impl<B: Backend, R: Real> MpmSolver<B, R> {
    /// The particles' state now.
    pub fn snapshot(&self, b: &B) -> Result<Snapshot> {
        let p = &self.parts;
        Ok(Snapshot {
            pos: wide2::<R>(b.read(&p.pos)?),
            vel: wide2::<R>(b.read(&p.vel)?),
            stress: wide4::<R>(b.read(&p.stress)?),
            be: wide4::<R>(b.read(&p.be)?),
            jac: wide(b.read(&p.jac)?),
            def: b.read(&p.def)?.iter().map(|f| f.map(|x| x.to_f64())).collect(),
            eps: wide(b.read(&p.eps)?),
            kind: b.read(&p.kind)?,
            mass: wide(b.read(&p.mass)?),
            vol0: wide(b.read(&p.vol0)?),
        })
    }

    /// The crack points' history (largest normal and sliding openings, failed, mode-I share), widened.
    pub fn crack_state(&self, b: &B) -> Result<Vec<[f64; 4]>> {
        Ok(b.read(&self.crack.state)?.iter().map(|s| s.map(|x| x.to_f64())).collect())
    }
}

impl Snapshot {
    /// The specimen's kinetic energy Σ ½ m |v|² and strain energy Σ V0 W(B̄_e, J) (Eq. 1) [J/m].
    pub fn energies(&self, m: &NeoHookeanJ2) -> (f64, f64) {
        let (mut kin, mut strain) = (0.0, 0.0);
        for i in 0..self.pos.len() {
            if self.kind[i] == TOOL {
                continue;
            }
            let v = self.vel[i];
            kin += 0.5 * self.mass[i] * (v[0] * v[0] + v[1] * v[1]);
            strain += self.vol0[i] * strain_energy(m, self.be[i], self.jac[i], self.jac[i].ln());
        }
        (kin, strain)
    }

    /// The frame of this state at `time`: kind, velocity, stress (xx, xy, yy, zz), von Mises stress, plastic
    /// strain, J and the deformation gradient F (xx, xy, yx, yy: ParaView's glyphs of the particles' domains).
    pub fn frame<'a>(&'a self, time: f64, scratch: &'a mut FrameScratch) -> Frame<'a> {
        scratch.points = self.pos.iter().flat_map(|x| [x[0], x[1], 0.0]).collect();
        scratch.vel = self.vel.iter().flat_map(|v| [v[0], v[1], 0.0]).collect();
        scratch.stress = self.stress.iter().flat_map(|s| *s).collect();
        scratch.mises = self.stress.iter().map(|s| von_mises(*s)).collect();
        scratch.def = self.def.iter().flat_map(|f| *f).collect();
        Frame {
            time,
            points: Values::F64(&scratch.points),
            point_data: vec![
                Array { name: "kind", components: 1, values: Values::U32(&self.kind) },
                Array { name: "velocity", components: 3, values: Values::F64(&scratch.vel) },
                Array { name: "stress", components: 4, values: Values::F64(&scratch.stress) },
                Array { name: "von_mises", components: 1, values: Values::F64(&scratch.mises) },
                Array { name: "plastic_strain", components: 1, values: Values::F64(&self.eps) },
                Array { name: "J", components: 1, values: Values::F64(&self.jac) },
                Array { name: "F", components: 4, values: Values::F64(&scratch.def) },
            ],
            field_data: Vec::new(),
        }
    }
}

/// The von Mises stress of a plane-strain (xx, xy, yy, zz) stress.
pub fn von_mises(s: [f64; 4]) -> f64 {
    let p = (s[0] + s[2] + s[3]) / 3.0;
    let d = [s[0] - p, s[2] - p, s[3] - p];
    (1.5 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * s[1] * s[1])).sqrt()
}

/// The flattened arrays a frame borrows.
#[derive(Default)]
pub struct FrameScratch {
    points: Vec<f64>,
    vel: Vec<f64>,
    stress: Vec<f64>,
    mises: Vec<f64>,
    def: Vec<f64>,
}
