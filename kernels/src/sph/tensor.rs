//! Dimension-specific tensor algebra of the solver, written once for 2D plane strain and 3D.
//!
//! Conventions (roethlin-solver.md §2.1, §2.3): L_ab = ∂v_a/∂x_b, D = ½(L + Lᵀ), W = ½(L − Lᵀ); tension positive;
//! σ = S − p I. Symmetric tensors are stored by components: 2D (xx, xy, yy, zz), 3D (xx, xy, xz, yy, yz, zz).
//! In plane strain D_zz = 0, S_zz is carried, and only the in-plane components enter the momentum equation.

use crate::real::Real;
use crate::vector::{Dim, Dim2, Dim3, SymTensor, Vector};

/// Tensor operations of one spatial dimension.
pub trait TensorOps<R: Real>: Dim {
    /// The velocity gradient L, row-major (2D: 4 entries, 3D: 9).
    type Grad: Copy + Default + AsRef<[R]> + AsMut<[R]>;

    /// L += w · (a ⊗ b).
    fn outer_add(l: &mut Self::Grad, w: R, a: &Self::Vec<R>, b: &Self::Vec<R>);
    /// tr L (= ∇·v).
    fn trace(l: &Self::Grad) -> R;
    /// |∇×v| from the antisymmetric part of L: 2D |L_yx − L_xy|, 3D the norm of the curl vector
    /// (L_zy − L_yz, L_xz − L_zx, L_yx − L_xy). The Balsara switch's rotation measure (`sph::interact::balsara`).
    fn curl_norm(l: &Self::Grad) -> R;
    /// Jaumann rate of the deviatoric stress: Ṡ = 2G (D − ⅓ tr D I) + W S − S W.
    fn jaumann(l: &Self::Grad, s: &Self::Sym<R>, shear: R) -> Self::Sym<R>;
    /// The same without the spin terms (2G dev D): the non-objective rate, a negative control in tests.
    fn spin_free_rate(l: &Self::Grad, shear: R) -> Self::Sym<R>;
    /// σ/ρ² with σ = S − p I (in-plane in 2D).
    fn stress_over_rho2(s: &Self::Sym<R>, p: R, rho: R) -> Self::Sym<R>;
    /// (A + B + c·(C + D) − π I) · g: the tensor part of the momentum pair term.
    fn pair_force(
        a: &Self::Sym<R>,
        b: &Self::Sym<R>,
        c: R,
        ra: &Self::Sym<R>,
        rb: &Self::Sym<R>,
        pi: R,
        g: &Self::Vec<R>,
    ) -> Self::Vec<R>;
    /// Gray–Monaghan artificial stress (roethlin-solver.md §3.6): diagonalise σ = Q diag(λ) Qᵀ, set
    /// R'_k = −ε λ_k/ρ² for λ_k > 0 (else 0), and return Q diag(R') Qᵀ. In 2D the in-plane stress.
    fn artificial_stress(s: &Self::Sym<R>, p: R, rho: R, eps: R) -> Self::Sym<R>;
    /// S : S (all components, including S_zz in plane strain).
    fn double_dot(s: &Self::Sym<R>) -> R;
    /// s += w · (x ⊗ x) (in-plane in 2D).
    fn sym_outer_add(s: &mut Self::Sym<R>, w: R, x: &Self::Vec<R>);
    /// s · v (in-plane in 2D).
    fn sym_apply(s: &Self::Sym<R>, v: &Self::Vec<R>) -> Self::Vec<R>;
    /// s⁻¹ where det s > `min_det`, else the identity (also for a non-finite s; in 2D of the in-plane block, with
    /// zz = 1).
    fn sym_inverse_or_identity(s: &Self::Sym<R>, min_det: R) -> Self::Sym<R>;
    /// Plane strain's velocity gradient for a particle held in plane strain (docs/3d.md, "Extruded 2D models"):
    /// ∂/∂z of the in-plane velocity and the in-plane derivatives of v_z are zero, L_xz = L_yz = L_zx = L_zy = 0, so
    /// D_xz = D_yz = W_xz = W_yz = 0 and S_xz, S_yz stay 0, as in the 2D solver. L_zz is kept: it is 0 where every
    /// neighbour is held too (v_z = 0), and the through-thickness rate at a symmetry face. Without it the layers of
    /// an extruded model, once they part by rounding, shear across one another and carry out-of-plane shear stress
    /// that the 2D model cannot (10–12 % of S:S in the most stressed tenth of the coarse extruded V0060 after
    /// 0.3 mm of cut). In 2D nothing: the 2D gradient has no z entries.
    fn plane_strain(l: &mut Self::Grad);
}

#[inline(always)]
fn sym<R: Real, S: SymTensor<R>>(s: &S) -> &[R] {
    s.components()
}

#[inline(always)]
fn sym_from<R: Real, S: SymTensor<R>, const N: usize>(c: [R; N]) -> S {
    let mut s = S::default();
    let d = s.components_mut();
    let mut k = 0;
    while k < N && k < d.len() {
        d[k] = c[k];
        k += 1;
    }
    s
}

#[inline(always)]
fn vec2<R: Real, V: Vector<R>>(x: R, y: R) -> V {
    V::new([x, y, R::ZERO])
}

impl<R: Real> TensorOps<R> for Dim2 {
    type Grad = [R; 4];

    #[inline(always)]
    fn outer_add(l: &mut [R; 4], w: R, a: &R::V2, b: &R::V2) {
        let (ax, ay) = (w * a.get(0), w * a.get(1));
        l[0] += ax * b.get(0);
        l[1] += ax * b.get(1);
        l[2] += ay * b.get(0);
        l[3] += ay * b.get(1);
    }

    #[inline(always)]
    fn trace(l: &[R; 4]) -> R {
        l[0] + l[3]
    }

    #[inline(always)]
    fn curl_norm(l: &[R; 4]) -> R {
        (l[2] - l[1]).abs()
    }

    #[inline(always)]
    fn jaumann(l: &[R; 4], s: &R::S2, g: R) -> R::S2 {
        let s = sym::<R, _>(s);
        let (sxx, sxy, syy) = (s[0], s[1], s[2]);
        let tr3 = (l[0] + l[3]) / R::from_f64(3.0);
        let two_g = g + g;
        let w = R::from_f64(0.5) * (l[1] - l[2]); // W_xy
        let half = R::from_f64(0.5);
        sym_from::<R, R::S2, 4>([
            two_g * (l[0] - tr3) + (w + w) * sxy,
            two_g * half * (l[1] + l[2]) + w * (syy - sxx),
            two_g * (l[3] - tr3) - (w + w) * sxy,
            -two_g * tr3,
        ])
    }

    #[inline(always)]
    fn spin_free_rate(l: &[R; 4], g: R) -> R::S2 {
        let tr3 = (l[0] + l[3]) / R::from_f64(3.0);
        let two_g = g + g;
        sym_from::<R, R::S2, 4>([two_g * (l[0] - tr3), g * (l[1] + l[2]), two_g * (l[3] - tr3), -two_g * tr3])
    }

    #[inline(always)]
    fn stress_over_rho2(s: &R::S2, p: R, rho: R) -> R::S2 {
        let s = sym::<R, _>(s);
        let k = R::ONE / (rho * rho);
        sym_from::<R, R::S2, 4>([(s[0] - p) * k, s[1] * k, (s[2] - p) * k, (s[3] - p) * k])
    }

    #[inline(always)]
    fn pair_force(a: &R::S2, b: &R::S2, c: R, ra: &R::S2, rb: &R::S2, pi: R, g: &R::V2) -> R::V2 {
        let (a, b, ra, rb) = (sym::<R, _>(a), sym::<R, _>(b), sym::<R, _>(ra), sym::<R, _>(rb));
        let txx = a[0] + b[0] + c * (ra[0] + rb[0]) - pi;
        let txy = a[1] + b[1] + c * (ra[1] + rb[1]);
        let tyy = a[2] + b[2] + c * (ra[2] + rb[2]) - pi;
        let (gx, gy) = (g.get(0), g.get(1));
        vec2(txx * gx + txy * gy, txy * gx + tyy * gy)
    }

    #[inline(always)]
    fn artificial_stress(s: &R::S2, p: R, rho: R, eps: R) -> R::S2 {
        // Trig-free 2×2 eigen-decomposition: λ = m ± rad, projector P1 = ½(I + (cos 2θ, sin 2θ; sin 2θ, −cos 2θ)).
        let s = sym::<R, _>(s);
        let (a, c, b) = (s[0] - p, s[1], s[2] - p);
        let half = R::from_f64(0.5);
        let m = half * (a + b);
        let d = half * (a - b);
        let rad = (d * d + c * c).sqrt();
        let k = -eps / (rho * rho);
        let r = |lam: R| if lam > R::ZERO { k * lam } else { R::ZERO };
        let (r1, r2) = (r(m + rad), r(m - rad));
        if rad == R::ZERO {
            return sym_from::<R, R::S2, 4>([r1, R::ZERO, r1, R::ZERO]);
        }
        let (c2, s2) = (d / rad, c / rad);
        let (ra, rd) = (half * (r1 + r2), half * (r1 - r2));
        sym_from::<R, R::S2, 4>([ra + rd * c2, rd * s2, ra - rd * c2, R::ZERO])
    }

    #[inline(always)]
    fn double_dot(s: &R::S2) -> R {
        let s = sym::<R, _>(s);
        s[0] * s[0] + s[2] * s[2] + s[3] * s[3] + R::from_f64(2.0) * s[1] * s[1]
    }

    #[inline(always)]
    fn sym_outer_add(s: &mut R::S2, w: R, x: &R::V2) {
        let (wx, y) = (w * x.get(0), x.get(1));
        let c = s.components_mut();
        c[0] += wx * x.get(0);
        c[1] += wx * y;
        c[2] += w * y * y;
    }

    #[inline(always)]
    fn sym_apply(s: &R::S2, v: &R::V2) -> R::V2 {
        let s = sym::<R, _>(s);
        let (x, y) = (v.get(0), v.get(1));
        vec2(s[0] * x + s[1] * y, s[1] * x + s[2] * y)
    }

    #[inline(always)]
    fn sym_inverse_or_identity(s: &R::S2, min_det: R) -> R::S2 {
        let s = sym::<R, _>(s);
        let det = s[0] * s[2] - s[1] * s[1];
        if det > min_det {
            let k = R::ONE / det;
            sym_from::<R, R::S2, 4>([s[2] * k, -s[1] * k, s[0] * k, R::ONE])
        } else {
            sym_from::<R, R::S2, 4>([R::ONE, R::ZERO, R::ONE, R::ONE])
        }
    }

    #[inline(always)]
    fn plane_strain(_l: &mut [R; 4]) {}
}

/// Index of component (a, b) in the 3D symmetric storage (xx, xy, xz, yy, yz, zz).
const S3: [[usize; 3]; 3] = [[0, 1, 2], [1, 3, 4], [2, 4, 5]];

impl<R: Real> TensorOps<R> for Dim3 {
    type Grad = [R; 9];

    #[inline(always)]
    fn outer_add(l: &mut [R; 9], w: R, a: &R::V3, b: &R::V3) {
        let mut i = 0;
        while i < 3 {
            let ai = w * a.get(i);
            let mut j = 0;
            while j < 3 {
                l[i * 3 + j] += ai * b.get(j);
                j += 1;
            }
            i += 1;
        }
    }

    #[inline(always)]
    fn trace(l: &[R; 9]) -> R {
        l[0] + l[4] + l[8]
    }

    #[inline(always)]
    fn curl_norm(l: &[R; 9]) -> R {
        let (x, y, z) = (l[7] - l[5], l[2] - l[6], l[3] - l[1]);
        (x * x + y * y + z * z).sqrt()
    }

    #[inline(always)]
    fn jaumann(l: &[R; 9], s: &R::S3, g: R) -> R::S3 {
        let s = sym::<R, _>(s);
        let half = R::from_f64(0.5);
        let tr3 = (l[0] + l[4] + l[8]) / R::from_f64(3.0);
        let two_g = g + g;
        let mut w = [[R::ZERO; 3]; 3];
        let mut sm = [[R::ZERO; 3]; 3];
        for a in 0..3 {
            for b in 0..3 {
                w[a][b] = half * (l[a * 3 + b] - l[b * 3 + a]);
                sm[a][b] = s[S3[a][b]];
            }
        }
        let mut out = [R::ZERO; 6];
        for a in 0..3 {
            for b in a..3 {
                let d = half * (l[a * 3 + b] + l[b * 3 + a]) - if a == b { tr3 } else { R::ZERO };
                let mut ws = R::ZERO;
                for k in 0..3 {
                    ws += w[a][k] * sm[k][b] - sm[a][k] * w[k][b];
                }
                out[S3[a][b]] = two_g * d + ws;
            }
        }
        sym_from::<R, R::S3, 6>(out)
    }

    #[inline(always)]
    fn spin_free_rate(l: &[R; 9], g: R) -> R::S3 {
        let half = R::from_f64(0.5);
        let tr3 = (l[0] + l[4] + l[8]) / R::from_f64(3.0);
        let mut out = [R::ZERO; 6];
        for a in 0..3 {
            for b in a..3 {
                let d = half * (l[a * 3 + b] + l[b * 3 + a]) - if a == b { tr3 } else { R::ZERO };
                out[S3[a][b]] = (g + g) * d;
            }
        }
        sym_from::<R, R::S3, 6>(out)
    }

    #[inline(always)]
    fn stress_over_rho2(s: &R::S3, p: R, rho: R) -> R::S3 {
        let s = sym::<R, _>(s);
        let k = R::ONE / (rho * rho);
        sym_from::<R, R::S3, 6>([(s[0] - p) * k, s[1] * k, s[2] * k, (s[3] - p) * k, s[4] * k, (s[5] - p) * k])
    }

    #[inline(always)]
    fn pair_force(a: &R::S3, b: &R::S3, c: R, ra: &R::S3, rb: &R::S3, pi: R, g: &R::V3) -> R::V3 {
        let (a, b, ra, rb) = (sym::<R, _>(a), sym::<R, _>(b), sym::<R, _>(ra), sym::<R, _>(rb));
        let mut t = [R::ZERO; 6];
        for k in 0..6 {
            t[k] = a[k] + b[k] + c * (ra[k] + rb[k]);
        }
        t[0] -= pi;
        t[3] -= pi;
        t[5] -= pi;
        let (gx, gy, gz) = (g.get(0), g.get(1), g.get(2));
        R::V3::new([
            t[0] * gx + t[1] * gy + t[2] * gz,
            t[1] * gx + t[3] * gy + t[4] * gz,
            t[2] * gx + t[4] * gy + t[5] * gz,
        ])
    }

    #[inline(always)]
    fn artificial_stress(s: &R::S3, p: R, rho: R, eps: R) -> R::S3 {
        let s = sym::<R, _>(s);
        let a = [s[0] - p, s[1], s[2], s[3] - p, s[4], s[5] - p];
        let (lam, q) = crate::sph::eigen::sym3_eigen(a);
        let k = -eps / (rho * rho);
        let mut rp = [R::ZERO; 3];
        for i in 0..3 {
            rp[i] = if lam[i] > R::ZERO { k * lam[i] } else { R::ZERO };
        }
        let mut out = [R::ZERO; 6];
        for a in 0..3 {
            for b in a..3 {
                let mut v = R::ZERO;
                for k in 0..3 {
                    v += q[a][k] * rp[k] * q[b][k];
                }
                out[S3[a][b]] = v;
            }
        }
        sym_from::<R, R::S3, 6>(out)
    }

    #[inline(always)]
    fn double_dot(s: &R::S3) -> R {
        let s = sym::<R, _>(s);
        let two = R::from_f64(2.0);
        s[0] * s[0] + s[3] * s[3] + s[5] * s[5] + two * (s[1] * s[1] + s[2] * s[2] + s[4] * s[4])
    }

    #[inline(always)]
    fn sym_outer_add(s: &mut R::S3, w: R, x: &R::V3) {
        let c = s.components_mut();
        let mut a = 0;
        while a < 3 {
            let wa = w * x.get(a);
            let mut b = a;
            while b < 3 {
                c[S3[a][b]] += wa * x.get(b);
                b += 1;
            }
            a += 1;
        }
    }

    #[inline(always)]
    fn sym_apply(s: &R::S3, v: &R::V3) -> R::V3 {
        let s = sym::<R, _>(s);
        let (x, y, z) = (v.get(0), v.get(1), v.get(2));
        R::V3::new([s[0] * x + s[1] * y + s[2] * z, s[1] * x + s[3] * y + s[4] * z, s[2] * x + s[4] * y + s[5] * z])
    }

    #[inline(always)]
    fn sym_inverse_or_identity(s: &R::S3, min_det: R) -> R::S3 {
        let s = sym::<R, _>(s);
        let (a, b, c, d, e, f) = (s[0], s[1], s[2], s[3], s[4], s[5]);
        // Cofactors of the symmetric matrix [[a, b, c], [b, d, e], [c, e, f]].
        let (cxx, cxy, cxz) = (d * f - e * e, c * e - b * f, b * e - c * d);
        let det = a * cxx + b * cxy + c * cxz;
        if det > min_det {
            let k = R::ONE / det;
            sym_from::<R, R::S3, 6>([
                cxx * k,
                cxy * k,
                cxz * k,
                (a * f - c * c) * k,
                (b * c - a * e) * k,
                (a * d - b * b) * k,
            ])
        } else {
            sym_from::<R, R::S3, 6>([R::ONE, R::ZERO, R::ZERO, R::ONE, R::ZERO, R::ONE])
        }
    }

    #[inline(always)]
    fn plane_strain(l: &mut [R; 9]) {
        // Row-major xz, yz, zx, zy.
        l[2] = R::ZERO;
        l[5] = R::ZERO;
        l[6] = R::ZERO;
        l[7] = R::ZERO;
    }
}
