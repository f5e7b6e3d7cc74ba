//! Particles from a scene: a regular lattice per body, the initial velocities, the boundary conditions, and the
//! check that bodies do not overlap.

use std::collections::HashMap;

use super::error::SceneError;
use super::read::points_on_axis;
use super::{BoundaryKind, Lattice, Scene, Shape};

/// The boundary condition of a particle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bc {
    /// No condition.
    Free,
    /// v = 0 for ever.
    Fixed,
    /// v prescribed for ever (m/s) (z = 0 in 2D).
    Velocity([f64; 3]),
    /// v_z = 0 for ever (3D plane strain).
    Plane,
}

/// The particles of a scene, body after body, each body's lattice in z, y, x order (x fastest).
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleSet {
    /// Positions (m); z = 0 in 2D.
    pub pos: Vec<[f64; 3]>,
    /// Initial velocities (m/s): the body's velocity plus its rigid rotation; for a particle under a boundary
    /// condition, the prescribed velocity (0 for `fixed`). z = 0 in 2D.
    pub vel: Vec<[f64; 3]>,
    /// Index of the body ([`Scene::bodies`]) of each particle.
    pub body: Vec<u32>,
    /// Boundary condition of each particle: the last `[[boundary]]` whose region (and body) contains it.
    pub bc: Vec<Bc>,
    /// The index into [`Scene::boundaries`] of the mechanical boundary that set `bc` (None for `Free`): its
    /// `reverse_at` times apply to the particle.
    pub bc_source: Vec<Option<usize>>,
    /// Initial temperature of each particle (K): `physics.initial_temperature`, or a temperature boundary's.
    pub temperature: Vec<f64>,
    /// Held at its temperature by a `kind = "temperature"` boundary.
    pub fixed_temperature: Vec<bool>,
    /// Mass of every particle, ρ0 · dx^dim (kg) (per unit depth in 2D).
    pub mass: f64,
    /// Volume of every particle, dx^dim (m^dim) (per unit depth in 2D).
    pub volume: f64,
}

impl ParticleSet {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }
}

/// The lattice coordinates of an axis of a box: corner + k·dx (nodes) or corner + (k + ½)·dx (cells).
fn axis(corner: f64, extent: f64, dx: f64, lattice: Lattice) -> Vec<f64> {
    let n = points_on_axis(extent, dx, lattice);
    (0..n)
        .map(|k| match lattice {
            Lattice::Nodes => corner + (k as f64) * dx,
            Lattice::Cells => corner + (k as f64 + 0.5) * dx,
        })
        .collect()
}

/// The lattice offsets from the centre along an axis of a round shape of radius `r`: the same lattice as
/// `axis(c − r, 2r, ..)`, −r + k·dx (nodes) or −r + (k + ½)·dx (cells). When 2r/dx is an integer m (to 1e-9),
/// the lattice is centred and the offsets are computed as (k − m/2)·dx, which is exactly antisymmetric: a point
/// exactly on a radius is then kept or dropped alike on every side, and every body of the same shape gets the
/// same particles wherever its centre is (the two rings or tubes of an impact have equal counts).
fn offsets(r: f64, dx: f64, lattice: Lattice) -> Vec<f64> {
    let n = points_on_axis(2.0 * r, dx, lattice);
    let ratio = 2.0 * r / dx;
    let m = (ratio + 1e-9).floor();
    let centred = (ratio - m).abs() <= 1e-9;
    (0..n)
        .map(|k| {
            let k = k as f64 + if lattice == Lattice::Cells { 0.5 } else { 0.0 };
            if centred { (k - 0.5 * m) * dx } else { -r + k * dx }
        })
        .collect()
}

/// Appends the lattice points inside `shape` to `out`, z slowest, x fastest.
fn fill(shape: &Shape, lattice: Lattice, dx: f64, out: &mut Vec<[f64; 3]>) {
    visit(shape, lattice, dx, &mut |p| out.push(p));
}

/// The largest y of the lattice points of a body of `shape` (its top particle row), `None` when the shape holds
/// no lattice point. Computed from the same lattice as the particles ([`visit`]), so it is exactly the y of the
/// generated top row: `tool.depth_of_cut` measures from it (read.rs).
pub(super) fn top_row(shape: &Shape, lattice: Lattice, dx: f64) -> Option<f64> {
    let mut top: Option<f64> = None;
    visit(shape, lattice, dx, &mut |p| top = Some(top.map_or(p[1], |t| t.max(p[1]))));
    top
}

/// Calls `emit` with each lattice point inside `shape`, z slowest, x fastest: the one place that decides which
/// points a body has (the particles, and the top row `tool.depth_of_cut` refers to).
fn visit(shape: &Shape, lattice: Lattice, dx: f64, emit: &mut dyn FnMut([f64; 3])) {
    let mut push_round = |c: [f64; 3], r: f64, zs: &[f64], keep: &dyn Fn(f64, f64, f64) -> bool| {
        let o = offsets(r, dx, lattice);
        for &z in zs {
            for &y in &o {
                for &x in &o {
                    if keep(x, y, z) {
                        emit([c[0] + x, c[1] + y, c[2] + z]);
                    }
                }
            }
        }
    };
    match *shape {
        Shape::Rectangle { min, max } => {
            let xs = axis(min[0], max[0] - min[0], dx, lattice);
            let ys = axis(min[1], max[1] - min[1], dx, lattice);
            for &y in &ys {
                for &x in &xs {
                    emit([x, y, 0.0]);
                }
            }
        }
        Shape::Box { min, max } => {
            let xs = axis(min[0], max[0] - min[0], dx, lattice);
            let ys = axis(min[1], max[1] - min[1], dx, lattice);
            let zs = axis(min[2], max[2] - min[2], dx, lattice);
            for &z in &zs {
                for &y in &ys {
                    for &x in &xs {
                        emit([x, y, z]);
                    }
                }
            }
        }
        Shape::Disk { center: c, radius } => {
            push_round([c[0], c[1], 0.0], radius, &[0.0], &|x, y, _| (x * x + y * y).sqrt() < radius)
        }
        Shape::Ring { center: c, inner_radius, outer_radius } => {
            push_round([c[0], c[1], 0.0], outer_radius, &[0.0], &|x, y, _| {
                let r = (x * x + y * y).sqrt();
                inner_radius <= r && r < outer_radius
            })
        }
        Shape::SphericalShell { center: c, inner_radius, outer_radius } => {
            let zs = offsets(outer_radius, dx, lattice);
            push_round(c, outer_radius, &zs, &|x, y, z| {
                let r = (x * x + y * y + z * z).sqrt();
                inner_radius <= r && r < outer_radius
            })
        }
        Shape::Cylinder { center: c, radius, height, inner_radius } => {
            // z from the base: c_z + k·dx (nodes, both ends included) or c_z + (k + ½)·dx (cells).
            let zs = axis(0.0, height, dx, lattice);
            push_round(c, radius, &zs, &|x, y, _| {
                let r = (x * x + y * y).sqrt();
                inner_radius <= r && r < radius
            })
        }
    }
}

pub(super) fn generate(scene: &Scene) -> Result<ParticleSet, SceneError> {
    let dim = scene.dim;
    let dx = scene.discretisation.dx;
    let mut pos = Vec::new();
    let mut vel = Vec::new();
    let mut body = Vec::new();
    let mut ranges = Vec::with_capacity(scene.bodies.len());
    for (i, b) in scene.bodies.iter().enumerate() {
        let start = pos.len();
        fill(&b.shape, b.lattice, dx, &mut pos);
        if pos.len() == start {
            return Err(SceneError::EmptyBody { file: scene.origin.clone(), body: b.name.clone(), index: i, dx });
        }
        let c = b.shape.centre();
        let w = b.angular_velocity;
        for p in &pos[start..] {
            let mut v = b.velocity;
            if w != 0.0 {
                v[0] += w * -(p[1] - c[1]);
                v[1] += w * (p[0] - c[0]);
            }
            vel.push(v);
        }
        body.resize(pos.len(), i as u32);
        ranges.push(start..pos.len());
    }

    check_overlap(scene, &pos, &ranges)?;

    // Boundary conditions: the last entry containing the particle wins.
    let mut bc = vec![Bc::Free; pos.len()];
    let mut bc_source = vec![None; pos.len()];
    let mut used = vec![false; scene.boundaries.len()];
    if !scene.boundaries.is_empty() {
        for (i, (p, (&b, (slot, v)))) in pos.iter().zip(body.iter().zip(bc.iter_mut().zip(vel.iter_mut()))).enumerate()
        {
            for (j, boundary) in scene.boundaries.iter().enumerate() {
                let contains = boundary.body.is_none_or(|only| only == b as usize)
                    && (0..dim).all(|k| boundary.min[k] <= p[k] && p[k] <= boundary.max[k]);
                if contains {
                    used[j] = true;
                    *slot = match boundary.kind {
                        BoundaryKind::Fixed => Bc::Fixed,
                        BoundaryKind::Velocity { velocity } => Bc::Velocity(velocity),
                        BoundaryKind::PlaneStrain => Bc::Plane,
                        BoundaryKind::Temperature { .. } => *slot,
                    };
                    if !matches!(boundary.kind, BoundaryKind::Temperature { .. }) {
                        bc_source[i] = Some(j);
                    }
                }
            }
            match *slot {
                Bc::Free => {}
                Bc::Fixed => *v = [0.0; 3],
                Bc::Velocity(velocity) => *v = velocity,
                Bc::Plane => v[2] = 0.0,
            }
        }
    }
    // Temperatures: the initial temperature, or that of the last temperature boundary containing the particle.
    let mut temperature: Vec<f64> = body
        .iter()
        .map(|&b| scene.bodies[b as usize].temperature.unwrap_or(scene.physics.initial_temperature))
        .collect();
    let mut fixed_temperature = vec![false; pos.len()];
    for (i, p) in pos.iter().enumerate() {
        for boundary in &scene.boundaries {
            if let BoundaryKind::Temperature { temperature: t } = boundary.kind {
                let contains = boundary.body.is_none_or(|only| only == body[i] as usize)
                    && (0..dim).all(|k| boundary.min[k] <= p[k] && p[k] <= boundary.max[k]);
                if contains {
                    fixed_temperature[i] = true;
                    temperature[i] = t.unwrap_or(scene.physics.initial_temperature);
                }
            }
        }
    }
    if let Some(j) = used.iter().position(|&u| !u) {
        return Err(SceneError::EmptyBoundary {
            file: scene.origin.clone(),
            index: j,
            kind: scene.boundaries[j].kind.as_str(),
        });
    }

    Ok(ParticleSet {
        pos,
        vel,
        body,
        bc,
        bc_source,
        temperature,
        fixed_temperature,
        mass: scene.particle_mass(),
        volume: scene.particle_volume(),
    })
}

/// Refuses two bodies with particles closer than 0.5·dx. Only pairs of bodies whose bounding boxes come that
/// close are examined, through a hash of cells of size 0.5·dx over the first body's particles in the overlap.
fn check_overlap(scene: &Scene, pos: &[[f64; 3]], ranges: &[std::ops::Range<usize>]) -> Result<(), SceneError> {
    let dim = scene.dim;
    let limit = 0.5 * scene.discretisation.dx;
    let bounds: Vec<([f64; 3], [f64; 3])> = ranges
        .iter()
        .map(|r| {
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for p in &pos[r.clone()] {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            (lo, hi)
        })
        .collect();
    let cell = |p: &[f64; 3]| -> [i64; 3] { std::array::from_fn(|k| (p[k] / limit).floor() as i64) };
    for a in 0..ranges.len() {
        for b in a + 1..ranges.len() {
            // The region where particles of a and b can come within `limit` of each other.
            let lo: [f64; 3] = std::array::from_fn(|k| bounds[a].0[k].max(bounds[b].0[k]) - limit);
            let hi: [f64; 3] = std::array::from_fn(|k| bounds[a].1[k].min(bounds[b].1[k]) + limit);
            if (0..dim).any(|k| lo[k] > hi[k]) {
                continue;
            }
            let within = |p: &[f64; 3]| (0..dim).all(|k| lo[k] <= p[k] && p[k] <= hi[k]);
            let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
            for i in ranges[a].clone().filter(|&i| within(&pos[i])) {
                cells.entry(cell(&pos[i])).or_default().push(i);
            }
            let reach: i64 = 1;
            let zr = if dim == 3 { reach } else { 0 };
            for j in ranges[b].clone().filter(|&j| within(&pos[j])) {
                let c = cell(&pos[j]);
                let mut closest: Option<(usize, f64)> = None;
                for dz in -zr..=zr {
                    for dy in -reach..=reach {
                        for dxc in -reach..=reach {
                            let Some(list) = cells.get(&[c[0] + dxc, c[1] + dy, c[2] + dz]) else { continue };
                            for &i in list {
                                let d = (0..3).map(|k| (pos[i][k] - pos[j][k]).powi(2)).sum::<f64>().sqrt();
                                if d < limit && closest.is_none_or(|(_, best)| d < best) {
                                    closest = Some((i, d));
                                }
                            }
                        }
                    }
                }
                if let Some((i, distance)) = closest {
                    return Err(SceneError::Overlap {
                        file: scene.origin.clone(),
                        first: scene.bodies[a].name.clone(),
                        second: scene.bodies[b].name.clone(),
                        points: Box::new([pos[i], pos[j]]),
                        dim,
                        distance,
                        limit,
                    });
                }
            }
        }
    }
    Ok(())
}
