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
        // Constant pairs: the indices are known at compile time, so no bounds check (and no panic path) is left
        // in the kernels.
        rotate::<R, 0, 1>(&mut a, &mut q, half);
        rotate::<R, 0, 2>(&mut a, &mut q, half);
        rotate::<R, 1, 2>(&mut a, &mut q, half);
        sweep += 1;
    }
    ([a[0][0], a[1][1], a[2][2]], q)
}

/// One Jacobi rotation zeroing a_pr: A ← Jᵀ A J, Q ← Q J.
#[inline(always)]
fn rotate<R: Real, const P: usize, const Q: usize>(a: &mut [[R; 3]; 3], q: &mut [[R; 3]; 3], half: R) {
    let apr = a[P][Q];
    if apr == R::ZERO {
        return;
    }
    // Rotation angle from tan 2φ = 2 a_pr / (a_rr − a_pp), with the small root t = tan φ.
    let theta = half * (a[Q][Q] - a[P][P]) / apr;
    let t = {
        let root = (theta * theta + R::ONE).sqrt();
        let t = R::ONE / (theta.abs() + root);
        if theta < R::ZERO { -t } else { t }
    };
    let c = R::ONE / (t * t + R::ONE).sqrt();
    let sn = t * c;
    for row in a.iter_mut() {
        let (akp, akr) = (row[P], row[Q]);
        row[P] = c * akp - sn * akr;
        row[Q] = sn * akp + c * akr;
    }
    let (ap, ar) = (a[P], a[Q]);
    for k in 0..3 {
        a[P][k] = c * ap[k] - sn * ar[k];
        a[Q][k] = sn * ap[k] + c * ar[k];
    }
    for row in q.iter_mut() {
        let (qkp, qkr) = (row[P], row[Q]);
        row[P] = c * qkp - sn * qkr;
        row[Q] = sn * qkp + c * qkr;
    }
}
