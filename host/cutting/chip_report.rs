//! The frame chip geometry ([`super::chip_frame`]) as users get it: the `cutting.chip_frame` entry of
//! summary.json, the line the run prints, and the table `swarf chip` prints, with Klippel's Tab. 9.56 beside it
//! for V0060 (klippel-constitutive.md §4.9).

use super::chip_frame::FrameChip;
use std::fmt::Write;

/// Tab. 9.56 (V0060, Ti6Al4V, 381.3 m/min, f = 0.1 mm): h_min, h_max, l_seg, t_seg, t_sl [µm] as printed
/// (ranges as text), for the experiment and Klippel's 208 732-particle simulation.
pub const TAB_9_56: [(&str, [&str; 5]); 2] = [
    ("Klippel Tab. 9.56, experiment", ["80", "150", "51-56", "4-6", "3"]),
    ("Klippel Tab. 9.56, SPH 208 732 particles", ["73-82", "120", "33-39", "6-11", "5-6"]),
];

/// µm of a length [m], None where it is not finite.
fn um(x: Option<f64>) -> Option<f64> {
    x.filter(|v| v.is_finite()).map(|v| v * 1e6)
}

/// The `cutting.chip_frame` entry of summary.json (µm, kHz; null where there is nothing to report), at `time`.
pub fn json(c: Option<&FrameChip>, time: f64) -> serde_json::Value {
    let Some(c) = c else { return serde_json::Value::Null };
    let seg = c.segments;
    serde_json::json!({
        "time_s": time,
        "sections": c.sections,
        "particles": c.particles,
        "length_um": um(Some(c.length)),
        "h_avg_um": um(Some(c.h_avg)),
        "h_p10_um": um(Some(c.h_p10)),
        "h_p90_um": um(Some(c.h_p90)),
        "segmentation": Some(c.segmentation).filter(|v| v.is_finite()),
        "v_chip_m_per_s": Some(c.v_chip).filter(|v| v.is_finite()),
        "segments": seg.map(|s| serde_json::json!({
            "crests": s.crests,
            "valleys": s.valleys,
            "h_min_um": um(Some(s.h_min)),
            "h_max_um": um(Some(s.h_max)),
            "degree": Some(s.degree).filter(|v| v.is_finite()),
            "l_seg_um": um(Some(s.l_seg)),
            "frequency_khz": Some(s.frequency * 1e-3).filter(|v| v.is_finite()),
        })),
        "t_seg_um": um(c.t_seg),
        "bands": c.bands,
        "t_sl_um": um(c.t_sl),
        "r_chip_um": um(c.r_chip),
        "method": "one frame's chip followed from the rake face to its free end in cross-sections normal to its \
                   axis, one spacing apart, less its head (the chip of the first 3 t1 of travel); h_min/h_max the mean valley/crest thickness (hysteresis 2 dx), l_seg the \
                   mean crest distance along the chip, f = v_c t1/h_avg / l_seg, t_seg and t_sl full widths at half \
                   maximum of the plastic strain above the chip's median, r_chip a circle fitted to the centreline \
                   off the rake face (docs/validation.md, \"Chip analysis of a frame\")",
    })
}

/// A value with its unit, or "n/a".
fn show(x: Option<f64>, scale: f64, unit: &str) -> String {
    x.filter(|v| v.is_finite()).map_or("n/a".to_string(), |v| format!("{:.1} {unit}", v * scale))
}

/// The one line a run prints after its cutting line.
pub fn line(c: &FrameChip) -> String {
    let s = c.segments;
    format!(
        "chip (last frame): h_avg {}, h_min {}, h_max {}, l_seg {}, f {}, t_seg {}, t_sl {}, r_chip {}",
        show(Some(c.h_avg), 1e6, "um"),
        show(s.map(|s| s.h_min), 1e6, "um"),
        show(s.map(|s| s.h_max), 1e6, "um"),
        show(s.map(|s| s.l_seg), 1e6, "um"),
        show(s.map(|s| s.frequency), 1e-3, "kHz"),
        show(c.t_seg, 1e6, "um"),
        show(c.t_sl, 1e6, "um"),
        show(c.r_chip, 1e6, "um"),
    )
}

/// The table `swarf chip` prints: one row per quantity (value and definition), then Tab. 9.56 where `v0060`.
pub fn table(c: &FrameChip, v0060: bool) -> String {
    let s = c.segments;
    let rows: [(&str, String, &str); 12] = [
        ("h_avg", show(Some(c.h_avg), 1e6, "um"), "mean thickness along the chip"),
        ("h_min", show(s.map(|s| s.h_min), 1e6, "um"), "mean valley thickness"),
        ("h_max", show(s.map(|s| s.h_max), 1e6, "um"), "mean crest thickness"),
        (
            "segments",
            s.map_or("0".into(), |s| format!("{} crests", s.crests)),
            "crests along the chip (hysteresis 2 dx)",
        ),
        ("degree", s.map_or("n/a".into(), |s| format!("{:.2}", s.degree)), "(h_max - h_min)/h_max"),
        ("segmentation", format!("{:.2}", c.segmentation), "(h_90 - h_10)/h_90 of the thickness along the chip"),
        ("l_seg", show(s.map(|s| s.l_seg), 1e6, "um"), "mean distance between crests along the chip"),
        ("f_seg", show(s.map(|s| s.frequency), 1e-3, "kHz"), "v_chip/l_seg, v_chip = v_c t1/h_avg"),
        ("t_seg", show(c.t_seg, 1e6, "um"), "primary shear band thickness (FWHM of plastic strain)"),
        ("t_sl", show(c.t_sl, 1e6, "um"), "secondary shear layer thickness along the rake side"),
        ("r_chip", show(c.r_chip, 1e6, "um"), "curl radius of the centreline off the rake face"),
        ("v_chip", format!("{:.3} m/s", c.v_chip), "chip speed v_c t1/h_avg"),
    ];
    let mut out = String::new();
    for (name, value, what) in rows {
        let _ = writeln!(out, "{name:<13} {value:>14}   {what}");
    }
    let _ = writeln!(out, "({} sections over {:.1} um of chip, {} particles)", c.sections, c.length * 1e6, c.particles);
    if v0060 {
        out.push_str(&beside_tab_9_56(c));
    }
    out
}

/// This frame's h_min, h_max, l_seg, t_seg, t_sl beside the rows of Tab. 9.56 [µm].
fn beside_tab_9_56(c: &FrameChip) -> String {
    let s = c.segments;
    let cell = |x: Option<f64>| x.filter(|v| v.is_finite()).map_or("n/a".to_string(), |v| format!("{:.1}", v * 1e6));
    let this = [s.map(|s| s.h_min), s.map(|s| s.h_max), s.map(|s| s.l_seg), c.t_seg, c.t_sl].map(cell);
    let mut out = String::from("\n| [um] | h_min | h_max | l_seg | t_seg | t_sl |\n|---|---|---|---|---|---|\n");
    let _ = writeln!(out, "| this frame | {} |", this.join(" | "));
    for (name, v) in TAB_9_56 {
        let _ = writeln!(out, "| {name} | {} |", v.join(" | "));
    }
    out
}
