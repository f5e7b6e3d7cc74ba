//! A fragment for the MPM particle update's test (docs/mpm.md "Fragments"), shared by the CPU and GPU tests: the
//! short cut with one specimen particle moved 3 h above the block, alone on its nodes, and it and two controls
//! (an interior particle and a corner of the block) given an elastic B̄_e ≠ I.

use swarf::backend::Backend;
use swarf::kernels::Real;
use swarf::kernels::mpm::grid::ABOVE;
use swarf::mpm::setup::{MpmSetup, setup};
use swarf::mpm::solver::MpmSolver;
use swarf::scene::mpm::MpmScene;

/// The elastic B̄_e (xx, xy, yy, zz) the three particles start with: dev B̄_e = (0.01, 0.005, −0.01, 0), a
/// von Mises stress of 0.027 G, below yield.
pub const BE: [f64; 4] = [1.01, 0.005, 0.99, 1.0];

/// The particles: the fragment, the interior control and the corner control.
pub struct Fragment {
    pub lone: usize,
    pub interior: usize,
    pub corner: usize,
}

/// The short cut's set-up (7 particles through h), its fragment moved 3 h up, and the three particles.
pub fn fragment_setup() -> (MpmSetup, Fragment) {
    let sets: Vec<String> =
        ["cut.particles_across=7", "cut.cut_length=2.0", "time.end=1.3e-3"].iter().map(|s| s.to_string()).collect();
    let scene = MpmScene::load("cases/mpm/nairn-cut.toml", &sets).expect("scene");
    let mut s = setup(&scene).expect("setup");
    let pts = &s.points;
    let above: Vec<usize> = (0..pts.pos.len()).filter(|&i| pts.kind[i] == ABOVE).collect();
    let key = |i: &usize| pts.pos[*i][0] + pts.pos[*i][1];
    // The block's top right corner is the fragment, the next one along the diagonal the corner control.
    let mut by_diag = above.clone();
    by_diag.sort_by(|a, b| key(a).total_cmp(&key(b)));
    let (lone, corner) = (by_diag[by_diag.len() - 1], by_diag[by_diag.len() - 2]);
    let (lo, hi) = above.iter().fold(([f64::MAX; 2], [f64::MIN; 2]), |(lo, hi), &i| {
        let p = pts.pos[i];
        ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
    });
    let centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    let d2 = |i: usize| (pts.pos[i][0] - centre[0]).powi(2) + (pts.pos[i][1] - centre[1]).powi(2);
    let interior = above.iter().copied().min_by(|&a, &b| d2(a).total_cmp(&d2(b))).expect("particles above");
    // 3 h above the block (h = 1 mm in nairn-cut.toml), inside the room the grid keeps for the chip.
    s.points.pos[lone][1] += 3e-3;
    (s, Fragment { lone, interior, corner })
}

/// The solver of [`fragment_setup`] with [`BE`] in the three particles.
pub fn fragment_solver<B: Backend, R: Real>(b: &B, s: &MpmSetup, f: &Fragment) -> MpmSolver<B, R> {
    let mut m = MpmSolver::<B, R>::new(b, s, 1.0).expect("solver");
    let mut state = m.save_state(b).expect("state");
    let be = &mut state.iter_mut().find(|(name, _)| name == "be").expect("the B_e blob").1;
    let width = be.len() / s.points.pos.len();
    for i in [f.lone, f.interior, f.corner] {
        let value: Vec<u8> = if width == 32 {
            bytemuck::cast_slice(&BE).to_vec()
        } else {
            bytemuck::cast_slice(&BE.map(|x| x as f32)).to_vec()
        };
        be[i * width..(i + 1) * width].copy_from_slice(&value);
    }
    m.load_state(b, &state).expect("load");
    m
}
