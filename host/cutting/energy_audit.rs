//! The energy audit of a run with a tool (docs/validation.md, "Energy audit of the cut"): the work of the tools'
//! contact forces, integrated over the samples of `forces.csv`, against the energy the solver books.
//!
//! A sample holds the contact's power ([`ContactPower`]: the tool's Σ f·v_T, the friction's Σ f_t·(v_T − v) and
//! the penalty's Σ f_c·(v_T − v)). The works are their integrals by the trapezoid rule over the samples, from
//! (t = 0, P = 0): before the first step no contact force acts. Nothing else works on the workpiece (fixed rows
//! and prescribed velocities aside), so the work the particles receive, W_p = W_tool − W_friction − W_normal, must
//! equal the change of energy.csv's `balance` (kinetic + elastic + plastic work + viscous dissipation, + the
//! cohesive and damage terms), up to the time integration's and the sampling's errors; booked/W_p > 1 is energy
//! the discretisation created.

use crate::tool::ContactPower;
use serde_json::{Value, json};

/// The works so far, fed sample by sample [J; per m of depth in 2D].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyAudit {
    /// ∫ Σ f·v_T dt: the tools' work on the workpiece.
    pub tool: f64,
    /// ∫ Σ f_t·(v_T − v) dt: taken out by friction at the interface.
    pub friction: f64,
    /// ∫ Σ f_c·(v_T − v) dt: taken out by the penalty (stored while pressed in) and its dashpot.
    pub normal: f64,
    /// Samples integrated.
    pub samples: usize,
    last: (f64, ContactPower),
}

impl EnergyAudit {
    /// Adds the sample at `time` (a non-finite power, e.g. a record written before the columns existed, is skipped).
    pub fn push(&mut self, time: f64, p: ContactPower) {
        if ![p.tool, p.friction, p.normal].iter().all(|x| x.is_finite()) {
            return;
        }
        let (t0, p0) = self.last;
        let dt = time - t0;
        self.tool += 0.5 * (p0.tool + p.tool) * dt;
        self.friction += 0.5 * (p0.friction + p.friction) * dt;
        self.normal += 0.5 * (p0.normal + p.normal) * dt;
        self.samples += 1;
        self.last = (time, p);
    }

    /// The work the workpiece's particles received, W_tool − W_friction − W_normal.
    pub fn workpiece(&self) -> f64 {
        self.tool - self.friction - self.normal
    }

    /// summary.json's `energy_audit` with the energy the run booked, `booked` (the change of `balance`).
    pub fn json(&self, booked: f64) -> Value {
        let num = |x: f64| Some(x).filter(|v| v.is_finite());
        let ratio = |w: f64| num(booked / w).filter(|_| w != 0.0);
        json!({
            "tool_work_j": num(self.tool),
            "friction_work_j": num(self.friction),
            "normal_work_j": num(self.normal),
            "workpiece_work_j": num(self.workpiece()),
            "booked_j": num(booked),
            "booked_over_workpiece_work": ratio(self.workpiece()),
            "booked_over_tool_work": ratio(self.tool),
            "samples": self.samples,
            "method": "works per m of depth in 2D: the contact forces' power at each sample of forces.csv (tool: \
                       Σ f·v_T, friction: Σ f_t·(v_T − v), normal: Σ f_c·(v_T − v), v_T the tool's velocity at the \
                       particle) integrated by the trapezoid rule from t = 0; booked: the change of energy.csv's \
                       balance over the run (docs/validation.md, \"Energy audit of the cut\")",
        })
    }

    /// The log's line.
    pub fn line(&self, booked: f64) -> String {
        format!(
            "energy audit: tool work {:.4e} J, friction {:.4e} J, penalty {:.4e} J; the particles received {:.4e} J \
             and the solver booked {:.4e} J ({:.3} of it)",
            self.tool,
            self.friction,
            self.normal,
            self.workpiece(),
            booked,
            booked / self.workpiece()
        )
    }
}
