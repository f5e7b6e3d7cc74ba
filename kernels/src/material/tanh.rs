//! Johnson–Cook extensions with strain softening for Ti6Al4V: Calamaz 2008 (TANH), 2010, 2011 and Sima–Özel
//! SO1–SO3 (klippel-constitutive.md §2.3, Eqs. 8.1–8.17; roethlin-solver.md §2.4 (7.11)).
//!
//! All share the JC rate and thermal factors of [`JohnsonCook`] (its low-rate form and temperature clamps apply
//! unchanged) and use the absolute ratio T/Tm (T clamped to [0, Tm − 1 K]) in their tanh factors, not T*
//! (klippel §2.3). The strain derivatives are analytic (Klippel integrates these models with Secant B only because
//! the derivatives are costly, §8.1.1.1; here both solvers work).

use super::{Flow, FlowStress, JohnsonCook, STRAIN_FLOOR, fmax, pow, sech2};
use bytemuck::{Pod, Zeroable};

/// A + B ε̄ⁿ exp(−ε̄^a) and its derivative B e^{−ε̄^a} ε̄ⁿ⁻¹ (n − a ε̄^a) (klippel Eqs. 8.4, 8.6), the latter at
/// max(ε̄, STRAIN_FLOOR).
#[inline(always)]
fn softened_hardening(jc: &JohnsonCook, a: f64, eps: f64) -> (f64, f64) {
    let e = fmax(eps, 0.0);
    let h = jc.a + jc.b * pow(e, jc.n) * libm::exp(-pow(e, a));
    let ed = fmax(eps, STRAIN_FLOOR);
    let ea = pow(ed, a);
    (h, jc.b * libm::exp(-ea) * pow(ed, jc.n - 1.0) * (jc.n - a * ea))
}

/// g + (1 − g)·tanh((ε̄ + p)^(−r))^s and its ε̄-derivative (1 − g) s tanhˢ⁻¹(x) sech²(x)·(−r x/(ε̄ + p)),
/// x = (ε̄ + p)^(−r) (klippel Eq. 8.7 for s = 1), the latter at max(ε̄, STRAIN_FLOOR).
#[inline(always)]
fn tanh_factor(g: f64, p: f64, r: f64, s: f64, eps: f64) -> (f64, f64) {
    let e = fmax(eps, 0.0);
    let x = pow(e + p, -r);
    let f = g + (1.0 - g) * pow(libm::tanh(x), s);
    let u = fmax(eps, STRAIN_FLOOR) + p;
    let x = pow(u, -r);
    let sh = sech2(x);
    let df = if sh == 0.0 { 0.0 } else { (1.0 - g) * s * pow(libm::tanh(x), s - 1.0) * sh * (-r * x / u) };
    (f, df)
}

/// σ = h(ε̄)·R(ε̄̇)·Θ(T)·F(ε̄) with the JC rate and thermal factors.
#[inline(always)]
fn compose(jc: &JohnsonCook, (h, dh): (f64, f64), (f, df): (f64, f64), rate: f64, temp: f64) -> Flow {
    let (r, dr) = jc.rate_factor(rate);
    let th = jc.thermal_factor(temp);
    Flow { sigma: h * r * th * f, d_eps: (dh * f + h * df) * r * th, d_rate: h * dr * th * f }.clamped()
}

/// JC-TANH2008, Calamaz 2008 (klippel §2.3 Eqs. 8.1–8.4; roethlin-solver.md §2.4 (7.11)):
/// σ_y = [A + B ε̄ⁿ exp(−ε̄^a)]·[1 + C ln ε̄̇*]·[1 − θᵐ]·[D + (1 − D) tanh(1/(ε̄ + S)^c)],
/// D = 1 − (T/Tm)^d, S = (T/Tm)^b. exp(−ε̄^a) multiplies only the B term (Eqs. 8.4, 8.6).
/// Röthlin Tab 7.8: a = 1.6, b = 0.4, c = 6, d = 1 ([C2D]: 1.1, 0.4, 12, 1).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Calamaz2008 {
    pub jc: JohnsonCook,
    /// a: exponent of the strain softening exp(−ε̄^a) [-].
    pub a: f64,
    /// b: S = (T/Tm)^b [-].
    pub b: f64,
    /// c: tanh(1/(ε̄ + S)^c) [-].
    pub c: f64,
    /// d: D = 1 − (T/Tm)^d [-].
    pub d: f64,
}

impl FlowStress for Calamaz2008 {
    #[inline]
    fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.flow(eps, rate, temp).sigma
    }

    #[inline]
    fn flow(&self, eps: f64, rate: f64, temp: f64) -> Flow {
        let tau = self.jc.melt_ratio(temp);
        let g = 1.0 - pow(tau, self.d);
        let p = pow(tau, self.b);
        compose(&self.jc, softened_hardening(&self.jc, self.a, eps), tanh_factor(g, p, self.c, 1.0, eps), rate, temp)
    }

    #[inline(always)]
    fn melt_temperature(&self) -> f64 {
        self.jc.melt_temp
    }
}

/// JC-TANH2010, Calamaz 2010 (klippel §2.3 Eqs. 8.11–8.12):
/// σ_y = [A + B ε̄ⁿ]·[1 + C ln ε̄̇*]·[1 − θᵐ]·[g + (1 − g) tanh(1/(ε̄ + ε₀))],
/// g = 1 − (p ε̄/(1 + p ε̄))·tanh((T − T0)/(T_rec − T0))^q.
/// The exponent q applies to tanh(·), as printed (klippel's [NOTE] calls it ambiguous); its argument is clamped
/// ≥ 0 (no softening term below T0, where tanh(·)^q would be negative or undefined). T is clamped as in JC.
/// Klippel Tab 8.3/8.7: ε₀ = 0.7, p = 0.6, T_rec = 600 K, q = 5.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Calamaz2010 {
    pub jc: JohnsonCook,
    /// ε₀: strain offset of tanh(1/(ε̄ + ε₀)) (strain at peak stress) [-].
    pub eps0: f64,
    /// p: post-peak slope parameter [-].
    pub p: f64,
    /// T_rec: softening onset temperature [K].
    pub t_rec: f64,
    /// q: temperature-range exponent [-].
    pub q: f64,
}

impl FlowStress for Calamaz2010 {
    #[inline]
    fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.flow(eps, rate, temp).sigma
    }

    #[inline]
    fn flow(&self, eps: f64, rate: f64, temp: f64) -> Flow {
        let t = super::clamp_below_melt(temp, self.jc.melt_temp);
        let arg = fmax((t - self.jc.ref_temp) / (self.t_rec - self.jc.ref_temp), 0.0);
        let z = pow(libm::tanh(arg), self.q);
        let e = fmax(eps, 0.0);
        let w = self.p * e / (1.0 + self.p * e);
        let f = 1.0 - w * z * (1.0 - libm::tanh(1.0 / (e + self.eps0)));
        // F = 1 − wZ(1 − t): dF/dε̄ = −Z [w'(1 − t) − w t'], t' = −sech²(1/(ε̄+ε₀))/(ε̄+ε₀)².
        let ed = fmax(eps, STRAIN_FLOOR);
        let wd = self.p * ed / (1.0 + self.p * ed);
        let dw = self.p / ((1.0 + self.p * ed) * (1.0 + self.p * ed));
        let u = ed + self.eps0;
        let tt = libm::tanh(1.0 / u);
        let d_tanh = -sech2(1.0 / u) / (u * u);
        let df = -z * (dw * (1.0 - tt) - wd * d_tanh);
        compose(&self.jc, self.jc.hardening(eps), (f, df), rate, temp)
    }

    #[inline(always)]
    fn melt_temperature(&self) -> f64 {
        self.jc.melt_temp
    }
}

/// Coefficient of the rate-dependent hardening exponent of Calamaz 2011, n − 0.12 (ε̄ ε̄̇)^a (klippel Eq. 8.13).
pub const CALAMAZ_2011_K: f64 = 0.12;

/// JC-CALAMAZ2011 (klippel §2.3 Eq. 8.13):
/// σ_y = [A + B (1/ε̄̇*)^a ε̄^(n − 0.12 (ε̄ ε̄̇*)^a)]·[1 + C ln ε̄̇*]·[1 − θᵐ], a ∈ {0, 0.11, 0.22} (Tab 8.3).
///
/// * ε̄̇* = ε̄̇/ε̄̇0 is clamped ≥ 1 inside the B term (the thesis prints 1/ε̄̇ and ε̄·ε̄̇ with ε̄̇0 = 1 /s, identical
///   above 1 /s; the clamp keeps (1/ε̄̇)^a finite at ε̄̇ = 0, the same "no rate effect below ε̄̇0" as the JC clamp).
/// * The exponent n − 0.12 (ε̄ ε̄̇*)^a is floored at 0, so σ_y stays bounded as ε̄ → 0 (only reachable with a = 0
///   and n < 0.12; no published set). Note a = 0 gives ε̄^(n − 0.12), i.e. only approximately JC (klippel §2.3
///   says "JC-classic ≈ CALAMAZ2011 with a = 0").
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Calamaz2011 {
    pub jc: JohnsonCook,
    /// a: rate exponent [-].
    pub a: f64,
}

impl FlowStress for Calamaz2011 {
    #[inline]
    fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.flow(eps, rate, temp).sigma
    }

    #[inline]
    fn flow(&self, eps: f64, rate: f64, temp: f64) -> Flow {
        let jc = &self.jc;
        let a = self.a;
        let r_raw = rate / jc.ref_rate;
        let above = r_raw > 1.0;
        let r = if above { r_raw } else { 1.0 };
        let ra = pow(r, -a);
        let e = fmax(eps, 0.0);
        let k = fmax(jc.n - CALAMAZ_2011_K * pow(e * r, a), 0.0);
        let h = jc.a + jc.b * ra * pow(e, k);
        // Derivatives at max(ε̄, STRAIN_FLOOR): with term = B r^-a ε̄^k, k = n − K (ε̄ r)^a,
        // ∂term/∂ε̄ = term/ε̄ (k − K a (ε̄ r)^a ln ε̄), ∂term/∂r = term/r (−a − K a (ε̄ r)^a ln ε̄)
        // (the K terms vanish where the floor of k is active).
        let ed = fmax(eps, STRAIN_FLOOR);
        let era = pow(ed * r, a);
        let k_raw = jc.n - CALAMAZ_2011_K * era;
        let kd = fmax(k_raw, 0.0);
        let term = jc.b * ra * pow(ed, kd);
        let dk_ln = if k_raw > 0.0 { CALAMAZ_2011_K * a * era * libm::log(ed) } else { 0.0 };
        let dh_eps = term / ed * (kd - dk_ln);
        let dh_rate = if above { term / r * (-a - dk_ln) / jc.ref_rate } else { 0.0 };
        let (rf, drf) = jc.rate_factor(rate);
        let th = jc.thermal_factor(temp);
        Flow { sigma: h * rf * th, d_eps: dh_eps * rf * th, d_rate: (dh_rate * rf + h * drf) * th }.clamped()
    }

    #[inline(always)]
    fn melt_temperature(&self) -> f64 {
        self.jc.melt_temp
    }
}

/// JC-TANHSO1, Sima–Özel (klippel §2.3 Eq. 8.14):
/// σ_y = [A + B ε̄ⁿ]·[1 + C ln ε̄̇*]·[1 − θᵐ]·[M + (1 − M)·(tanh(1/(ε̄ + p)^r))^S].
/// Klippel Tab 8.3: p = 0, r = 1, S = 7, M = 0.7 (at ε̄ = 0 with p = 0, 1/0^r = ∞ and tanh = 1).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SimaOzel1 {
    pub jc: JohnsonCook,
    /// M: the softening floor [-].
    pub big_m: f64,
    /// p: strain offset [-].
    pub p: f64,
    /// r: inner exponent [-].
    pub r: f64,
    /// S: outer exponent [-].
    pub s: f64,
}

impl FlowStress for SimaOzel1 {
    #[inline]
    fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.flow(eps, rate, temp).sigma
    }

    #[inline]
    fn flow(&self, eps: f64, rate: f64, temp: f64) -> Flow {
        let f = tanh_factor(self.big_m, self.p, self.r, self.s, eps);
        compose(&self.jc, self.jc.hardening(eps), f, rate, temp)
    }

    #[inline(always)]
    fn melt_temperature(&self) -> f64 {
        self.jc.melt_temp
    }
}

/// JC-TANHSO2, Sima–Özel (klippel §2.3 Eqs. 8.15–8.16):
/// σ_y = [A + B ε̄ⁿ]·[1 + C ln ε̄̇*]·[1 − θᵐ]·[g + (1 − g)·(tanh(1/(ε̄ + p)^r))^S], g = 1 − (T/Tm)^d,
/// p = (T/Tm)^b. Klippel Tab 8.3: b = 1, d = 0.5, r = 1, S = 5.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SimaOzel2 {
    pub jc: JohnsonCook,
    /// b: p = (T/Tm)^b [-].
    pub b: f64,
    /// d: g = 1 − (T/Tm)^d [-].
    pub d: f64,
    /// r: inner exponent [-].
    pub r: f64,
    /// S: outer exponent [-].
    pub s: f64,
}

impl FlowStress for SimaOzel2 {
    #[inline]
    fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.flow(eps, rate, temp).sigma
    }

    #[inline]
    fn flow(&self, eps: f64, rate: f64, temp: f64) -> Flow {
        let tau = self.jc.melt_ratio(temp);
        let f = tanh_factor(1.0 - pow(tau, self.d), pow(tau, self.b), self.r, self.s, eps);
        compose(&self.jc, self.jc.hardening(eps), f, rate, temp)
    }

    #[inline(always)]
    fn melt_temperature(&self) -> f64 {
        self.jc.melt_temp
    }
}

/// JC-TANHSO3, Sima–Özel (klippel §2.3 Eq. 8.17):
/// σ_y = [A + B ε̄ⁿ exp(−ε̄^a)]·[1 + C ln ε̄̇*]·[1 − θᵐ]·[g + (1 − g)·(tanh(1/(ε̄ + p)^r))^S],
/// g = 1 − (T/Tm)^d, p = (T/Tm)^b. With S = 1 and r = c it is TANH2008. Klippel Tab 8.7 (cutting runs):
/// a = 2, b = 5, d = 1, r = 1, S = 0.05; Tab 8.3: a = 2, b = 1, d = 0.5, r = 1, S = 5.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SimaOzel3 {
    pub jc: JohnsonCook,
    /// a: exponent of exp(−ε̄^a) [-].
    pub a: f64,
    /// b: p = (T/Tm)^b [-].
    pub b: f64,
    /// d: g = 1 − (T/Tm)^d [-].
    pub d: f64,
    /// r: inner exponent [-].
    pub r: f64,
    /// S: outer exponent [-].
    pub s: f64,
}

impl FlowStress for SimaOzel3 {
    #[inline]
    fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.flow(eps, rate, temp).sigma
    }

    #[inline]
    fn flow(&self, eps: f64, rate: f64, temp: f64) -> Flow {
        let tau = self.jc.melt_ratio(temp);
        let f = tanh_factor(1.0 - pow(tau, self.d), pow(tau, self.b), self.r, self.s, eps);
        compose(&self.jc, softened_hardening(&self.jc, self.a, eps), f, rate, temp)
    }

    #[inline(always)]
    fn melt_temperature(&self) -> f64 {
        self.jc.melt_temp
    }
}
