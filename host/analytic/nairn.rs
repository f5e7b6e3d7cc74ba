//! Nairn's revised analytical models of cutting as ductile fracture (nairn-mpm.md §4; paper Eqs. 11–22): the force
//! balance with rubbing under the tool, the crack-tip-touching model (Atkins' energy balance minimised over the
//! shear angle), the plastic-bending model (Williams, Patel and Blackman, revised for rubbing and linear hardening),
//! the dimensionless mapping, the back-calculation of the rubbing force from simulated forces, the bias of a linear
//! extrapolation of frictional data, and a fit of Eq. 14 for the toughness G_c. A port of the digest's reference
//! implementation (§4.6), tested against its tables (tests/analytic_nairn.rs).
//!
//! Units: SI per unit width b (forces F/b in N/m, lengths in m, stresses in Pa, G_c in J/m²); angles in radians.

use std::f64::consts::FRAC_PI_2;

/// The specimen's properties that the models use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Specimen {
    /// Initial yield stress σ_y0 [Pa].
    pub yield_stress: f64,
    /// Plane-strain modulus E′ = E/(1 − ν²) [Pa].
    pub plane_modulus: f64,
    /// Toughness G_c [J/m²].
    pub toughness: f64,
    /// Y = σ_y/τ_y: √3 (von Mises, the simulations) or 2 (Tresca).
    pub yield_ratio: f64,
}

impl Specimen {
    /// The paper's polymer-like set (§2): K = 980 MPa, G = 376 MPa (E′ from them), σ_y0 = 25 MPa, G_c = 2000 J/m²,
    /// von Mises.
    pub fn paper() -> Specimen {
        let (k, g) = (980e6, 376e6);
        let e = 9.0 * k * g / (3.0 * k + g);
        let nu = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
        Specimen { yield_stress: 25e6, plane_modulus: e / (1.0 - nu * nu), toughness: 2000.0, yield_ratio: 3f64.sqrt() }
    }

    /// The dimensionless depth η = h σ_y0²/(2 E′ G_c) (§4.5).
    pub fn eta(&self, h: f64) -> f64 {
        h * self.yield_stress * self.yield_stress / (2.0 * self.plane_modulus * self.toughness)
    }

    /// The depth of a dimensionless depth η.
    pub fn depth(&self, eta: f64) -> f64 {
        eta * 2.0 * self.plane_modulus * self.toughness / (self.yield_stress * self.yield_stress)
    }
}

/// Z = (μ − tan α)/(1 + μ tan α) = tan(λ − α), μ = tan λ (Eq. 12).
pub fn z(mu: f64, alpha: f64) -> f64 {
    (mu - alpha.tan()) / (1.0 + mu * alpha.tan())
}

/// Eq. 12: the transverse force F_t = Z F_c + (1 − μZ) F_n^b.
pub fn transverse_force(fc: f64, rubbing: f64, mu: f64, alpha: f64) -> f64 {
    let z = z(mu, alpha);
    z * fc + (1.0 - mu * z) * rubbing
}

/// Eq. 12 inverted: the rubbing force under the tool from the simulated forces, F_n^b = (F_t − Z F_c)/(1 − μZ)
/// (F_t positive into the workpiece).
pub fn rubbing_force(fc: f64, ft: f64, mu: f64, alpha: f64) -> f64 {
    let z = z(mu, alpha);
    (ft - z * fc) / (1.0 - mu * z)
}

/// Eq. 13 solved for F_c/b at a given shear angle φ: plastic shear work τ_y γ h (γ = cot φ + tan(φ − α)), chip
/// friction S sin φ/cos(φ − α) with S = μ(F_c − μF_n^b)/(cos α + μ sin α) from Eq. 11, rubbing friction μF_n^b, and
/// fracture G_c.
pub fn energy_balance(phi: f64, h: f64, alpha: f64, mu: f64, rubbing: f64, s: &Specimen) -> f64 {
    let tau = s.yield_stress / s.yield_ratio;
    let gamma = 1.0 / phi.tan() + (phi - alpha).tan();
    let q = phi.sin() / ((phi - alpha).cos() * (alpha.cos() + mu * alpha.sin()));
    (tau * gamma * h + s.toughness + mu * rubbing * (1.0 - mu * q)) / (1.0 - mu * q)
}

/// Eq. 14, the crack-tip-touching model: F_c/b = G_c + μF_n^b/b + (2σ_y h/Y)(Z + √(1 + Z² + YμG_c sec α/(hσ_y(cos α +
/// μ sin α)))).
pub fn touching(h: f64, alpha: f64, mu: f64, rubbing: f64, s: &Specimen) -> f64 {
    let z = z(mu, alpha);
    let (sy, y, gc) = (s.yield_stress, s.yield_ratio, s.toughness);
    let root = (1.0 + z * z + y * mu * gc / alpha.cos() / (h * sy * (alpha.cos() + mu * alpha.sin()))).sqrt();
    gc + mu * rubbing + 2.0 * sy * h / y * (z + root)
}

/// Eq. 15, the frictionless touching model: F_c/b = G_c + (2σ_y h/Y)(sec α − tan α).
pub fn touching_frictionless(h: f64, alpha: f64, s: &Specimen) -> f64 {
    s.toughness + 2.0 * s.yield_stress * h / s.yield_ratio * (1.0 / alpha.cos() - alpha.tan())
}

/// The shear angle that minimises Eq. 13 (golden-section search on (α, π/2)); Merchant's 45° + α/2 when μ = 0.
pub fn optimum_shear_angle(h: f64, alpha: f64, mu: f64, rubbing: f64, s: &Specimen) -> f64 {
    let f = |phi: f64| energy_balance(phi, h, alpha, mu, rubbing, s);
    let (mut a, mut b) = (alpha.max(0.0) + 1e-9, FRAC_PI_2 - 1e-9);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..200 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    0.5 * (a + b)
}

/// A_1/(bG_c) of Eq. 21 (k_0 ≥ 1) or η k_0²/3 (k_0 < 1): the complementary bending energy; e = E_p/E′.
pub fn a1(k: f64, eta: f64, e: f64) -> f64 {
    if k < 1.0 {
        eta * k * k / 3.0
    } else {
        eta * (1.0 - 2.0 / (3.0 * k) + e / 3.0 * (k - 1.0).powi(2) * (1.0 + 2.0 / k))
    }
}

/// A_2/(bG_c) of Eq. 22 (k_0 ≥ 1; 0 below): the plastic bending energy dissipated.
pub fn a2(k: f64, eta: f64, e: f64) -> f64 {
    if k < 1.0 {
        return 0.0;
    }
    let u = 1.0 / k;
    eta * (1.0 - e)
        * (1.0 - u).powi(2)
        * (k + 0.25 * (1.0 - u) * ((1.0 + u / 3.0) + e / 3.0 * (1.0 - u) * (2.0 * k + 1.0).powi(2)))
}

/// Eq. 20, the moment over ¼ b h² σ_y0 at the curvature ratio k_0 = κ/κ_y.
pub fn moment(k: f64, e: f64) -> f64 {
    if k <= 1.0 {
        2.0 * k / 3.0
    } else {
        1.0 - 1.0 / (3.0 * k * k) + e / 3.0 * (1.0 - 1.0 / k).powi(2) * (2.0 * k + 1.0)
    }
}

/// The crack-root rotation correction χ of the bending model (nairn-mpm.md §4.3, the reference implementation's
/// value).
pub const CHI: f64 = 0.64;

/// The plastic-bending model's answer: F_c/(bG_c) (Eq. 18) and the root curvature ratio k_0 (Eq. 19).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bending {
    pub force: f64,
    pub k0: f64,
}

/// Eqs. 18–19 at dimensionless depth η, with e = E_p/E′ (the digest's §8 item 3: the slope that fits the
/// derivation is the tangent modulus E_T, i.e. e = E_T/E′), the rubbing force `rubbing` = F_n^b/(bG_c), and the
/// crack-root rotation correction χ (0.64). Solves Eq. 19 at its first root on a logarithmic grid of k_0 from 1e-3
/// to 1e6 (the reference implementation's), refined by bisection. None when Eq. 19 has no root (e.g. Z > 0 at
/// η < 1: no bending model for μ > tan α).
pub fn bending(eta: f64, alpha: f64, mu: f64, e: f64, rubbing: f64, s: &Specimen, chi: f64) -> Option<Bending> {
    let z = z(mu, alpha);
    let den = 1.0 - alpha.sin() - z * alpha.cos();
    let c = 2.0 * chi * s.yield_stress / s.plane_modulus;
    let r = |k: f64| {
        a1(k, eta, e) - 1.0 - c * k / den * (z + z * a2(k, eta, e) + (1.0 - mu * z) * rubbing * (1.0 - alpha.sin()))
    };
    const N: usize = 4000;
    let at = |i: usize| 10f64.powf(-3.0 + 9.0 * i as f64 / (N - 1) as f64);
    let (mut lo, mut rlo) = (at(0), r(at(0)));
    for i in 1..N {
        let hi = at(i);
        let rhi = r(hi);
        if rlo.signum() != rhi.signum() {
            let (mut a, mut b, ra) = (lo, hi, rlo);
            for _ in 0..200 {
                let m = 0.5 * (a + b);
                if r(m).signum() == ra.signum() { a = m } else { b = m }
            }
            let k0 = 0.5 * (a + b);
            let force = (1.0 + a2(k0, eta, e) + (1.0 - mu * z) * rubbing * alpha.cos()) / den;
            return Some(Bending { force, k0 });
        }
        (lo, rlo) = (hi, rhi);
    }
    None
}

/// The factor 1 + sin λ/cos α (μ = tan λ) by which a linear extrapolation of frictional touching-regime forces to
/// h = 0 overestimates G_c, asymptotically (§4.2).
pub fn intercept_bias(mu: f64, alpha: f64) -> f64 {
    1.0 + mu.atan().sin() / alpha.cos()
}

/// Least-squares line through (h, F_c/b): (slope, intercept).
pub fn linear_fit(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let (sx, sy) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = points.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    let slope = sxy / sxx;
    (slope, my - slope * mx)
}

/// G_c fitted to touching-regime points (h, F_c/b, F_n^b/b) by least squares on Eq. 14, with σ_y, E′, α, μ known
/// (§4.2: the way to recover the toughness from frictional data). Golden-section search on [0, 10·max F_c/b].
pub fn fit_toughness(points: &[(f64, f64, f64)], alpha: f64, mu: f64, s: &Specimen) -> f64 {
    let sse = |gc: f64| {
        let sp = Specimen { toughness: gc, ..*s };
        points.iter().map(|(h, f, fnb)| (touching(*h, alpha, mu, *fnb, &sp) - f).powi(2)).sum::<f64>()
    };
    let top = points.iter().map(|p| p.1).fold(0.0, f64::max) * 10.0;
    let (mut a, mut b) = (0.0, top.max(1.0));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..300 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if sse(c) < sse(d) { b = d } else { a = c }
    }
    0.5 * (a + b)
}

/// A table of both models' predictions over the depths of cut `depths` [m] (`swarf model`): η, the touching model's
/// F_c/b [N/m] and F_c/(bG_c) with its shear angle, the bending model's F_c/(bG_c) and k_0 (or "none" where Eq. 19
/// has no root). `e` = E_T/E′, `rubbing` = F_n^b/b [N/m], χ = CHI.
pub fn table(s: &Specimen, alpha: f64, mu: f64, e: f64, rubbing: f64, depths: &[f64]) -> String {
    let mut out = format!(
        "Nairn's models (nairn-mpm.md §4): σ_y0 = {:.4e} Pa, E' = {:.4e} Pa, G_c = {} J/m², Y = {:.4}, rake {:.2}°, \
         μ = {mu}, E_T/E' = {e:.4}, F_n^b/b = {rubbing} N/m\n",
        s.yield_stress,
        s.plane_modulus,
        s.toughness,
        s.yield_ratio,
        alpha.to_degrees()
    );
    out.push_str(
        "| h [mm] | eta | touching F_c/b [N/m] | touching F_c/(bG_c) | shear angle [deg] | bending F_c/(bG_c) | k0 |\n",
    );
    out.push_str("|---|---|---|---|---|---|---|\n");
    for &h in depths {
        let eta = s.eta(h);
        let t = touching(h, alpha, mu, rubbing, s);
        let phi = optimum_shear_angle(h, alpha, mu, rubbing, s).to_degrees();
        let bend = match bending(eta, alpha, mu, e, rubbing / s.toughness, s, CHI) {
            Some(b) => format!("{:.2} | {:.3}", b.force, b.k0),
            None => "none | -".to_string(),
        };
        out.push_str(&format!("| {:.3} | {eta:.4} | {t:.0} | {:.2} | {phi:.2} | {bend} |\n", h * 1e3, t / s.toughness));
    }
    out
}
