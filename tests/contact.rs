//! Contact with the rigid 2D cutting tool (kernels/src/contact): the tool's construction and its exact signed
//! distance against an independent description of the outline and a brute-force polyline (roethlin-solver.md
//! §5.4, §10.3 AT-40, AT-41), the penalty normal force (AT-42, (5.116); klippel-constitutive.md §1.3 (4.45), §8
//! H15), the LS-DYNA incremental stick/slip friction (AT-43, (5.129–5.130); klippel (4.47–4.48), §8 H11), the
//! shear-stress cap of the friction (klippel (9.21); roethlin §5.4 (7.6)/(7.7)), friction heating and Usui wear.
//!
//! Units: SI (m, s, kg per unit depth in 2D). Tolerances are stated at each assertion with their source.

use std::f64::consts::FRAC_PI_2;

use swarf::kernels::contact::ToolState;
use swarf::kernels::contact::penalty::{ContactParams, ContactResult, cap, contact_force, friction_update, law};
use swarf::kernels::contact::tool2d::{ARC, BACK, FLANK, RAKE, ShapeError, TOP, Tool2d, ToolShape};
use swarf::rng::SplitMix64;

const UM: f64 = 1e-6;
const MM: f64 = 1e-3;
/// The tool's size, the scale of the absolute geometric tolerances.
const SCALE: f64 = 1e-3;
/// AT-41: "exact signed distance ... 1e-12", taken relative to the tool's size.
const TOL_D: f64 = 1e-12 * SCALE;
/// Tool length and height of AT-40 (the [C2D] reference tool: 0.0413 cm × 0.0431 cm).
const LENGTH: f64 = 0.4 * MM;
const HEIGHT: f64 = 0.43 * MM;

type V2 = [f64; 2];

fn sub(a: V2, b: V2) -> V2 {
    [a[0] - b[0], a[1] - b[1]]
}
fn add(a: V2, b: V2) -> V2 {
    [a[0] + b[0], a[1] + b[1]]
}
fn scale(s: f64, a: V2) -> V2 {
    [s * a[0], s * a[1]]
}
fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn cross(a: V2, b: V2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn norm(a: V2) -> f64 {
    a[0].hypot(a[1])
}
fn unit(a: V2) -> V2 {
    scale(1.0 / norm(a), a)
}
fn dist(a: V2, b: V2) -> f64 {
    norm(sub(a, b))
}
fn max_diff(a: V2, b: V2) -> f64 {
    (a[0] - b[0]).abs().max((a[1] - b[1]).abs())
}

fn assert_rel(got: f64, want: f64, rel: f64, what: &str) {
    let err = (got - want).abs();
    assert!(
        err <= rel * want.abs(),
        "{what}: got {got:e}, want {want:e} (rel. error {:e} > {rel:e})",
        err / want.abs()
    );
}

fn assert_vec_rel(got: V2, want: V2, rel: f64, what: &str) {
    let err = dist(got, want);
    assert!(
        err <= rel * norm(want),
        "{what}: got {got:?}, want {want:?} (rel. error {:e} > {rel:e})",
        err / norm(want)
    );
}

fn shape(rake_deg: f64, clearance_deg: f64, radius_um: f64) -> ToolShape {
    ToolShape {
        rake_angle: rake_deg.to_radians(),
        clearance_angle: clearance_deg.to_radians(),
        edge_radius: radius_um * UM,
        length: LENGTH,
        height: HEIGHT,
    }
}

fn build(s: &ToolShape) -> Tool2d {
    Tool2d::new(s).unwrap_or_else(|e| panic!("{s:?}: {e:?}"))
}

/// AT-40's tools (γ = 10°, α = 8°, r_c ∈ {10, 20, 50} µm), a negative rake, γ = 0°, and the limits α = 0 and a sharp
/// edge (r = 0): (γ [°], α [°], r [µm]).
const SHAPES: [(f64, f64, f64); 8] = [
    (10.0, 8.0, 10.0),
    (10.0, 8.0, 20.0),
    (10.0, 8.0, 50.0),
    (-20.0, 5.0, 15.0),
    (0.0, 7.0, 33.0),
    (25.0, 12.0, 5.0),
    (10.0, 0.0, 20.0),
    (10.0, 8.0, 0.0),
];

// ---------------------------------------------------------------------------------------------------------------
// An independent description of the outline, from the documented construction only (tool2d.rs module doc and
// roethlin §5.4): the tool lies above the origin, the edge arc's lowest point is the origin, so its centre is
// (0, r); the arc is tangent to the rake and flank lines, so its tangent points are the feet of the perpendiculars
// from the centre, c + r n; the rake face ends at y = height, the flank at x = −length, the top-left corner is
// (−length, height). Outline counter-clockwise: flank, arc, rake, top, back.

#[derive(Clone, Copy, Debug)]
enum Piece {
    /// A straight face a → b with its outward normal (the travel direction turned clockwise), its primitive index
    /// in the tool, and tan(turn/2) of the corners at a and b (0 where the joint is smooth, i.e. the arc's ends).
    Seg { a: V2, b: V2, n: V2, prim: u32, corner_a: f64, corner_b: f64 },
    /// The edge arc: centre, radius, and the normal angles at its flank and rake ends.
    Arc { c: V2, r: f64, th0: f64, th1: f64 },
}

impl Piece {
    /// The point and outward normal at parameter t ∈ [0, 1].
    fn at(&self, t: f64) -> (V2, V2) {
        match *self {
            Piece::Seg { a, b, n, .. } => (add(a, scale(t, sub(b, a))), n),
            Piece::Arc { c, r, th0, th1 } => {
                let th = th0 + t * (th1 - th0);
                let u = [th.cos(), th.sin()];
                (add(c, scale(r, u)), u)
            }
        }
    }

    fn length(&self) -> f64 {
        match *self {
            Piece::Seg { a, b, .. } => dist(a, b),
            Piece::Arc { r, th0, th1, .. } => r * (th1 - th0),
        }
    }

    fn prim(&self) -> u32 {
        match *self {
            Piece::Seg { prim, .. } => prim,
            Piece::Arc { .. } => ARC,
        }
    }
}

/// A convex corner of the outline and the outward normals of the faces before and after it (counter-clockwise).
#[derive(Clone, Copy, Debug)]
struct Corner {
    p: V2,
    n_in: V2,
    n_out: V2,
}

#[derive(Clone, Debug)]
struct Outline {
    centre: V2,
    r: f64,
    t_f: V2,
    t_r: V2,
    top: V2,
    top_left: V2,
    back: V2,
    n_rake: V2,
    n_flank: V2,
    /// The wedge angle β = 90° − γ − α.
    wedge: f64,
    pieces: Vec<Piece>,
    corners: Vec<Corner>,
}

/// tan(turn/2) for the turn between two outward normals of a convex outline: an inside point at distance t from
/// the corner along one face and depth δ is closer to that face than to the other iff t > δ·tan(turn/2).
fn half_turn_tan(n_in: V2, n_out: V2) -> f64 {
    (0.5 * dot(n_in, n_out).clamp(-1.0, 1.0).acos()).tan()
}

impl Outline {
    fn new(s: &ToolShape) -> Outline {
        let (g, a, r) = (s.rake_angle, s.clearance_angle, s.edge_radius);
        let d_r = [-g.sin(), g.cos()];
        let d_f = [-a.cos(), a.sin()];
        let centre = [0.0, r];
        let (th0, th1) = (-FRAC_PI_2 - a, g);
        let t_f = add(centre, scale(r, [th0.cos(), th0.sin()]));
        let t_r = add(centre, scale(r, [th1.cos(), th1.sin()]));
        let top = add(t_r, scale((s.height - t_r[1]) / g.cos(), d_r));
        let back = add(t_f, scale((t_f[0] + s.length) / a.cos(), d_f));
        let top_left = [-s.length, s.height];
        let normal = |p: V2, q: V2| {
            let d = unit(sub(q, p));
            [d[1], -d[0]]
        };
        let n_flank = normal(back, t_f);
        let n_rake = normal(t_r, top);
        let (n_top, n_back) = (normal(top, top_left), normal(top_left, back));
        let sharp = if r == 0.0 { half_turn_tan(n_flank, n_rake) } else { 0.0 };
        let (c_top, c_tl, c_back) =
            (half_turn_tan(n_rake, n_top), half_turn_tan(n_top, n_back), half_turn_tan(n_back, n_flank));
        let mut pieces =
            vec![Piece::Seg { a: back, b: t_f, n: n_flank, prim: FLANK as u32, corner_a: c_back, corner_b: sharp }];
        if r > 0.0 {
            pieces.push(Piece::Arc { c: centre, r, th0, th1 });
        }
        pieces.push(Piece::Seg { a: t_r, b: top, n: n_rake, prim: RAKE as u32, corner_a: sharp, corner_b: c_top });
        pieces.push(Piece::Seg { a: top, b: top_left, n: n_top, prim: TOP as u32, corner_a: c_top, corner_b: c_tl });
        pieces.push(Piece::Seg {
            a: top_left,
            b: back,
            n: n_back,
            prim: BACK as u32,
            corner_a: c_tl,
            corner_b: c_back,
        });
        let mut corners = vec![
            Corner { p: top, n_in: n_rake, n_out: n_top },
            Corner { p: top_left, n_in: n_top, n_out: n_back },
            Corner { p: back, n_in: n_back, n_out: n_flank },
        ];
        if r == 0.0 {
            corners.push(Corner { p: centre, n_in: n_flank, n_out: n_rake });
        }
        Outline { centre, r, t_f, t_r, top, top_left, back, n_rake, n_flank, wedge: FRAC_PI_2 - g - a, pieces, corners }
    }
}

// ---------------------------------------------------------------------------------------------------------------
// AT-40: construction

/// The perpendicular distance of `p` from the line through a and b.
fn line_distance(p: V2, a: V2, b: V2) -> f64 {
    cross(sub(b, a), sub(p, a)).abs() / dist(a, b)
}

fn seg_a(t: &Tool2d, k: usize) -> V2 {
    [t.seg[k][0], t.seg[k][1]]
}
fn seg_b(t: &Tool2d, k: usize) -> V2 {
    [t.seg[k][2], t.seg[k][3]]
}
fn seg_n(t: &Tool2d, k: usize) -> V2 {
    [t.seg[k][4], t.seg[k][5]]
}

/// Intersection of the lines a1 + s(b1 − a1) and a2 + u(b2 − a2).
fn intersect(a1: V2, b1: V2, a2: V2, b2: V2) -> V2 {
    let (d1, d2) = (sub(b1, a1), sub(b2, a2));
    let s = cross(sub(a2, a1), d2) / cross(d1, d2);
    add(a1, scale(s, d1))
}

#[test]
fn at40_edge_arc_is_tangent_to_rake_and_flank() {
    for &(g, a, r_um) in SHAPES.iter().filter(|s| s.2 > 0.0) {
        let s = shape(g, a, r_um);
        let tool = build(&s);
        let r = s.edge_radius;
        let what = format!("γ = {g}°, α = {a}°, r = {r_um} µm");
        assert_eq!(tool.radius, r, "{what}: radius");
        let c = tool.centre;
        // AT-40: the perpendicular distance from the arc centre to the rake and flank lines is r_c, 1e-12 relative.
        for k in [RAKE, FLANK] {
            let d = line_distance(c, seg_a(&tool, k), seg_b(&tool, k));
            assert_rel(d, r, 1e-12, &format!("{what}: centre to line of segment {k}"));
            // ... on the inner side: the signed distance along the segment's outward normal is −r.
            assert_rel(dot(sub(c, seg_a(&tool, k)), seg_n(&tool, k)), -r, 1e-12, &format!("{what}: side of {k}"));
        }
        // The tangent points (the arc's ends, the faces' ends at the edge) lie on the circle (1e-12 relative), and
        // are the feet of the perpendiculars: c + r n (1e-12 r).
        let (t_r, t_f) = (seg_a(&tool, RAKE), seg_b(&tool, FLANK));
        assert_eq!(t_r, tool.rake_tangent(), "{what}: rake_tangent");
        assert_rel(dist(t_r, c), r, 1e-12, &format!("{what}: |T_r − c|"));
        assert_rel(dist(t_f, c), r, 1e-12, &format!("{what}: |T_f − c|"));
        assert!(max_diff(t_r, add(c, scale(r, seg_n(&tool, RAKE)))) <= 1e-12 * r, "{what}: T_r = c + r n_rake");
        assert!(max_diff(t_f, add(c, scale(r, seg_n(&tool, FLANK)))) <= 1e-12 * r, "{what}: T_f = c + r n_flank");
        // The arc's end normals are the faces' normals (1e-15: unit vectors computed from the same angles).
        assert!(max_diff(tool.n_rake, seg_n(&tool, RAKE)) <= 1e-15, "{what}: n_rake");
        assert!(max_diff(tool.n_flank, seg_n(&tool, FLANK)) <= 1e-15, "{what}: n_flank");
        // The centre lies on the bisector of the corner T of the two lines (roethlin §5.4), at r/sin(β/2) from it,
        // and the tangent points at r/tan(β/2) (module doc): 1e-12 relative (the intersection of two lines meeting
        // at β ≥ 57° loses at most a few ulps).
        let tip = intersect(t_r, seg_b(&tool, RAKE), seg_a(&tool, FLANK), t_f);
        let beta = FRAC_PI_2 - s.rake_angle - s.clearance_angle;
        assert_rel(dist(c, tip), r / (0.5 * beta).sin(), 1e-12, &format!("{what}: |c − T|"));
        assert_rel(dist(t_r, tip), r / (0.5 * beta).tan(), 1e-12, &format!("{what}: |T_r − T|"));
        assert_rel(dist(t_f, tip), r / (0.5 * beta).tan(), 1e-12, &format!("{what}: |T_f − T|"));
        let bis = unit(add(unit(sub(t_r, tip)), unit(sub(t_f, tip))));
        assert!(max_diff(unit(sub(c, tip)), bis) <= 1e-12, "{what}: centre off the bisector");
        // The faces run along the documented directions d_r = (−sin γ, cos γ), d_f = (−cos α, sin α) (1e-12).
        let (gr, ar) = (s.rake_angle, s.clearance_angle);
        assert!(max_diff(unit(sub(seg_b(&tool, RAKE), t_r)), [-gr.sin(), gr.cos()]) <= 1e-12, "{what}: d_r");
        assert!(max_diff(unit(sub(seg_a(&tool, FLANK), t_f)), [-ar.cos(), ar.sin()]) <= 1e-12, "{what}: d_f");
    }
}

#[test]
fn at40_tool_matches_the_documented_outline() {
    for &(g, a, r_um) in &SHAPES {
        let s = shape(g, a, r_um);
        let tool = build(&s);
        let o = Outline::new(&s);
        let what = format!("γ = {g}°, α = {a}°, r = {r_um} µm");
        // Every vertex equals the independent construction within 1e-12 of the tool's size; normals within 1e-14.
        let close = |p: V2, q: V2, name: &str| {
            assert!(max_diff(p, q) <= TOL_D, "{what}: {name}: tool {p:?}, outline {q:?}");
        };
        close(tool.centre, o.centre, "centre");
        close(seg_a(&tool, RAKE), o.t_r, "T_r");
        close(seg_b(&tool, RAKE), o.top, "R");
        close(seg_a(&tool, TOP), o.top, "R (top)");
        close(seg_b(&tool, TOP), o.top_left, "TL");
        close(seg_a(&tool, BACK), o.top_left, "TL (back)");
        close(seg_b(&tool, BACK), o.back, "F");
        close(seg_a(&tool, FLANK), o.back, "F (flank)");
        close(seg_b(&tool, FLANK), o.t_f, "T_f");
        for (k, n) in [(RAKE, o.n_rake), (TOP, [0.0, 1.0]), (BACK, [-1.0, 0.0]), (FLANK, o.n_flank)] {
            assert!(max_diff(seg_n(&tool, k), n) <= 1e-14, "{what}: normal of segment {k}");
            assert!((norm(seg_n(&tool, k)) - 1.0).abs() <= 1e-15, "{what}: |normal| of segment {k}");
        }
        // The chord normal points from the chord T_f–T_r to the edge: perpendicular to the chord, along n_f + n_r.
        if o.r > 0.0 {
            assert!(dot(tool.n_chord, unit(sub(o.t_r, o.t_f))).abs() <= 1e-14, "{what}: n_chord ⟂ chord");
            assert!(max_diff(tool.n_chord, unit(add(o.n_flank, o.n_rake))) <= 1e-14, "{what}: n_chord");
        }
        assert!(o.wedge > 0.0);
    }
}

#[test]
fn at40_lowest_point_of_the_outline_is_the_origin() {
    for &(g, a, r_um) in &SHAPES {
        let s = shape(g, a, r_um);
        let tool = build(&s);
        let what = format!("γ = {g}°, α = {a}°, r = {r_um} µm");
        // Sample the tool's own outline (its segments, and the arc between its end normals) densely. The documented
        // construction (α ≥ 0) puts the downward normal −90° inside the arc's normal range [−90° − α, γ], so the
        // arc's lowest point, at −90°, is sampled exactly as well.
        let mut min_y = f64::INFINITY;
        let mut argmin = [0.0; 2];
        let mut take = |p: V2| {
            if p[1] < min_y {
                min_y = p[1];
                argmin = p;
            }
        };
        for k in 0..4 {
            let (pa, pb) = (seg_a(&tool, k), seg_b(&tool, k));
            for i in 0..=4000 {
                take(add(pa, scale(i as f64 / 4000.0, sub(pb, pa))));
            }
        }
        if tool.radius > 0.0 {
            let th0 = tool.n_flank[1].atan2(tool.n_flank[0]);
            let th1 = tool.n_rake[1].atan2(tool.n_rake[0]);
            assert!(th0 <= -FRAC_PI_2 && -FRAC_PI_2 <= th1, "{what}: −90° outside the arc [{th0}, {th1}]");
            let mut ths: Vec<f64> = (0..=4000).map(|i| th0 + (th1 - th0) * i as f64 / 4000.0).collect();
            ths.push(-FRAC_PI_2);
            for th in ths {
                take(add(tool.centre, scale(tool.radius, [th.cos(), th.sin()])));
            }
        }
        // AT-40 (module doc: "the origin is the lowest point of the cutting edge"): min y = 0 within 1e-15·scale,
        // and it is attained at x = 0.
        assert!(min_y.abs() <= 1e-15 * SCALE, "{what}: lowest y {min_y:e}");
        assert!(argmin[0].abs() <= 1e-15 * SCALE || a == 0.0, "{what}: lowest point at {argmin:?}");
        // The exact distance at the origin is 0 (1e-18 m), the points straight below it are outside at their depth
        // with the origin as closest point, and the points just above it inside.
        let q = tool.closest([0.0, 0.0]);
        assert!(q.distance.abs() <= 1e-18, "{what}: distance at the origin {:e}", q.distance);
        for d in [1e-9, 1e-7, 1e-5] {
            let q = tool.closest([0.0, -d]);
            // AT-41 tolerances: distance 1e-12·scale, normal 1e-9; the closest point is the origin (1e-18 m).
            assert!((q.distance - d).abs() <= TOL_D, "{what}: distance below the origin {:e}", q.distance);
            assert!(max_diff(q.point, [0.0, 0.0]) <= 1e-18, "{what}: closest point {:?}", q.point);
            assert!(max_diff(q.normal, [0.0, -1.0]) <= 1e-9, "{what}: normal {:?}", q.normal);
            assert!(!tool.contains([0.0, -d]), "{what}: contains below the origin");
            // Inside: straight up into the arc (d < r), or along the wedge's bisector (d_r + d_f) for a sharp edge.
            let (gr, ar) = (s.rake_angle, s.clearance_angle);
            let up = if s.edge_radius > d { [0.0, 1.0] } else { unit([-gr.sin() - ar.cos(), gr.cos() + ar.sin()]) };
            assert!(tool.contains(scale(d, up)), "{what}: contains above the origin, d = {d:e}");
        }
    }
}

#[test]
fn at40_sharp_edge_collapses_to_the_origin() {
    let tool = build(&shape(10.0, 8.0, 0.0));
    // r = 0: the arc is the corner point T, which is the origin (module doc), exactly up to rounding (1e-18 m).
    for p in [tool.centre, seg_a(&tool, RAKE), seg_b(&tool, FLANK)] {
        assert!(max_diff(p, [0.0, 0.0]) <= 1e-18, "sharp edge point {p:?}");
    }
    assert_eq!(tool.radius, 0.0);
}

#[test]
fn at40_invalid_shapes_are_rejected() {
    let ok = shape(10.0, 8.0, 20.0);
    assert!(Tool2d::new(&ok).is_ok());
    let with = |f: &dyn Fn(&mut ToolShape)| {
        let mut s = ok;
        f(&mut s);
        Tool2d::new(&s)
    };
    // Angles: wedge β = 90° − γ − α ≤ 0 (β = 0 exactly at γ = 90°, α = 0), β ≥ 180°, α < 0, non-finite angles.
    assert_eq!(with(&|s| (s.rake_angle, s.clearance_angle) = (FRAC_PI_2, 0.0)), Err(ShapeError::Angles));
    assert_eq!(
        with(&|s| (s.rake_angle, s.clearance_angle) = (60f64.to_radians(), 40f64.to_radians())),
        Err(ShapeError::Angles)
    );
    assert_eq!(
        with(&|s| (s.rake_angle, s.clearance_angle) = (-100f64.to_radians(), 5f64.to_radians())),
        Err(ShapeError::Angles)
    );
    assert_eq!(with(&|s| s.clearance_angle = -1f64.to_radians()), Err(ShapeError::Angles));
    assert_eq!(with(&|s| s.clearance_angle = -1e-300), Err(ShapeError::Angles));
    assert_eq!(with(&|s| s.rake_angle = f64::NAN), Err(ShapeError::Angles));
    assert_eq!(with(&|s| s.clearance_angle = f64::NAN), Err(ShapeError::Angles));
    assert_eq!(with(&|s| s.rake_angle = f64::INFINITY), Err(ShapeError::Angles));
    // Size: negative or non-finite radius, non-positive or non-finite length and height.
    assert_eq!(with(&|s| s.edge_radius = -1e-6), Err(ShapeError::Size));
    assert_eq!(with(&|s| s.edge_radius = f64::NAN), Err(ShapeError::Size));
    assert_eq!(with(&|s| s.edge_radius = f64::INFINITY), Err(ShapeError::Size));
    assert_eq!(with(&|s| s.length = 0.0), Err(ShapeError::Size));
    assert_eq!(with(&|s| s.length = -1e-3), Err(ShapeError::Size));
    assert_eq!(with(&|s| s.length = f64::NAN), Err(ShapeError::Size));
    assert_eq!(with(&|s| s.length = f64::INFINITY), Err(ShapeError::Size));
    assert_eq!(with(&|s| s.height = 0.0), Err(ShapeError::Size));
    assert_eq!(with(&|s| s.height = f64::NAN), Err(ShapeError::Size));
    assert_eq!(with(&|s| s.height = f64::INFINITY), Err(ShapeError::Size));
    // TooSmall: faces shorter than the arc's tangent length r/tan(β/2) (≈ 0.73 r at β = 72°). The rake face from
    // T to y = height: height 30 µm with r = 50 µm (T_r is at y = r(1 + sin γ) ≈ 59 µm).
    assert_eq!(with(&|s| (s.edge_radius, s.height) = (50.0 * UM, 30.0 * UM)), Err(ShapeError::TooSmall));
    // The flank face from T to x = −length: length 5 µm with r = 50 µm (T_f is at x = −r sin α ≈ −7 µm).
    assert_eq!(with(&|s| (s.edge_radius, s.length) = (50.0 * UM, 5.0 * UM)), Err(ShapeError::TooSmall));
    // The flank rising above the top: α = 40°, γ = −20°, length 0.4 mm climbs ≈ 0.33 mm > height 0.2 mm.
    assert_eq!(
        with(&|s| (s.rake_angle, s.clearance_angle, s.height) = (-20f64.to_radians(), 40f64.to_radians(), 0.2 * MM)),
        Err(ShapeError::TooSmall)
    );
    // Just long enough faces are accepted: the rake face from T_r = c + r n_r up to 1 µm above it (length 0.1 mm
    // keeps the flank, rising at tan 8°, below that top).
    let t_r_y = 20.0 * UM * (1.0 + 10f64.to_radians().sin());
    assert!(with(&|s| (s.height, s.length) = (t_r_y + 1.0 * UM, 0.1 * MM)).is_ok());
}

// ---------------------------------------------------------------------------------------------------------------
// AT-41: exact signed distance, normal and closest point along the outline

/// Offsets along the outward normal: small against the edge radius (≥ 5 µm here) and the tool.
const OFFSETS: [f64; 6] = [1e-7, -1e-7, 1e-6, -1e-6, 3e-6, -3e-6];

#[test]
fn at41_offsets_along_the_normal_are_exact() {
    let mut rng = SplitMix64::new(0x41);
    let mut checked = 0usize;
    for &(g, a, r_um) in &SHAPES {
        let s = shape(g, a, r_um);
        let tool = build(&s);
        let o = Outline::new(&s);
        for piece in &o.pieces {
            let len = piece.length();
            // Interior parameters on a uniform grid, random ones, and the end points.
            let mut ts: Vec<(f64, bool)> = (0..64).map(|i| ((i as f64 + 0.5) / 64.0, true)).collect();
            ts.extend((0..64).map(|_| (0.001 + 0.998 * rng.uniform(), true)));
            ts.extend([(0.0, false), (1.0, false)]);
            for &(t, interior) in &ts {
                let (p, n) = piece.at(t);
                for &d in &OFFSETS {
                    if d < 0.0 {
                        // Inside, the closest point stays p(s) only at more than |δ|·tan(turn/2) from a corner (the
                        // bisector of the corner); keep twice that, so that the normal is not a near tie either.
                        // On the arc, |δ| < r keeps the centre side clear.
                        match *piece {
                            Piece::Seg { corner_a, corner_b, .. } => {
                                if t * len <= 2.0 * d.abs() * corner_a || (1.0 - t) * len <= 2.0 * d.abs() * corner_b {
                                    continue;
                                }
                            }
                            Piece::Arc { r, .. } => {
                                if d.abs() >= 0.5 * r {
                                    continue;
                                }
                            }
                        }
                    }
                    let x = add(p, scale(d, n));
                    let q = tool.closest(x);
                    let what = format!("γ = {g}°, α = {a}°, r = {r_um} µm, {piece:?} t = {t}, δ = {d:e}");
                    // AT-41: the signed distance is δ within 1e-12 of the tool's size.
                    assert!((q.distance - d).abs() <= TOL_D, "{what}: distance {:e}", q.distance);
                    // The normal is the outline's outward normal at p(s) (1e-9), the closest point p(s) (1e-12·scale).
                    assert!(max_diff(q.normal, n) <= 1e-9, "{what}: normal {:?}, want {n:?}", q.normal);
                    assert!(max_diff(q.point, p) <= TOL_D, "{what}: point {:?}, want {p:?}", q.point);
                    assert_eq!(tool.contains(x), d < 0.0, "{what}: contains");
                    if interior {
                        assert_eq!(q.primitive, piece.prim(), "{what}: primitive");
                    }
                    checked += 1;
                }
            }
        }
        // Outside the convex corners, in their normal cone: distance δ, closest point the corner, normal the
        // direction to the query (1e-12·scale, 1e-9).
        for c in &o.corners {
            for w in [0.0, 0.1, 0.5, 0.9, 1.0] {
                let u = unit(add(scale(1.0 - w, c.n_in), scale(w, c.n_out)));
                for d in [1e-7, 1e-6, 3e-6, 1e-4] {
                    let q = tool.closest(add(c.p, scale(d, u)));
                    let what = format!("γ = {g}°, α = {a}°, r = {r_um} µm, corner {:?}, w = {w}, δ = {d:e}", c.p);
                    assert!((q.distance - d).abs() <= TOL_D, "{what}: distance {:e}", q.distance);
                    assert!(max_diff(q.point, c.p) <= TOL_D, "{what}: point {:?}", q.point);
                    assert!(max_diff(q.normal, u) <= 1e-9, "{what}: normal {:?}, want {u:?}", q.normal);
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 10_000, "only {checked} queries");
}

/// KNOWN FAILURE (bug in tool2d.rs `Tool2d::closest`, reported, not fixed here): for a point just outside the edge
/// arc, the distance is |p − c| − r but the normal is recomputed as (p − point)/distance from the rounded arc point,
/// so at distances of a few ulps (~1e-20 m) it is not a unit vector: [0.75, −1.0] or even [0, 0]. The module doc
/// promises an outward unit normal. Fix: on the arc, keep the normal u = (p − c)/|p − c| for outside points too
/// (recompute (p − point)/d only for the segments, where d = |p − point| by construction).
#[test]
fn at41_outside_normal_near_the_arc_is_unit() {
    // The explicit inputs first (r = 20 µm and 50 µm tools of AT-40).
    for (r_um, p) in
        [(20.0, [1.0806046117362798e-5, 3.1705803038420668e-6]), (50.0, [2.689404235764852e-5, 7.848956292103424e-6])]
    {
        let tool = build(&shape(10.0, 8.0, r_um));
        let q = tool.closest(p);
        assert!(q.distance >= 0.0, "r = {r_um} µm: {p:?} is outside or on the arc: {q:?}");
        if q.distance > 0.0 {
            // Outward unit normal (module doc), 1e-12; outward: along p − c.
            assert!((norm(q.normal) - 1.0).abs() <= 1e-12, "r = {r_um} µm, p = {p:?}: normal {:?} not unit", q.normal);
            assert!(dot(q.normal, sub(p, tool.centre)) > 0.0, "r = {r_um} µm, p = {p:?}: normal {:?}", q.normal);
        }
    }
    // A sweep along the arc at 0..6 ulps outside.
    for r_um in [10.0, 20.0, 50.0] {
        let tool = build(&shape(10.0, 8.0, r_um));
        for i in 0..20_000 {
            let th = -1.0 - 0.5 * i as f64 / 20_000.0;
            let u = [th.cos(), th.sin()];
            for k in 0..6 {
                let p = add(tool.centre, scale(tool.radius + k as f64 * 3.4e-21, u));
                let q = tool.closest(p);
                if q.distance > 0.0 {
                    assert!(
                        (norm(q.normal) - 1.0).abs() <= 1e-12 && dot(q.normal, u) > 0.0,
                        "r = {r_um} µm, p = {p:?}: distance {:e}, normal {:?}",
                        q.distance,
                        q.normal
                    );
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------------------------
// AT-41 against brute force: a dense polyline through the outline, searched exhaustively (with bounding boxes
// that only prune what cannot be nearer), and an even-odd ray-casting inside test on it.

/// Polyline vertex spacing [m].
const STEP: f64 = 1e-8;

struct Node {
    lo: [f64; 2],
    hi: [f64; 2],
    first: usize,
    last: usize,
    children: Option<(usize, usize)>,
}

/// A closed polyline (chords a → b) with a bounding-box tree over runs of consecutive chords.
struct Polyline {
    chords: Vec<[f64; 4]>,
    nodes: Vec<Node>,
}

impl Polyline {
    /// Vertices every ≤ `STEP` of arc length along each piece, the piece ends (the corners, the tangent points)
    /// included exactly.
    fn new(o: &Outline) -> Polyline {
        let mut verts = Vec::new();
        for piece in &o.pieces {
            let n = (piece.length() / STEP).ceil().max(1.0) as usize;
            verts.extend((0..n).map(|i| piece.at(i as f64 / n as f64).0));
        }
        let chords: Vec<[f64; 4]> = (0..verts.len())
            .map(|i| {
                let (a, b) = (verts[i], verts[(i + 1) % verts.len()]);
                [a[0], a[1], b[0], b[1]]
            })
            .collect();
        let mut p = Polyline { chords, nodes: Vec::new() };
        p.build(0, p.chords.len());
        p
    }

    fn build(&mut self, first: usize, last: usize) -> usize {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for c in &self.chords[first..last] {
            for k in 0..2 {
                lo[k] = lo[k].min(c[k]).min(c[k + 2]);
                hi[k] = hi[k].max(c[k]).max(c[k + 2]);
            }
        }
        let id = self.nodes.len();
        self.nodes.push(Node { lo, hi, first, last, children: None });
        if last - first > 16 {
            let mid = (first + last) / 2;
            let l = self.build(first, mid);
            let r = self.build(mid, last);
            self.nodes[id].children = Some((l, r));
        }
        id
    }

    fn box_d2(&self, i: usize, p: V2) -> f64 {
        let nd = &self.nodes[i];
        let dx = (nd.lo[0] - p[0]).max(p[0] - nd.hi[0]).max(0.0);
        let dy = (nd.lo[1] - p[1]).max(p[1] - nd.hi[1]).max(0.0);
        dx * dx + dy * dy
    }

    /// The distance from `p` to the nearest chord.
    fn distance(&self, p: V2) -> f64 {
        let mut best = f64::INFINITY;
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            if self.box_d2(i, p) >= best {
                continue;
            }
            let nd = &self.nodes[i];
            match nd.children {
                Some((l, r)) => {
                    let (near, far) = if self.box_d2(l, p) <= self.box_d2(r, p) { (l, r) } else { (r, l) };
                    stack.push(far);
                    stack.push(near);
                }
                None => {
                    for c in &self.chords[nd.first..nd.last] {
                        let (a, ab) = ([c[0], c[1]], [c[2] - c[0], c[3] - c[1]]);
                        let t = (dot(sub(p, a), ab) / dot(ab, ab)).clamp(0.0, 1.0);
                        let e = sub(p, add(a, scale(t, ab)));
                        best = best.min(dot(e, e));
                    }
                }
            }
        }
        best.sqrt()
    }

    /// Even-odd rule: the number of chords a ray from `p` towards +x crosses is odd.
    fn inside(&self, p: V2) -> bool {
        let mut count = 0usize;
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let nd = &self.nodes[i];
            if p[1] < nd.lo[1] || p[1] > nd.hi[1] || p[0] > nd.hi[0] {
                continue;
            }
            match nd.children {
                Some((l, r)) => stack.extend([l, r]),
                None => {
                    for c in &self.chords[nd.first..nd.last] {
                        if (c[1] > p[1]) != (c[3] > p[1]) {
                            let x = c[0] + (p[1] - c[1]) * (c[2] - c[0]) / (c[3] - c[1]);
                            if p[0] < x {
                                count += 1;
                            }
                        }
                    }
                }
            }
        }
        count % 2 == 1
    }
}

/// Compares the tool with the polyline on an n × n grid over [x0, x1] × [y0, y1]; returns the number of points
/// whose sign was checked.
fn grid_check(tool: &Tool2d, o: &Outline, poly: &Polyline, x: [f64; 2], y: [f64; 2], n: usize, what: &str) -> usize {
    // The polyline's error: on the straight faces the chords are the faces (rounding only); on the arc a chord of
    // arc length ≤ s lies inside the circle by its sagitta r(1 − cos(s/2r)) ≤ s²/(8r). The distance to the polyline
    // differs from the exact one by at most that, plus rounding of ~1e-19 m in the vertices, allowed as 1e-15 m.
    let bound = if o.r > 0.0 { STEP * STEP / (8.0 * o.r) } else { 0.0 } + 1e-15;
    let mut signs = 0;
    for i in 0..n {
        for j in 0..n {
            let p =
                [x[0] + (x[1] - x[0]) * i as f64 / (n - 1) as f64, y[0] + (y[1] - y[0]) * j as f64 / (n - 1) as f64];
            let q = tool.closest(p);
            let dp = poly.distance(p);
            assert!(
                (q.distance.abs() - dp).abs() <= bound,
                "{what}: at {p:?} |distance| {:e}, polyline {dp:e} (bound {bound:e})",
                q.distance.abs()
            );
            // The closest point and normal reproduce the query: p = point + distance·normal (1e-12·scale), and the
            // point lies on its primitive (1e-12·scale). The normal is a unit vector (1e-12) at 10 nm or more from
            // the outline; closer in, an outside normal near the arc is (p − point)/d and loses ulp(p)/d ≈ 7e-21/d
            // (see at41_outside_normal_near_the_arc_is_unit, which fails: bug report).
            if q.distance.abs() >= 1e-8 {
                assert!((norm(q.normal) - 1.0).abs() <= 1e-12, "{what}: at {p:?} |normal| = {}", norm(q.normal));
            }
            let back = add(q.point, scale(q.distance, q.normal));
            assert!(max_diff(back, p) <= TOL_D, "{what}: at {p:?} point + distance·normal = {back:?}");
            let k = q.primitive as usize;
            let off = if q.primitive == ARC {
                dist(q.point, tool.centre) - tool.radius
            } else {
                dot(sub(q.point, seg_a(tool, k)), seg_n(tool, k))
            };
            assert!(off.abs() <= TOL_D, "{what}: at {p:?} point {:?} off primitive {k} by {off:e}", q.point);
            if (i * n + j).is_multiple_of(7) {
                let dq = poly.distance(q.point);
                assert!(dq <= bound, "{what}: at {p:?} closest point {:?} is {dq:e} off the outline", q.point);
            }
            // The sign, away from the boundary (2× the bound): the even-odd test on the polyline.
            if dp > 2.0 * bound {
                let inside = poly.inside(p);
                assert_eq!(q.distance < 0.0, inside, "{what}: sign at {p:?} (distance {:e})", q.distance);
                assert_eq!(tool.contains(p), inside, "{what}: contains at {p:?}");
                signs += 1;
            }
        }
    }
    signs
}

#[test]
fn at41_signed_distance_matches_brute_force_on_grids() {
    std::thread::scope(|scope| {
        let handles: Vec<_> = SHAPES
            .iter()
            .map(|&(g, a, r_um)| {
                scope.spawn(move || {
                    let s = shape(g, a, r_um);
                    let tool = build(&s);
                    let o = Outline::new(&s);
                    let poly = Polyline::new(&o);
                    let what = format!("γ = {g}°, α = {a}°, r = {r_um} µm");
                    // The edge region, 400 × 400 (0.63 µm spacing), and the whole tool box plus margin, 150 × 150.
                    let edge = [-0.15 * MM, 0.1 * MM];
                    let n_edge = grid_check(&tool, &o, &poly, edge, edge, 400, &what);
                    let n_box = grid_check(
                        &tool,
                        &o,
                        &poly,
                        [-LENGTH - 0.1 * MM, 0.15 * MM],
                        [-0.1 * MM, HEIGHT + 0.1 * MM],
                        150,
                        &what,
                    );
                    // Nearly every point is away from the boundary, so its sign is checked (and both signs occur).
                    assert!(n_edge > 150_000 && n_box > 20_000, "{what}: signs checked {n_edge}, {n_box}");
                })
            })
            .collect();
        for h in handles {
            h.join().unwrap();
        }
    });
}

// ---------------------------------------------------------------------------------------------------------------
// AT-42, AT-43 and the friction extras: the penalty contact

/// Ti-6Al-4V-like particle of the [C2D] cutting case: ρ = 4430 kg/m³, Δx = 10 µm, m = ρΔx² per unit depth,
/// Δt = 1 ns; κ = 0.1, μ = 0.35 (roethlin §5.4, §2.6).
const RHO: f64 = 4430.0;
const DX: f64 = 10e-6;
const MASS: f64 = RHO * DX * DX;
const DT: f64 = 1e-9;
const KAPPA: f64 = 0.1;
const MU: f64 = 0.35;

fn params() -> ContactParams {
    ContactParams { kappa: KAPPA, friction_kappa: KAPPA, friction: MU, ..Default::default() }
}

/// A translating tool in the plane.
fn tool_state(offset: V2, velocity: V2, dt: f64, step: f64) -> ToolState {
    ToolState {
        offset: [offset[0], offset[1], 0.0],
        velocity: [velocity[0], velocity[1], 0.0],
        dt,
        step,
        ..Default::default()
    }
}

fn at_rest(dt: f64) -> ToolState {
    tool_state([0.0, 0.0], [0.0, 0.0], dt, dt)
}

fn reference_tool() -> (Tool2d, Outline) {
    let s = shape(10.0, 8.0, 20.0);
    (build(&s), Outline::new(&s))
}

/// The midpoint of the flank or rake face and its outward normal and tangent (the face direction).
fn face(o: &Outline, prim: u32, t: f64) -> (V2, V2, V2) {
    let piece = o.pieces.iter().find(|p| p.prim() == prim).unwrap();
    let (p, n) = piece.at(t);
    (p, n, [-n[1], n[0]])
}

#[test]
fn at42_penalty_force_is_kappa_m_d_n_over_dt2() {
    let (tool, o) = reference_tool();
    let c = params();
    for (prim, t) in [(RAKE as u32, 0.5), (RAKE as u32, 0.1), (FLANK as u32, 0.5), (FLANK as u32, 0.97), (ARC, 0.4)] {
        let piece = o.pieces.iter().find(|p| p.prim() == prim).unwrap();
        let (p, n) = piece.at(t);
        for d in [1e-9, 1e-7, 1e-6, 5e-6] {
            for dt in [DT, 4.7e-10] {
                let x = sub(p, scale(d, n));
                let r =
                    contact_force(&c, &tool, &at_rest(dt), x, [3.0, -1.0], [0.0, 0.0], MASS, RHO, 300.0, 560.0, 1e9);
                let what = format!("primitive {prim} t = {t}, d = {d:e}, Δt = {dt:e}");
                // (5.116) with the tool's exact depth and normal: relative 1e-14 (a few roundings).
                let g = tool.closest(x);
                let want = scale(KAPPA * MASS * -g.distance / (dt * dt), g.normal);
                assert_vec_rel(r.normal, want, 1e-14, &what);
                // The depth and normal are the geometric ones (AT-41): the force against the nominal depth d and
                // the face normal, relative TOL_D/d and 1e-9.
                let nominal = scale(KAPPA * MASS * d / (dt * dt), n);
                assert_vec_rel(r.normal, nominal, TOL_D / d + 1e-9, &format!("{what} (nominal)"));
                // It pushes the particle out, along the outward normal.
                assert!(dot(r.normal, n) > 0.0 && cross(r.normal, n).abs() <= 1e-9 * norm(r.normal), "{what}");
            }
        }
    }
    // The tool's translation: the particle at offset + x sees the same force (relative 1e-9: the subtraction of
    // a 1 mm offset rounds the 1 µm depth at 1e-19/1e-6 = 1e-13).
    let (p, n, _) = face(&o, FLANK as u32, 0.5);
    let x = sub(p, scale(1e-6, n));
    let off = [1.234e-3, -0.5e-3];
    let moved = tool_state(off, [0.0, 0.0], DT, DT);
    let r0 = contact_force(&c, &tool, &at_rest(DT), x, [0.0; 2], [0.0; 2], MASS, RHO, 300.0, 560.0, 0.0);
    let r1 = contact_force(&c, &tool, &moved, add(x, off), [0.0; 2], [0.0; 2], MASS, RHO, 300.0, 560.0, 0.0);
    assert_vec_rel(r1.normal, r0.normal, 1e-9, "offset tool");
}

#[test]
fn at42_no_force_outside_the_tool() {
    let (tool, o) = reference_tool();
    let mut c = params();
    (c.heat_fraction, c.usui_psi, c.usui_xi) = (0.9, 1e-9, 1000.0);
    let history = [1.0e3, -2.0e3];
    let mut points = vec![[0.0, 0.0], o.top_left, [0.0, -1e-12], [1e-3, 1e-3], [-1e-3, 0.2e-3]];
    for piece in &o.pieces {
        for t in [0.0, 0.3, 0.8] {
            let (p, n) = piece.at(t);
            points.extend([add(p, scale(1e-9, n)), add(p, scale(3e-6, n))]);
        }
    }
    let mut tested = 0;
    for x in points {
        let g = tool.closest(x);
        // Outside or on the outline (distance ≥ 0; −0.0 on a vertex): all outputs zero, the friction history
        // included, exactly (5.116: no penetration, no force).
        if g.distance < 0.0 {
            continue;
        }
        let r = contact_force(&c, &tool, &at_rest(DT), x, [5.0, 1.0], history, MASS, RHO, 900.0, 560.0, 1e9);
        assert_eq!(r, ContactResult::default(), "at {x:?} (distance {:e})", g.distance);
        tested += 1;
    }
    assert!(tested >= 25, "only {tested} points outside");
}

#[test]
fn at43_friction_grows_saturates_and_reverses_without_chatter() {
    let k = KAPPA * MASS / DT;
    let f_c = KAPPA * MASS * 1e-6 / (DT * DT);
    let f_max = MU * f_c;
    let dir = [0.3f64.cos(), 0.3f64.sin()];
    // |v_t| = 9 m/s: k|v_t| = 398.7 N/m per step against μ|f_c| = 1.55e4 N/m, saturation after 38.9 steps.
    let v_t = scale(9.0, dir);
    let inc = k * 9.0;
    // Growth (5.129): f* = f_old − k v_t, so |f| grows by exactly k|v_t| per step, opposite to v_t (1e-12); then
    // (5.130) slip at μ|f_c| (1e-14 relative), still opposite to v_t. Steps within 1e-12 of the switch are skipped.
    let mut f = [0.0, 0.0];
    let mut grew = 0;
    for i in 1..=60 {
        let next = friction_update(f, v_t, k, f_max);
        let along = -dot(next, dir);
        assert!(cross(next, dir).abs() <= 1e-12 * f_max, "step {i}: off the slip direction {next:?}");
        if i as f64 * inc < f_max * (1.0 - 1e-12) {
            assert_rel(along - (-dot(f, dir)), inc, 1e-12, &format!("increment at step {i}"));
            grew += 1;
        } else if i as f64 * inc > f_max * (1.0 + 1e-12) {
            assert_rel(along, f_max, 1e-14, &format!("saturated at step {i}"));
        }
        f = next;
    }
    assert_eq!(grew, (f_max / inc).floor() as usize, "steps of growth");
    // It stays there.
    for i in 0..50 {
        f = friction_update(f, v_t, k, f_max);
        assert_vec_rel(f, scale(-f_max, dir), 1e-14, &format!("held {i}"));
    }
    // Reversal (v_t → −v_t): the component of f along v_t rises monotonically from −μ|f_c| through
    // zero and saturates at +μ|f_c| along v_t within ceil(2μ f_c/(k|v_t|)) + 1 steps, one sign change, no chatter.
    let back = scale(-1.0, v_t);
    let limit = (2.0 * f_max / inc).ceil() as usize + 1;
    let mut sign_changes = 0;
    let mut prev = dot(f, dir);
    let mut last_sign = prev.signum();
    let mut reached = None;
    for i in 0..limit + 50 {
        f = friction_update(f, back, k, f_max);
        let along = dot(f, dir);
        assert!(cross(f, dir).abs() <= 1e-12 * f_max, "reversal step {i}: off the slip line {f:?}");
        assert!(along >= prev, "reversal step {i}: not monotonic ({prev:e} → {along:e})");
        if reached.is_none() {
            assert!(along > prev, "reversal step {i}: stalled before saturation");
        }
        // Sign changes of the nonzero values (an exact zero in passing is not a change).
        if along != 0.0 {
            if last_sign != 0.0 && along.signum() != last_sign {
                sign_changes += 1;
            }
            last_sign = along.signum();
        }
        if (along - f_max).abs() <= 1e-14 * f_max && reached.is_none() {
            reached = Some(i + 1);
        }
        if reached.is_some() {
            assert_rel(along, f_max, 1e-14, &format!("reversed saturation at step {i}"));
        }
        prev = along;
    }
    assert_eq!(sign_changes, 1, "sign changes during reversal");
    let reached = reached.expect("never saturated after the reversal");
    assert!(reached <= limit, "saturated after {reached} steps, bound {limit}");
    // Stick (klippel §8 H11): a tiny slip, k|v_t| = 0.0443 N/m per step against f_max = 1.55e4 N/m accumulates
    // exactly, −n k v_t (1e-12), far below μ|f_c| after 1000 steps.
    let v_small = scale(1e-3, dir);
    let mut f = [0.0, 0.0];
    for i in 1..=1000 {
        f = friction_update(f, v_small, k, f_max);
        assert_vec_rel(f, scale(-(i as f64) * k, v_small), 1e-12, &format!("stick step {i}"));
    }
    assert!(norm(f) < 1e-2 * f_max);
}

#[test]
fn at43_friction_through_contact_force_sliding_on_the_rake() {
    let (tool, o) = reference_tool();
    let c = params();
    let k = KAPPA * MASS / DT;
    let d = 1e-6;
    let (p, n, t) = face(&o, RAKE as u32, 0.5);
    let x = sub(p, scale(d, n));
    let f_c = KAPPA * MASS * -tool.closest(x).distance / (DT * DT);
    let f_max = MU * f_c;
    // The particle slides up the rake at 9 m/s relative to a moving tool, plus a normal velocity component that the
    // tangential slip must not see: v − v_tool = 9 t + 3 n.
    let v_tool = [2.0, 0.5];
    let state = tool_state([0.0, 0.0], v_tool, DT, DT);
    let v = add(v_tool, add(scale(9.0, t), scale(3.0, n)));
    let inc = k * 9.0;
    let mut f = [0.0, 0.0];
    for step in 1..=60 {
        let r = contact_force(&c, &tool, &state, x, v, f, MASS, RHO, 300.0, 560.0, 0.0);
        let what = format!("step {step}");
        // No normal component (1e-12 of the force), opposite to the relative tangential velocity.
        assert!(dot(r.friction, n).abs() <= 1e-12 * norm(r.friction), "{what}: normal part {:e}", dot(r.friction, n));
        assert!(dot(r.friction, t) < 0.0, "{what}: friction {:?} not opposite to the slip", r.friction);
        // (5.129–5.130): |f_t| = min(step·k|v_t|, μ|f_c|) (1e-12).
        assert_rel(norm(r.friction), (step as f64 * inc).min(f_max), 1e-12, &what);
        f = r.friction;
    }
    // The friction history is projected on the current tangent: its normal part is dropped. With no slip
    // (v = v_tool), the history's tangential part is kept (stick, 1e-12) or capped at μ|f_c| (slip, 1e-14).
    let rest = tool_state([0.0, 0.0], v_tool, DT, DT);
    for (f_n, f_t) in [(5.0e3, 3.0e3), (-4.0e4, -1.0e4), (2.0e3, 3.0e4)] {
        let old = add(scale(f_n, n), scale(f_t, t));
        let r = contact_force(&c, &tool, &rest, x, v_tool, old, MASS, RHO, 300.0, 560.0, 0.0);
        let want = scale(f_t.signum() * f_t.abs().min(f_max), t);
        assert_vec_rel(r.friction, want, 1e-12, &format!("history ({f_n:e}, {f_t:e})"));
    }
}

#[test]
fn at43_relative_velocity_tool_moving_over_a_resting_particle() {
    let (tool, o) = reference_tool();
    let c = params();
    let k = KAPPA * MASS / DT;
    let (p, n, _) = face(&o, FLANK as u32, 0.5);
    let x = sub(p, scale(1e-6, n));
    // The tool moves at +1 m/s in x over a particle at rest on its flank (errata 25: v_rel = v − v_tool). The
    // slip is −(e_x − (e_x·n) n), so the friction on the particle is k(e_x − (e_x·n) n): along +x (the tool drags
    // the particle), tangential, of size k cos α < μ|f_c| (stick), 1e-12 relative.
    let state = tool_state([0.0, 0.0], [1.0, 0.0], DT, DT);
    let r = contact_force(&c, &tool, &state, x, [0.0, 0.0], [0.0, 0.0], MASS, RHO, 300.0, 560.0, 0.0);
    let e_t = sub([1.0, 0.0], scale(n[0], n));
    assert_vec_rel(r.friction, scale(k, e_t), 1e-12, "drag");
    assert!(r.friction[0] > 0.0, "friction {:?}", r.friction);
    assert!(dot(r.friction, n).abs() <= 1e-12 * norm(r.friction));
    assert_rel(norm(r.friction), k * 8f64.to_radians().cos(), 1e-12, "k cos α");
    // Moving with the tool: no slip, no friction (exactly zero from a zero history).
    let r = contact_force(&c, &tool, &state, x, [1.0, 0.0], [0.0, 0.0], MASS, RHO, 300.0, 560.0, 0.0);
    assert_eq!(r.friction, [0.0, 0.0]);
}

#[test]
fn friction_shear_stress_cap() {
    let (tool, o) = reference_tool();
    let (p, n, t) = face(&o, RAKE as u32, 0.5);
    let x = sub(p, scale(2e-6, n));
    let area = (MASS / RHO).sqrt();
    let f_c = KAPPA * MASS * -tool.closest(x).distance / (DT * DT);
    // Fast sliding (k|v_t| = 8.9e4 N/m > every cap here): the friction slides at its limit in one step.
    let v = scale(2000.0, t);
    let run = |mode: u32, cap_stress: f64, sy: f64| {
        let c = ContactParams { cap_mode: mode, cap_stress, ..params() };
        contact_force(&c, &tool, &at_rest(DT), x, v, [0.0, 0.0], MASS, RHO, 300.0, 560.0, sy)
    };
    // STATIC (7.6): F_max = min(μ|f_c|, τ A), A = √(m/ρ) (klippel (9.21), 2D face per unit depth); 1e-14 relative.
    for tau in [1e7, 5.0e8, 1.0e9, 5.0e9, 1e12] {
        let r = run(cap::STATIC, tau, 123.0);
        let want = (MU * f_c).min(tau * area);
        assert_rel(norm(r.friction), want, 1e-14, &format!("STATIC τ = {tau:e}"));
        assert!(norm(r.friction) <= tau * area * (1.0 + 1e-14));
        assert!(dot(r.friction, t) < 0.0);
    }
    // CURRENT (7.7): τ = (κ_fric/√3)·σ_y with the particle's current σ_y; it scales with σ_y while the cap binds.
    let k_fric = 1.0 / 3f64.sqrt();
    let mut prev = 0.0;
    for sy in [1e8, 2e8, 4e8, 8e8] {
        let r = run(cap::CURRENT, k_fric, sy);
        let want = (MU * f_c).min(k_fric * sy * area);
        assert!(k_fric * sy * area < MU * f_c, "the cap binds at σ_y = {sy:e}");
        assert_rel(norm(r.friction), want, 1e-14, &format!("CURRENT σ_y = {sy:e}"));
        if prev > 0.0 {
            assert_rel(norm(r.friction), 2.0 * prev, 1e-14, "doubling σ_y doubles the cap");
        }
        prev = norm(r.friction);
    }
    // A high current yield leaves Coulomb in charge; NONE ignores the cap stress.
    assert_rel(norm(run(cap::CURRENT, k_fric, 1e12).friction), MU * f_c, 1e-14, "CURRENT, Coulomb");
    assert_rel(norm(run(cap::NONE, 1.0, 1.0).friction), MU * f_c, 1e-14, "NONE");
}

#[test]
fn friction_heating_and_usui_wear() {
    let (tool, o) = reference_tool();
    let (p, n, t) = face(&o, FLANK as u32, 0.4);
    let x = sub(p, scale(1.5e-6, n));
    let area = (MASS / RHO).sqrt();
    let cp = 560.0;
    let (eta, psi, xi, temp) = (0.9, 1.0e-12, 1500.0, 800.0);
    let c = ContactParams { heat_fraction: eta, usui_psi: psi, usui_xi: xi, ..params() };
    // Slip of 7 m/s along the flank relative to the tool, with a small normal component.
    let v_tool = [-1.0, 0.0];
    let state = tool_state([0.0, 0.0], v_tool, DT, DT);
    let slip = 7.0;
    let v = add(v_tool, add(scale(slip, t), scale(0.01, n)));
    for history in [[0.0, 0.0], scale(-3e3, t), scale(5e4, t)] {
        let r = contact_force(&c, &tool, &state, x, v, history, MASS, RHO, temp, cp, 0.0);
        assert!(norm(r.friction) > 0.0 && norm(r.normal) > 0.0);
        // Friction heat ΔT = η Δt |f_t| |v_t| / (m c_p) (roethlin §5.2 step 12; here step = Δt): 1e-14 relative.
        let heat = eta * DT * norm(r.friction) * slip / (MASS * cp);
        assert_rel(r.heating, heat, 1e-14, &format!("heating, history {history:?}"));
        // Usui (erratum 16: exp(−ξ/T)): Ẇ = Ψ exp(−ξ/T) (|f_c|/A) |v_t|, A = √(m/ρ): 1e-14 relative.
        let wear = psi * (-xi / temp).exp() * (norm(r.normal) / area) * slip;
        assert_rel(r.wear, wear, 1e-14, &format!("wear, history {history:?}"));
    }
    // A step cut short (ToolState::step < dt, to land on an output time): the heat is η·step·|f_t||v_t|/(m c_p)
    // (1e-14), while the penalty and friction keep the nominal Δt's stiffness (identical forces).
    let short = ToolState { step: 0.3 * DT, ..state };
    let r_full = contact_force(&c, &tool, &state, x, v, [0.0; 2], MASS, RHO, temp, cp, 0.0);
    let r_short = contact_force(&c, &tool, &short, x, v, [0.0; 2], MASS, RHO, temp, cp, 0.0);
    assert_eq!((r_short.normal, r_short.friction, r_short.wear), (r_full.normal, r_full.friction, r_full.wear));
    let heat = eta * 0.3 * DT * norm(r_short.friction) * slip / (MASS * cp);
    assert_rel(r_short.heating, heat, 1e-14, "heating over a short step");
    // Both off: exactly zero, with the forces unchanged.
    let off = ContactParams { heat_fraction: 0.0, usui_psi: 0.0, ..c };
    let r_on = contact_force(&c, &tool, &state, x, v, [0.0; 2], MASS, RHO, temp, cp, 0.0);
    let r_off = contact_force(&off, &tool, &state, x, v, [0.0; 2], MASS, RHO, temp, cp, 0.0);
    assert_eq!((r_off.heating, r_off.wear), (0.0, 0.0));
    assert!(r_on.heating > 0.0 && r_on.wear > 0.0);
    assert_eq!((r_off.normal, r_off.friction), (r_on.normal, r_on.friction));
}

// The BULK penalty law and the damped spring (issue 22 item 3; kernels/src/contact/penalty.rs)

/// Ti6Al4V's bulk modulus K = E/(3(1 − 2ν)) with E = 110 GPa, ν = 0.35 (roethlin §5.7) [Pa].
const BULK: f64 = 110e9 / (3.0 * (1.0 - 2.0 * 0.35));

fn bulk_params(damping: f64) -> ContactParams {
    ContactParams { law: law::BULK, bulk: BULK, damping, ..params() }
}

/// LS-DYNA's penalty (5.117) in 2D per unit depth: f_c = κ K A²/V d = κ K d, the same for every time step (the
/// STEP law's force grows as 1/Δt²); 1e-14 relative against the tool's exact depth.
#[test]
fn bulk_penalty_is_kappa_k_d_at_every_time_step() {
    let (tool, o) = reference_tool();
    let c = bulk_params(0.0);
    for (prim, t) in [(RAKE as u32, 0.5), (FLANK as u32, 0.5), (ARC, 0.4)] {
        let (p, n, _) = face(&o, prim, t);
        for d in [1e-8, 1e-7, 1e-6] {
            let x = sub(p, scale(d, n));
            let g = tool.closest(x);
            let want = scale(KAPPA * BULK * -g.distance, g.normal);
            for dt in [DT, 0.5 * DT, 4.7e-10] {
                let r = contact_force(&c, &tool, &at_rest(dt), x, [0.0; 2], [0.0; 2], MASS, RHO, 300.0, 560.0, 0.0);
                assert_vec_rel(r.normal, want, 1e-14, &format!("primitive {prim}, d = {d:e}, Δt = {dt:e}"));
            }
        }
    }
}

/// The dashpot: f_c = max(0, k d − 2ξ√(k m) v_n) with v_n = (v − v_tool)·n; approaching particles are pushed harder,
/// receding ones less, never pulled in (1e-13 relative; exactly zero when clamped). ξ = 0 is the undamped spring.
#[test]
fn damped_penalty_adds_the_dashpot_and_never_pulls() {
    let (tool, o) = reference_tool();
    let (p, n, _) = face(&o, RAKE as u32, 0.5);
    let d = 1e-7;
    let x = sub(p, scale(d, n));
    let depth = -tool.closest(x).distance;
    for (c, k) in
        [(bulk_params(0.7), KAPPA * BULK), (ContactParams { damping: 0.7, ..params() }, KAPPA * MASS / (DT * DT))]
    {
        let cd = 2.0 * 0.7 * (k * MASS).sqrt();
        for vn in [-3.0, -0.1, 0.0, 0.2] {
            // A tangential velocity does not enter the normal force.
            let v = add(scale(vn, n), [0.0, 1.5]);
            let v = sub(v, scale(dot([0.0, 1.5], n), n));
            let r = contact_force(&c, &tool, &at_rest(DT), x, v, [0.0; 2], MASS, RHO, 300.0, 560.0, 0.0);
            let want = (k * depth - cd * dot(v, n)).max(0.0);
            assert_rel(dot(r.normal, n), want, 1e-13, &format!("law {}, v_n = {vn}", c.law));
        }
        // Receding fast: the dashpot would pull; the force is zero instead.
        let v = scale(10.0 * k * depth / cd, n);
        let r = contact_force(&c, &tool, &at_rest(DT), x, v, [0.0; 2], MASS, RHO, 300.0, 560.0, 0.0);
        assert_eq!(r.normal, [0.0, 0.0], "law {}: receding particle", c.law);
    }
    // ξ = 0: the spring alone, bit for bit.
    let r0 = contact_force(
        &bulk_params(0.0),
        &tool,
        &at_rest(DT),
        x,
        scale(-3.0, n),
        [0.0; 2],
        MASS,
        RHO,
        300.0,
        560.0,
        0.0,
    );
    assert_eq!(dot(r0.normal, n), KAPPA * BULK * depth);
}

/// BULK friction: the stick stiffness is κ_t K per unit slip, so a particle sliding at |v_t| gains κ_t K |v_t| Δt
/// per step of length Δt and saturates at μ f_c after the slip distance μ f_c/(κ_t K) = μ d, the same distance
/// whatever the step (1e-12 relative; the STEP law's slip to saturation scales with Δt²).
#[test]
fn bulk_friction_saturates_after_a_slip_of_mu_times_the_penetration() {
    let (tool, o) = reference_tool();
    let c = bulk_params(0.0);
    let (p, n, t) = face(&o, RAKE as u32, 0.5);
    let d = 2e-7;
    let x = sub(p, scale(d, n));
    let depth = -tool.closest(x).distance;
    let v_t = 4.0;
    for dt in [DT, 0.25 * DT] {
        let mut f = [0.0, 0.0];
        let mut steps_to_saturate = None;
        for i in 1..=2000 {
            let r = contact_force(&c, &tool, &at_rest(dt), x, scale(v_t, t), f, MASS, RHO, 300.0, 560.0, 0.0);
            let along = -dot(r.friction, t);
            let want = (i as f64 * KAPPA * BULK * v_t * dt).min(MU * KAPPA * BULK * depth);
            assert_rel(along, want, 1e-12, &format!("Δt = {dt:e}, step {i}"));
            if steps_to_saturate.is_none() && along >= MU * KAPPA * BULK * depth * (1.0 - 1e-12) {
                steps_to_saturate = Some(i);
            }
            f = r.friction;
        }
        let slip = steps_to_saturate.expect("saturates") as f64 * v_t * dt;
        assert!((slip - MU * depth).abs() <= v_t * dt, "Δt = {dt:e}: slip to saturation {slip:e} m against μ d");
    }
}
