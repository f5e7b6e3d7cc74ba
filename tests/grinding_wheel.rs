//! Issue 24: the grinding wheel segment's scenes (cases/3d/grinding-wheel-{a,b,c}.toml, written by
//! cases/3d/grinding-wheel.py; docs/3d.md "Grinding wheel segment") carry the kinematics rebuilt from the thesis'
//! wheel, pattern and feed (roethlin-solver.md §7.10, the [D] note on §7.6.3): every grain turns about one axis
//! along +z through the wheel's centre, d = 10 µm below the workpiece's top plus the radius; the grains' flat faces
//! lie on the wheel's radius r = 250 µm; one revolution per 2r of feed (v_s = π v_w); the run is half a revolution;
//! the active box moves with the feed. CPU (reads the scenes only).

use swarf::scene::{Scene, Shape};

const R: f64 = 250e-6;
const FEED: f64 = 1.8;
const DEPTH: f64 = 10e-6;

#[test]
fn wheel_scenes_hold_the_rebuilt_kinematics() {
    for (p, per_turn) in [("a", 8usize), ("b", 16), ("c", 31)] {
        let file = format!("cases/3d/grinding-wheel-{p}.toml");
        let scene = Scene::load(&file, &[]).unwrap_or_else(|e| panic!("{file}: {e}"));
        let Shape::Box { min, max } = scene.bodies[0].shape else { panic!("{file}: the workpiece is a box") };
        let mut axis_point: Option<[f64; 3]> = None;
        let mut grains = 0;
        for t in scene.tools() {
            let r = t.rotation.as_ref().unwrap_or_else(|| panic!("{file}: every grain turns"));
            assert_eq!(r.axis, [0.0, 0.0, 1.0], "{file}: the wheel's axis");
            let omega = r.rpm * std::f64::consts::TAU / 60.0;
            // One revolution per 2r of feed: v_s = ω r = π v_w (1e-9: rpm is written to 0.1).
            assert!((omega * R / (std::f64::consts::PI * FEED) - 1.0).abs() < 1e-9, "{file}: v_s = {}", omega * R);
            assert_eq!(t.velocity, [FEED, 0.0, 0.0], "{file}: the feed");
            let a: [f64; 3] = std::array::from_fn(|k| t.position[k] + r.centre[k]);
            // One axis for every grain (to the file's 7 digits: 1e-10 m), at the top − d + r.
            let first = *axis_point.get_or_insert(a);
            assert!((a[0] - first[0]).abs() < 1e-10 && (a[1] - first[1]).abs() < 1e-10, "{file}: axis {a:?}");
            assert!((a[1] - (max[1] - DEPTH + R)).abs() < 1e-10, "{file}: axis height {}", a[1]);
            // The flat face on the radius: the farthest vertex from the axis lies between r and the face's corner
            // (its half-diagonal of about 10 µm adds 0.2 µm).
            let mesh = t.mesh.as_ref().unwrap_or_else(|| panic!("{file}: a mesh grain"));
            let far = (mesh.grid.verts.iter())
                .map(|v| (t.position[0] + v[0] - a[0]).hypot(t.position[1] + v[1] - a[1]))
                .fold(0.0, f64::max);
            assert!((R - 1e-10..=R + 0.5e-6).contains(&far), "{file}: a grain's reach {far:e}");
            // Each grain's lane lies inside the workpiece's width.
            let z: Vec<f64> = mesh.grid.verts.iter().map(|v| t.position[2] + v[2]).collect();
            let mid = 0.5 * (z.iter().cloned().fold(f64::MAX, f64::min) + z.iter().cloned().fold(f64::MIN, f64::max));
            assert!(min[2] < mid && mid < max[2], "{file}: a grain's lane at z = {mid:e}");
            grains += 1;
        }
        // Half a revolution; never more grains than two lanes hold.
        let omega = std::f64::consts::TAU * scene.tools().next().and_then(|t| t.rotation.as_ref()).unwrap().rpm / 60.0;
        assert!((omega * scene.time.end / std::f64::consts::PI - 1.0).abs() < 1e-6, "{file}: end {}", scene.time.end);
        assert!(grains > per_turn / 2 && grains <= 2 * per_turn, "{file}: {grains} grains");
        let b = scene.blanking.as_ref().unwrap_or_else(|| panic!("{file}: blanking"));
        assert_eq!(b.velocity, [FEED, 0.0, 0.0], "{file}: the active box moves with the feed");
        let a = axis_point.expect("grains");
        assert!(b.min[0] < a[0] && a[0] + (2.0 * R * DEPTH).sqrt() < b.max[0], "{file}: the box holds the engaged arc");
    }
}
