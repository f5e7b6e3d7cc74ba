//! The synthetic chip station shared by the chip-thickness tests (tests/cutting_analysis.rs, tests/steady_state.rs):
//! a 10 µm lattice, the rake point away from the origin so that the frame's offset is exercised, the uncut surface
//! 8 Δx above it and the station 30 Δx up the face.

use swarf::cutting::chip::Station;

pub const DX: f64 = 10e-6;
/// Cutting edge (the rake point) away from the origin, so that the frame's offset is exercised.
pub const EDGE: [f64; 2] = [2.0e-3, 1.0e-3];
/// Uncut chip thickness: the top surface lies 8Δx above the edge.
pub const SURFACE: f64 = EDGE[1] + 8.0 * DX;
pub const STATION: f64 = 30.0 * DX;

/// The station at rake angle `rake_deg` (degrees).
pub fn station(rake_deg: f64) -> Station {
    Station {
        rake_point: EDGE,
        rake_angle: rake_deg.to_radians(),
        surface_y: SURFACE,
        station: STATION,
        half_width: DX,
        spacing: DX,
    }
}

/// The point with face coordinates (u, w): rake_point + u d + w n (d up the face, n out of it).
pub fn at(s: &Station, u: f64, w: f64) -> [f64; 2] {
    let (sin, cos) = s.rake_angle.sin_cos();
    [s.rake_point[0] - u * sin + w * cos, s.rake_point[1] + u * cos + w * sin]
}
