//! The cut in the picture (issue 27, item 4): every frame of a run with a tool has the tool's outline beside it
//! (`tool_NNNNN.vtp`, part 1 of the frame's time step in `particles.pvd`) and the per-particle contact forces
//! (`contact_normal_force`, `contact_friction_force`, three components) in the VTU.

use std::process::Command;
use swarf::kernels::contact::tool2d::Tool2d;
use swarf::output::{OwnedValues, pvd, vtp, vtu};
use swarf::scene::Scene;
use swarf::tool::outline::outline;
use swarf::tool::setup::{build_tool, motion};

fn tool_of(path: &str) -> (Scene, Tool2d) {
    let text = std::fs::read_to_string(path).expect("scene");
    let scene = Scene::from_str(&text, path, &[]).expect("scene parses");
    let tool = build_tool(scene.tool.as_ref().expect("a tool")).expect("tool builds");
    (scene, tool)
}

/// Every vertex of the outline lies on the tool's boundary (its exact signed distance, `Tool2d::closest`, is zero
/// to rounding: 1e-9 of the edge radius at most), the polygon runs counter-clockwise (positive area), and each
/// edge's midpoint is on or inside the boundary: on it for the straight faces, at most the chord's sagitta
/// r (1 − cos(Δθ/2)) inside on the arc. For the V0060 tool and for the same tool with a sharp edge.
#[test]
fn the_outline_lies_on_the_tool() {
    let (scene, rounded) = tool_of("cases/cutting/v0060.toml");
    let mut sharp_spec = scene.tool.clone().expect("tool");
    sharp_spec.edge_radius = 0.0;
    let sharp = build_tool(&sharp_spec).expect("a sharp tool builds");
    for (what, tool) in [("rounded", rounded), ("sharp", sharp)] {
        let pts = outline(&tool);
        let scale = tool.radius.max(1e-6);
        // F, T_f, the arc, T_r, R, TL; a sharp edge is the quadrilateral F, T, R, TL.
        assert!(pts.len() >= if tool.radius > 0.0 { 7 } else { 4 }, "{what}: {} vertices", pts.len());
        for (i, p) in pts.iter().enumerate() {
            let d = tool.closest(*p).distance;
            assert!(d.abs() <= 1e-9 * scale, "{what}: vertex {i} {p:?} is {d:e} m from the boundary");
        }
        let area: f64 = (0..pts.len())
            .map(|i| {
                let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
            / 2.0;
        assert!(area > 0.0, "{what}: the outline runs clockwise (area {area:e})");
        // 16 points per radian: Δθ ≤ 1/16 rad, sagitta ≤ r (1 − cos(1/32)).
        let sagitta = tool.radius * (1.0 - (1.0f64 / 32.0).cos());
        for i in 0..pts.len() {
            let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
            let m = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
            let d = tool.closest(m).distance;
            assert!(d <= 1e-9 * scale && d >= -sagitta - 1e-9 * scale, "{what}: edge {i}'s midpoint at {d:e} m");
        }
    }
}

/// A short V0060 cut on the CPU: the PVD lists a tool outline for every frame at the frame's time; each outline
/// is the tool's outline moved by the scene's motion at that time (to 1e-15 m: the same additions); the frames
/// carry both contact forces with three components and z = 0; at the last frame the tool touches the workpiece
/// (non-zero normal forces), only particles within 2 Δx of the tool carry a force, and the friction force of each
/// is tangential: orthogonal to its normal force to 1e-9 of their magnitudes (the LS-DYNA friction acts in the
/// contact plane, kernels/src/contact/penalty.rs).
#[test]
fn frames_carry_the_tool_outline_and_the_contact_forces() {
    let out = std::env::temp_dir().join(format!("swarf-frame-tool-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let st = Command::new(env!("CARGO_BIN_EXE_swarf"))
        .args(["--backend", "cpu", "run", "cases/cutting/v0060.toml", "--quiet", "--set", "time.end=4e-6", "--out"])
        .arg(&out)
        .status()
        .expect("swarf runs");
    assert!(st.success());
    let (scene, tool) = tool_of("cases/cutting/v0060.toml");
    let m = motion(scene.tool.as_ref().expect("tool"));
    let entries = pvd::read_parts(&out.join("particles.pvd")).expect("pvd");
    let frames: Vec<_> = entries.iter().filter(|e| e.1 == 0).collect();
    let tools: Vec<_> = entries.iter().filter(|e| e.1 == 1).collect();
    assert!(frames.len() >= 2, "{} frames", frames.len());
    assert_eq!(frames.iter().map(|e| e.0).collect::<Vec<_>>(), tools.iter().map(|e| e.0).collect::<Vec<_>>());
    let local = outline(&tool);
    for (t, _, file) in &tools {
        let (time, pts) = vtp::read_outline(&out.join(file)).expect("outline reads");
        assert_eq!(time, *t, "{file}: its time");
        let o = m.offset_at(*t);
        assert_eq!(pts.len(), local.len(), "{file}");
        for (p, q) in pts.iter().zip(&local) {
            let want = [o[0] + q[0], o[1] + q[1], 0.0];
            assert!(p.iter().zip(want).all(|(a, b)| (a - b).abs() <= 1e-15), "{file}: {p:?} against {want:?}");
        }
    }
    let (t_last, _, last) = frames.last().expect("a frame");
    let f = vtu::read(&out.join(last)).expect("frame reads");
    let array = |name: &str| -> Vec<f64> {
        let (_, c, v) = f.point_data.iter().find(|(n, _, _)| n == name).unwrap_or_else(|| panic!("no {name}"));
        assert_eq!(*c, 3, "{name}: components");
        match v {
            OwnedValues::F64(v) => v.clone(),
            other => panic!("{name}: {other:?}"),
        }
    };
    let (fnorm, ffric) = (array("contact_normal_force"), array("contact_friction_force"));
    let pos = match &f.points {
        OwnedValues::F64(v) => v.clone(),
        other => panic!("points {other:?}"),
    };
    let o = m.offset_at(*t_last);
    let dx = scene.discretisation.dx;
    let mut touching = 0;
    for i in 0..f.n {
        let (n, t) = (&fnorm[3 * i..3 * i + 3], &ffric[3 * i..3 * i + 3]);
        assert_eq!((n[2], t[2]), (0.0, 0.0), "particle {i}: z components");
        let mag = (n[0] * n[0] + n[1] * n[1]).sqrt();
        if mag == 0.0 {
            continue;
        }
        touching += 1;
        let d = tool.closest([pos[3 * i] - o[0], pos[3 * i + 1] - o[1]]).distance;
        assert!(d.abs() <= 2.0 * dx, "particle {i} carries a contact force {d:e} m from the tool");
        let tm = (t[0] * t[0] + t[1] * t[1]).sqrt();
        let dot = n[0] * t[0] + n[1] * t[1];
        assert!(dot.abs() <= 1e-9 * mag * tm.max(mag), "particle {i}: friction not tangential ({dot:e})");
    }
    assert!(touching > 0, "no particle touches the tool at t = {t_last:e} s");
    let _ = std::fs::remove_dir_all(&out);
}
