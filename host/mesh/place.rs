//! Placing a tool mesh: x' = R·(s·x) + t, a uniform scale s > 0 (e.g. 1e-6 for a file in µm), a rotation R (a
//! proper orthogonal 3×3 matrix, or Rodrigues' formula from an axis and angle) and a translation t. Scene keys are
//! a later step; this is the function they will call.

use super::check::{cross, dot};
use super::{MeshError, TriMesh};

/// A similarity transform with positive scale and a proper rotation (orientation and closedness are kept).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    pub scale: f64,
    /// Row-major: x'_i = Σ_j R_ij x_j.
    pub rotation: [[f64; 3]; 3],
    pub translation: [f64; 3],
}

/// How far RᵀR may be from the identity, entry by entry.
pub const ROTATION_TOL: f64 = 1e-9;

impl Placement {
    pub const IDENTITY: Placement =
        Placement { scale: 1.0, rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], translation: [0.0; 3] };

    /// A placement from a matrix: refuses a non-positive or non-finite scale, a non-finite translation and a matrix
    /// that is not a rotation (|RᵀR − I| > [`ROTATION_TOL`] in an entry, or det R < 0: a reflection would turn the
    /// mesh inside out).
    pub fn new(scale: f64, rotation: [[f64; 3]; 3], translation: [f64; 3]) -> Result<Self, MeshError> {
        if !(scale > 0.0 && scale.is_finite()) {
            return Err(MeshError::Placement(format!("scale = {scale}: expected a finite value > 0")));
        }
        if !translation.iter().all(|x| x.is_finite()) {
            return Err(MeshError::Placement(format!("translation = {translation:?}: expected finite values")));
        }
        for i in 0..3 {
            for j in 0..3 {
                let rtr: f64 = (0..3).map(|k| rotation[k][i] * rotation[k][j]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                if rtr.is_nan() || (rtr - want).abs() > ROTATION_TOL {
                    return Err(MeshError::Placement(format!(
                        "rotation {rotation:?} is not orthonormal ((RᵀR)_{i}{j} = {rtr}): expected a rotation matrix"
                    )));
                }
            }
        }
        if dot(rotation[0], cross(rotation[1], rotation[2])) < 0.0 {
            return Err(MeshError::Placement(format!(
                "rotation {rotation:?} has det < 0 (a reflection): expected det = +1"
            )));
        }
        Ok(Placement { scale, rotation, translation })
    }

    /// A placement from a rotation of `angle` radians about `axis` (right-handed; any non-zero length), by
    /// Rodrigues' formula R = I + sin θ K + (1 − cos θ) K², K the cross-product matrix of the unit axis.
    pub fn from_axis_angle(scale: f64, axis: [f64; 3], angle: f64, translation: [f64; 3]) -> Result<Self, MeshError> {
        let len = dot(axis, axis).sqrt();
        if !(len > 0.0 && len.is_finite() && angle.is_finite()) {
            return Err(MeshError::Placement(format!(
                "axis {axis:?}, angle {angle}: expected a finite non-zero axis and a finite angle"
            )));
        }
        let [x, y, z] = axis.map(|a| a / len);
        let (s, c) = angle.sin_cos();
        let k = [[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]];
        let mut r = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                let k2: f64 = (0..3).map(|m| k[i][m] * k[m][j]).sum();
                r[i][j] = if i == j { 1.0 } else { 0.0 } + s * k[i][j] + (1.0 - c) * k2;
            }
        }
        Self::new(scale, r, translation)
    }

    /// The image of a point.
    pub fn point(&self, p: [f64; 3]) -> [f64; 3] {
        let q = p.map(|x| x * self.scale);
        [0, 1, 2].map(|i| dot(self.rotation[i], q) + self.translation[i])
    }

    /// The placed mesh (the same triangles; a proper rotation keeps their orientation).
    pub fn apply(&self, m: &TriMesh) -> TriMesh {
        TriMesh {
            source: m.source.clone(),
            vertices: m.vertices.iter().map(|&p| self.point(p)).collect(),
            triangles: m.triangles.clone(),
        }
    }
}
