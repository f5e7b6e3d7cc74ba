//! Scene texts shared by the CPU and GPU tests.

/// A Ti6Al4V block (elastic–plastic, 12 × 6 particles, Δx = 10 µm) dropped at `speed` onto the flat top face of a
/// resting tool (rake 0°, clearance 7°, top at y = 0.2 mm).
pub fn drop_scene(speed: f64, kappa: f64, friction: f64, slide: f64) -> String {
    format!(
        r#"
name = "drop"
dim = 2
[discretisation]
dx = 1.0e-5
h_over_dx = 1.5
[material]
name = "Ti6Al4V-V0060-DE-mu035"
[physics]
plastic_heating = false
[[body]]
name = "block"
shape = "rectangle"
min = [-3.0e-4, 2.02e-4]
max = [-1.8e-4, 2.62e-4]
velocity = [{slide}, -{speed}]
[tool]
rake_angle = 0.0
clearance_angle = 7.0
edge_radius = 2.0e-5
length = 4.0e-4
height = 2.0e-4
position = [0.0, 0.0]
velocity = [0.0, 0.0]
contact_stiffness = {kappa}
friction = {friction}
[stabilisation]
artificial_viscosity = {{ alpha = 1.0, beta = 1.0, eta = 0.1 }}
[time]
end = 1.2e-6
[output]
every = 2.0e-9
"#
    )
}

/// [`drop_scene`] at 50 m/s with a sliding component, plastic with heating, the CURRENT friction cap, friction
/// heating and the Usui wear output: every input of the contact pass that the plastic corrector produces.
pub fn plastic_drop_scene() -> String {
    drop_scene(50.0, 0.1, 0.35, 10.0)
        .replace("plastic_heating = false", "plasticity = true\nplastic_heating = true")
        .replace(
            "friction = 0.35\n",
            "friction = 0.35\nfriction_cap = \"current\"\nfriction_heating = 0.5\nusui = { psi = 1.0e-9, xi = 5000.0 }\n",
        )
}
