//! Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations: robust for repeated eigenvalues,
//! branch-light and deterministic (the same operations on CPU and GPU). Used by the 3D artificial stress
//! (roethlin-solver.md §3.6; the theses port Eberly's solver, any robust symmetric solver serves).

use crate::real::Real;

/// Eigenvalues λ and eigenvectors (columns of Q) of the symmetric matrix given as (xx, xy, xz, yy, yz, zz), so
/// that A = Q diag(λ) Qᵀ. At most 8 sweeps; converges to rounding in 4–6 for any input.
#[inline(always)]
pub fn sym3_eigen<R: Real>(s: [R; 6]) -> ([R; 3], [[R; 3]; 3]) {
    let mut a = [[s[0], s[1], s[2]], [s[1], s[3], s[4]], [s[2], s[4], s[5]]];
    let mut q = [[R::ONE, R::ZERO, R::ZERO], [R::ZERO, R::ONE, R::ZERO], [R::ZERO, R::ZERO, R::ONE]];
    let half = R::from_f64(0.5);
    let mut sweep = 0;
    while sweep < 8 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if off <= R::EPSILON * R::EPSILON * diag || off == R::ZERO {
            break;
        }
        for (p, r) in [(0usize, 1usize), (0, 2), (1, 2)] {
            let apr = a[p][r];
            if apr == R::ZERO {
                continue;
            }
            // Rotation angle from tan 2φ = 2 a_pr / (a_rr − a_pp), with the small root t = tan φ.
            let theta = half * (a[r][r] - a[p][p]) / apr;
            let t = {
                let root = (theta * theta + R::ONE).sqrt();
                let t = R::ONE / (theta.abs() + root);
                if theta < R::ZERO { -t } else { t }
            };
            let c = R::ONE / (t * t + R::ONE).sqrt();
            let sn = t * c;
            // A ← Jᵀ A J on rows/columns p and r.
            for k in 0..3 {
                let (akp, akr) = (a[k][p], a[k][r]);
                a[k][p] = c * akp - sn * akr;
                a[k][r] = sn * akp + c * akr;
            }
            for k in 0..3 {
                let (apk, ark) = (a[p][k], a[r][k]);
                a[p][k] = c * apk - sn * ark;
                a[r][k] = sn * apk + c * ark;
            }
            for k in 0..3 {
                let (qkp, qkr) = (q[k][p], q[k][r]);
                q[k][p] = c * qkp - sn * qkr;
                q[k][r] = sn * qkp + c * qkr;
            }
        }
        sweep += 1;
    }
    ([a[0][0], a[1][1], a[2][2]], q)
}
