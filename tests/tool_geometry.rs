//! The tool-geometry seam and the rigid tool motion (kernels/src/contact/{geometry,motion}.rs, host/cutting/motion.rs):
//! the 2D parametric tool's answers through the trait equal its own `closest`/`contains` bit for bit; the signed
//! distance, normal and closest point near the rake, the flank and the edge arc against the construction's
//! analytic values (roethlin-solver.md §5.4); the generic contact law in 2D equal to the previous 2D law bit for
//! bit (a frozen copy below); a rotating tool's velocity against v + ω × r; and a ramped rotating motion's offset
//! and angle against the integral of its velocities.
//!
//! Units: SI. Tolerances are stated at each assertion with their source.

use swarf::cutting::motion::{Rotation, ToolMotion, rotation_matrix};
use swarf::kernels::contact::penalty::{ContactParams, cap, contact_force};
use swarf::kernels::contact::tool2d::{Tool2d, ToolShape};
use swarf::kernels::contact::{ToolGeometry, ToolState};
use swarf::rng::SplitMix64;

const UM: f64 = 1e-6;
/// The tools' size (0.4 mm × 0.43 mm), the scale of the absolute tolerances.
const SCALE: f64 = 1e-3;

fn tool(rake_deg: f64, clearance_deg: f64, radius_um: f64) -> Tool2d {
    let s = ToolShape {
        rake_angle: rake_deg.to_radians(),
        clearance_angle: clearance_deg.to_radians(),
        edge_radius: radius_um * UM,
        length: 0.4e-3,
        height: 0.43e-3,
    };
    Tool2d::new(&s).expect("a valid tool")
}

/// AT-40's tool (γ = 10°, α = 8°, r = 20 µm), a negative rake, α = 0 and a sharp edge.
fn tools() -> Vec<Tool2d> {
    vec![tool(10.0, 8.0, 20.0), tool(-20.0, 5.0, 15.0), tool(10.0, 0.0, 20.0), tool(10.0, 8.0, 0.0)]
}

fn bits3(a: [f64; 3]) -> [u64; 3] {
    a.map(f64::to_bits)
}

#[test]
fn trait_answers_equal_closest_and_contains_bit_for_bit() {
    let mut rng = SplitMix64::new(0x7001);
    for t in tools() {
        let mut inside = 0;
        for k in 0..20_000 {
            // Half the points within 30 µm of the edge (where the primitives compete), half over the whole tool.
            let span = if k % 2 == 0 { 60.0 * UM } else { 1.2e-3 };
            let p = [(rng.uniform() - 0.7) * span, (rng.uniform() - 0.3) * span];
            let z = (rng.uniform() - 0.5) * 1e-3;
            let want = t.closest(p);
            let got = ToolGeometry::query(&t, [p[0], p[1], z]);
            assert_eq!(got.distance.to_bits(), want.distance.to_bits(), "distance at {p:?}");
            assert_eq!(bits3(got.normal), bits3([want.normal[0], want.normal[1], 0.0]), "normal at {p:?}");
            assert_eq!(bits3(got.point), bits3([want.point[0], want.point[1], z]), "closest point at {p:?}");
            let c = t.contains(p);
            assert_eq!(ToolGeometry::contains(&t, [p[0], p[1], z]), c, "contains at {p:?}");
            inside += c as usize;
        }
        assert!(inside > 1000 && inside < 19_000, "{inside} points inside: the sample must straddle the outline");
    }
}

fn assert_close(got: [f64; 3], want: [f64; 3], tol: f64, what: &str) {
    let err = (0..3).map(|k| (got[k] - want[k]).abs()).fold(0.0, f64::max);
    assert!(err <= tol, "{what}: got {got:?}, want {want:?} (error {err:e} > {tol:e})");
}

#[test]
fn distance_normal_and_closest_point_near_rake_flank_and_arc() {
    // The construction (tool2d.rs module doc): the arc's lowest point is the origin, so its centre is (0, r); the
    // rake line is tangent to the arc at c + r n_r, n_r = (cos γ, sin γ), running up along (−sin γ, cos γ); the
    // flank line at c + r n_f, n_f = (−sin α, −cos α), running back along (−cos α, sin α).
    let (g, a, r) = (10f64.to_radians(), 8f64.to_radians(), 20.0 * UM);
    let t = tool(10.0, 8.0, 20.0);
    let c = [0.0, r];
    let on_line = |n: [f64; 2], d: [f64; 2], s: f64| [c[0] + r * n[0] + s * d[0], c[1] + r * n[1] + s * d[1]];
    let n_r = [g.cos(), g.sin()];
    let n_f = [-a.sin(), -a.cos()];
    let mut cases = Vec::new();
    for s in [30.0 * UM, 100.0 * UM, 250.0 * UM] {
        cases.push(("rake", on_line(n_r, [-g.sin(), g.cos()], s), n_r));
        cases.push(("flank", on_line(n_f, [-a.cos(), a.sin()], s), n_f));
    }
    // The arc between its flank end (angle −(90° − α)) and its rake end (γ).
    for deg in [-70.0f64, -36.0, 0.0] {
        let n = [deg.to_radians().cos(), deg.to_radians().sin()];
        cases.push(("arc", [c[0] + r * n[0], c[1] + r * n[1]], n));
    }
    for (what, q, n) in cases {
        for h in [-5.0 * UM, -0.5 * UM, 0.3 * UM, 4.0 * UM] {
            let p = [q[0] + h * n[0], q[1] + h * n[1], 0.0];
            let sp = ToolGeometry::query(&t, p);
            let at = format!("{what} at {q:?}, offset {h:e} along the normal");
            // AT-41: exact signed distance to 1e-12 of the tool's size; the normal to 1e-9 (it is recomputed from
            // the closest point outside, so it carries the distance's rounding over h ≥ 0.3 µm); the point to 1e-12
            // of the tool's size.
            assert!((sp.distance - h).abs() <= 1e-12 * SCALE, "{at}: distance {:e}", sp.distance);
            assert_close(sp.normal, [n[0], n[1], 0.0], 1e-9, &format!("{at}: normal"));
            assert_close(sp.point, [q[0], q[1], 0.0], 1e-12 * SCALE, &format!("{at}: closest point"));
            assert_eq!(ToolGeometry::contains(&t, p), h < 0.0, "{at}: inside");
        }
    }
}

// ---------------------------------------------------------------------------------------------------------------
// The previous 2D contact law, frozen verbatim (kernels/src/contact/penalty.rs before the geometry seam, with the
// tool inside the parameters and a translating [f64; 2] tool state): the generic law must give its bits in 2D.

fn old_friction_update(f_old: [f64; 2], v_t: [f64; 2], k: f64, f_max: f64) -> [f64; 2] {
    let fs = [f_old[0] - k * v_t[0], f_old[1] - k * v_t[1]];
    let m2 = fs[0] * fs[0] + fs[1] * fs[1];
    if m2 <= f_max * f_max {
        fs
    } else {
        let s = f_max / m2.sqrt();
        [s * fs[0], s * fs[1]]
    }
}

#[allow(clippy::too_many_arguments)]
fn old_contact_force(
    c: &ContactParams,
    tool: &Tool2d,
    offset: [f64; 2],
    velocity: [f64; 2],
    (dt, step): (f64, f64),
    x: [f64; 2],
    v: [f64; 2],
    f_old: [f64; 2],
    (m, rho, temp, cp, yield_stress): (f64, f64, f64, f64, f64),
) -> ([f64; 2], [f64; 2], f64, f64) {
    let q = tool.closest([x[0] - offset[0], x[1] - offset[1]]);
    if q.distance.partial_cmp(&0.0) != Some(std::cmp::Ordering::Less) {
        return ([0.0; 2], [0.0; 2], 0.0, 0.0);
    }
    let n = q.normal;
    let depth = -q.distance;
    let fc = c.kappa * m * depth / (dt * dt);
    let normal = [fc * n[0], fc * n[1]];
    let vr = [v[0] - velocity[0], v[1] - velocity[1]];
    let vn = vr[0] * n[0] + vr[1] * n[1];
    let vt = [vr[0] - vn * n[0], vr[1] - vn * n[1]];
    let on = f_old[0] * n[0] + f_old[1] * n[1];
    let f_prev = [f_old[0] - on * n[0], f_old[1] - on * n[1]];
    let area = (m / rho).sqrt();
    let mut f_max = c.friction * fc;
    if c.cap_mode != cap::NONE {
        let tau = if c.cap_mode == cap::CURRENT { c.cap_stress * yield_stress } else { c.cap_stress };
        let lim = tau * area;
        if lim < f_max {
            f_max = lim;
        }
    }
    let friction = old_friction_update(f_prev, vt, c.friction_kappa * m / dt, f_max);
    let ft = (friction[0] * friction[0] + friction[1] * friction[1]).sqrt();
    let slip = (vt[0] * vt[0] + vt[1] * vt[1]).sqrt();
    let heating = if c.heat_fraction > 0.0 && cp > 0.0 { c.heat_fraction * step * ft * slip / (m * cp) } else { 0.0 };
    let wear = if c.usui_psi > 0.0 && temp > 0.0 {
        c.usui_psi * libm::exp(-c.usui_xi / temp) * (fc / area) * slip
    } else {
        0.0
    };
    (normal, friction, heating, wear)
}

#[test]
fn generic_contact_law_in_2d_equals_the_previous_law_bit_for_bit() {
    let mut rng = SplitMix64::new(0x7002);
    let mut touching = 0;
    for t in tools() {
        for k in 0..20_000 {
            let u = |rng: &mut SplitMix64, a: f64, b: f64| a + (b - a) * rng.uniform();
            let c = ContactParams {
                kappa: u(&mut rng, 0.05, 1.0),
                friction_kappa: u(&mut rng, 0.05, 1.0),
                friction: u(&mut rng, 0.0, 0.6),
                cap_stress: u(&mut rng, 1e7, 1e9),
                heat_fraction: if k % 3 == 0 { 0.0 } else { 0.9 },
                usui_psi: if k % 4 == 0 { 0.0 } else { 1e-12 },
                usui_xi: 1500.0,
                melt: 1900.0,
                cap_mode: [cap::NONE, cap::STATIC, cap::CURRENT][k % 3],
                // The theses' law, undamped, projected slip (the defaults), which the previous law was.
                ..Default::default()
            };
            let offset = [u(&mut rng, -1e-3, 1e-3), u(&mut rng, -1e-3, 1e-3)];
            let velocity = [u(&mut rng, -5.0, 5.0), u(&mut rng, -5.0, 5.0)];
            let (dt, step) = (1e-9, if k % 5 == 0 { 0.3e-9 } else { 1e-9 });
            let x = [offset[0] + u(&mut rng, -40.0, 20.0) * UM, offset[1] + u(&mut rng, -10.0, 50.0) * UM];
            let v = [u(&mut rng, -10.0, 10.0), u(&mut rng, -10.0, 10.0)];
            let f_old = [u(&mut rng, -1e4, 1e4), u(&mut rng, -1e4, 1e4)];
            let (m, rho, temp, cp, sy) = (4.43e-7, 4430.0, u(&mut rng, 0.0, 1500.0), 560.0, u(&mut rng, 1e8, 1e9));
            let s = ToolState {
                offset: [offset[0], offset[1], 0.0],
                velocity: [velocity[0], velocity[1], 0.0],
                dt,
                step,
                ..Default::default()
            };
            let r = contact_force(&c, &t, &s, x, v, f_old, m, rho, temp, cp, sy);
            let (normal, friction, heating, wear) =
                old_contact_force(&c, &t, offset, velocity, (dt, step), x, v, f_old, (m, rho, temp, cp, sy));
            let what = format!("case {k} at {x:?}");
            assert_eq!(r.normal.map(f64::to_bits), normal.map(f64::to_bits), "{what}: normal");
            assert_eq!(r.friction.map(f64::to_bits), friction.map(f64::to_bits), "{what}: friction");
            assert_eq!((r.heating.to_bits(), r.wear.to_bits()), (heating.to_bits(), wear.to_bits()), "{what}");
            touching += (normal != [0.0; 2]) as usize;
        }
    }
    assert!(touching > 10_000, "{touching} contacts: the comparison must exercise the law");
}

#[test]
fn the_2d_tool_in_3d_is_its_prism() {
    // With no velocity, history or cap along z, the 3D law on the prism gives the 2D forces in x and y, bit for
    // bit (the z terms add exact zeros), and no force along z.
    let t = tool(10.0, 8.0, 20.0);
    let c = ContactParams { kappa: 0.1, friction_kappa: 0.1, friction: 0.35, ..Default::default() };
    let s = ToolState { velocity: [1.5, -0.5, 0.0], dt: 1e-9, step: 1e-9, ..Default::default() };
    let mut rng = SplitMix64::new(0x7003);
    let mut touching = 0;
    for _ in 0..5000 {
        let x = [(rng.uniform() - 0.7) * 60.0 * UM, (rng.uniform() - 0.2) * 60.0 * UM];
        let v = [rng.normal(), rng.normal()];
        let f = [1e3 * rng.normal(), 1e3 * rng.normal()];
        let z = (rng.uniform() - 0.5) * 1e-3;
        let r2 = contact_force(&c, &t, &s, x, v, f, 4.43e-7, 4430.0, 300.0, 560.0, 0.0);
        let r3 = contact_force(
            &c,
            &t,
            &s,
            [x[0], x[1], z],
            [v[0], v[1], 0.0],
            [f[0], f[1], 0.0],
            4.43e-7,
            4430.0,
            300.0,
            560.0,
            0.0,
        );
        assert_eq!(bits3(r3.normal), bits3([r2.normal[0], r2.normal[1], 0.0]), "normal at {x:?}");
        assert_eq!(bits3(r3.friction), bits3([r2.friction[0], r2.friction[1], 0.0]), "friction at {x:?}");
        touching += (r2.normal != [0.0; 2]) as usize;
    }
    assert!(touching > 500, "{touching} contacts");
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn rotating() -> ToolMotion {
    let a = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
    ToolMotion {
        start: [1e-3, -2e-3, 0.5e-3],
        velocity: [2.0, -1.0, 0.5],
        ramp: 1e-6,
        rotation: Some(Rotation { axis: a, centre: [0.2e-3, 0.1e-3, -0.3e-3], rate: 3.0e5 }),
    }
}

#[test]
fn rotating_tool_velocity_is_v_plus_omega_cross_r() {
    let m = rotating();
    let mut rng = SplitMix64::new(0x7004);
    for t in [0.0, 0.4e-6, 1e-6, 3.7e-6] {
        let s = m.state_at(t, 1e-9, 1e-9);
        assert_eq!(s.rotating, 1);
        let (o, v) = (m.offset_at(t), m.velocity_at(t));
        let w = m.rotation.unwrap().axis.map(|a| a * m.angular_velocity_at(t));
        let c = m.rotation.unwrap().centre;
        for _ in 0..100 {
            let x: [f64; 3] = std::array::from_fn(|k| o[k] + 1e-3 * rng.normal());
            let r: [f64; 3] = std::array::from_fn(|k| x[k] - o[k] - c[k]);
            let wr = cross(w, r);
            let want: [f64; 3] = std::array::from_fn(|k| v[k] + wr[k]);
            // The same products in another grouping: 1e-15 of |v| + |ω||r| (a few roundings).
            let scale = 2.5 + 3e5 * 3e-3;
            assert_close(s.velocity_at(x), want, 1e-15 * scale, &format!("t = {t:e}, x = {x:?}"));
            // The tool-frame map and its inverse: x → p → x to 1e-15 of the 3 mm scale.
            assert_close(s.point_to_world(s.to_tool(x)), x, 3e-18 * 1e3, "round trip");
        }
    }
    // Without a rotation the state takes the translating path: no rotation data, v_tool = v exactly.
    let plain = ToolMotion { rotation: None, ..m }.state_at(2e-6, 1e-9, 1e-9);
    assert_eq!(plain.rotating, 0);
    assert_eq!(plain.velocity_at([1.0, 2.0, 3.0]), plain.velocity);
    assert_eq!(plain.to_tool([1.0, 2.0, 3.0]), std::array::from_fn(|k| [1.0, 2.0, 3.0][k] - plain.offset[k]));
}

#[test]
fn rotation_matrix_is_a_right_handed_rotation_by_the_angle() {
    let a = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
    for angle in [0.0, 0.3, -1.2, 2.9, 10.0] {
        let r = rotation_matrix(a, angle);
        // Orthonormal with determinant +1, the axis fixed: 1e-15 (entries of size 1).
        for i in 0..3 {
            for j in 0..3 {
                let d: f64 = (0..3).map(|k| r[k][i] * r[k][j]).sum();
                assert!((d - (i == j) as u8 as f64).abs() <= 1e-15, "RᵀR at ({i}, {j}): {d}");
            }
        }
        let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
            + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        assert!((det - 1.0).abs() <= 1e-15, "det {det}");
        let ra: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| r[i][j] * a[j]).sum());
        assert_close(ra, a, 1e-15, "the axis");
        // A vector normal to the axis turns by the angle, counter-clockwise seen from the axis's tip.
        let u = [2.0 / 3.0, 1.0 / 3.0, -2.0 / 3.0];
        let ru: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| r[i][j] * u[j]).sum());
        let cu = cross(a, u);
        let want: [f64; 3] = std::array::from_fn(|k| angle.cos() * u[k] + angle.sin() * cu[k]);
        assert_close(ru, want, 1e-15, &format!("angle {angle}"));
    }
    // In the plane (axis z) a quarter turn takes x to y.
    let q = rotation_matrix([0.0, 0.0, 1.0], std::f64::consts::FRAC_PI_2);
    assert_close([q[0][0], q[1][0], q[2][0]], [0.0, 1.0, 0.0], 1e-16, "x → y");
}

/// ∫ f over [a, b] by Simpson's rule on n (even) intervals: exact for the ramp's piecewise linear velocity when
/// the ramp's end is an end of the range.
fn simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let inner: f64 = (1..n).map(|i| f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 }).sum();
    (f(a) + inner + f(b)) * h / 3.0
}

#[test]
fn ramped_rotating_motion_integrates_its_velocities() {
    let m = rotating();
    for t in [0.0, 0.3e-6, 1e-6, 2.7e-6, 40e-6] {
        // Split at the ramp's end so that each piece is linear (Simpson exact there); 1e-12 relative to the
        // distance travelled and the angle turned (the sums' rounding over 200 nodes).
        let pieces = if t > m.ramp { vec![(0.0, m.ramp), (m.ramp, t)] } else { vec![(0.0, t)] };
        let integral = |f: &dyn Fn(f64) -> f64| pieces.iter().map(|&(a, b)| simpson(f, a, b, 200)).sum::<f64>();
        let o = m.offset_at(t);
        for (k, ok) in o.iter().enumerate() {
            let want = m.start[k] + integral(&|s| m.velocity_at(s)[k]);
            let travel = (m.velocity[k] * t).abs();
            assert!((ok - want).abs() <= 1e-12 * travel + 1e-18, "t = {t:e}: offset[{k}] {ok} against {want}");
        }
        let angle = integral(&|s| m.angular_velocity_at(s));
        let turned = m.rotation.unwrap().rate * t;
        assert!(
            (m.angle_at(t) - angle).abs() <= 1e-12 * turned + 1e-18,
            "t = {t:e}: angle {} against {angle}",
            m.angle_at(t)
        );
        // The state the kernels see carries R(θ(t)) and ω(t) = θ̇(t) a.
        let s = m.state_at(t, 1e-9, 1e-9);
        assert_eq!(s.rotation, rotation_matrix(m.rotation.unwrap().axis, m.angle_at(t)));
        assert_eq!(s.omega, m.rotation.unwrap().axis.map(|a| a * m.angular_velocity_at(t)));
    }
    // The ramp: half the final velocity at half the ramp, the full one after it (exact).
    assert_eq!(m.angular_velocity_at(0.5e-6), 0.5 * 3.0e5);
    assert_eq!(m.angular_velocity_at(5e-6), 3.0e5);
}

#[test]
fn contact_under_a_rotating_tool_is_the_resting_contact_in_the_tools_frame() {
    // A 2D tool turned by θ about z through its centre c: a particle at x sees the penetration of p = c + Rᵀ(x − o − c)
    // in the unturned tool, the normal turned by R; a particle moving with the tool's material velocity at its
    // point (v = v_tool(x)) slips nowhere and takes no friction from a zero history (exactly).
    let t = tool(10.0, 8.0, 20.0);
    let c = ContactParams { kappa: 0.1, friction_kappa: 0.1, friction: 0.35, ..Default::default() };
    let m = ToolMotion {
        start: [0.3e-3, 0.1e-3, 0.0],
        velocity: [-2.0, 0.5, 0.0],
        ramp: 0.0,
        rotation: Some(Rotation { axis: [0.0, 0.0, 1.0], centre: [-0.1e-3, 0.2e-3, 0.0], rate: 2.0e4 }),
    };
    let s = m.state_at(7e-6, 1e-9, 1e-9);
    let rest = ToolState { dt: 1e-9, step: 1e-9, ..Default::default() };
    let mut rng = SplitMix64::new(0x7005);
    let mut touching = 0;
    for _ in 0..3000 {
        let p = [(rng.uniform() - 0.7) * 60.0 * UM, (rng.uniform() - 0.2) * 60.0 * UM, 0.0];
        let x3 = s.point_to_world(p);
        let x = [x3[0], x3[1]];
        let vt = s.velocity_at(x3);
        let r = contact_force(&c, &t, &s, x, [vt[0], vt[1]], [0.0; 2], 4.43e-7, 4430.0, 300.0, 560.0, 0.0);
        let p2 = s.to_tool(x3);
        let r0 = contact_force(&c, &t, &rest, [p2[0], p2[1]], [0.0; 2], [0.0; 2], 4.43e-7, 4430.0, 300.0, 560.0, 0.0);
        let turned = s.direction_to_world([r0.normal[0], r0.normal[1], 0.0]);
        // The same query in the tool's frame (the same depth and normal), the force turned by R: 1e-15 of its size
        // (R f_c n against f_c R n: a few roundings).
        let size = r0.normal[0].hypot(r0.normal[1]);
        assert_close([r.normal[0], r.normal[1], 0.0], turned, 1e-15 * size, &format!("normal force at {p:?}"));
        assert_eq!(r.friction, [0.0; 2], "at {p:?}");
        touching += (r.normal != [0.0; 2]) as usize;
    }
    assert!(touching > 300, "{touching} contacts");
}
