//! The MPM scene's tables (`scene::mpm`), validated key by key like the SPH scene's.

use super::super::doc::{Doc, Val};
use super::super::mpm::{
    BondSetup, CohesiveSpec, CutSetup, Damping, LawShape, MpmMaterial, MpmScene, MpmTime, PositionUpdate, Setup,
};
use super::{Result, Tab, plain_file_name, positive};
use crate::scene::Precision;

const ROOT_KEYS: &[&str] = &["method", "name", "precision", "material", "cohesive", "cut", "bond", "time", "damping"];

/// `[time]`'s defaults (its `end` is the set-up's).
const TIME: MpmTime = MpmTime { end: 0.0, cfl: 0.5, samples: 400, frames: 10 };
/// `[damping]`'s defaults: full PIC, no start-up damping.
const DAMPING: Damping = Damping { pic: 1.0, feedback: 0.0, position_update: PositionUpdate::Second };

/// The whole MPM scene.
pub(in crate::scene) fn mpm_scene(doc: &Doc) -> Result<MpmScene> {
    let Val::Table(entries) = &doc.root.val else { unreachable!("a TOML document is a table") };
    let root = Tab { doc, path: "", node: &doc.root, entries };
    root.check_keys(ROOT_KEYS, &["dim", "body", "tool", "discretisation"], " (an SPH key: this is an MPM scene)")?;
    let e =
        "a non-empty string naming the scene, a plain file name for its run folder (no '/' or '\\', not '.' or '..')";
    let name = root.required("name", e, root.string("name", e, plain_file_name)?)?.to_string();
    let e = "\"f32\" or \"f64\"";
    let precision = root
        .string("precision", e, |s| s == "f32" || s == "f64")?
        .and_then(Precision::from_name)
        .unwrap_or(Precision::F64);
    let material = material(&root)?;
    let cohesive = cohesive(&root)?;
    let setup = setup(&root)?;
    let time = time(&root, &setup)?;
    let damping = damping(&root)?;
    Ok(MpmScene { origin: doc.file.clone(), name, precision, material, cohesive, setup, time, damping })
}

/// The `method` key: "sph" (default) or "mpm".
pub(in crate::scene) fn method(doc: &Doc) -> Result<String> {
    let Val::Table(entries) = &doc.root.val else { unreachable!("a TOML document is a table") };
    let root = Tab { doc, path: "", node: &doc.root, entries };
    let m = root.string("method", "\"sph\" or \"mpm\"", |s| s == "sph" || s == "mpm")?;
    Ok(m.unwrap_or("sph").to_string())
}

fn material(root: &Tab<'_>) -> Result<MpmMaterial> {
    let e = "a table [material] with bulk_modulus, shear_modulus, density, yield_stress (and tangent_modulus)";
    let t = root.required("material", e, root.table("material", "material", e)?)?;
    t.check_keys(&["bulk_modulus", "shear_modulus", "density", "yield_stress", "tangent_modulus"], &[], "")?;
    let p = "a positive value in Pa";
    let bulk_modulus = t.required("bulk_modulus", p, t.number("bulk_modulus", p, positive)?)?;
    let shear_modulus = t.required("shear_modulus", p, t.number("shear_modulus", p, positive)?)?;
    let d = "a positive density in kg/m^3";
    let density = t.required("density", d, t.number("density", d, positive)?)?;
    let yield_stress = t.required("yield_stress", p, t.number("yield_stress", p, positive)?)?;
    let e_young = super::super::mpm::young_modulus(bulk_modulus, shear_modulus);
    let te = format!("a tangent modulus in Pa, >= 0 and below Young's modulus {e_young:.4e}");
    let tangent_modulus = t.number("tangent_modulus", &te, |x| (0.0..e_young).contains(&x))?.unwrap_or(0.0);
    Ok(MpmMaterial { bulk_modulus, shear_modulus, density, yield_stress, tangent_modulus })
}

fn cohesive(root: &Tab<'_>) -> Result<CohesiveSpec> {
    let e = "a table [cohesive] with toughness and peak (and law, toughness_shear, peak_shear)";
    let t = root.required("cohesive", e, root.table("cohesive", "cohesive", e)?)?;
    t.check_keys(&LAW_KEYS, &[], "")?;
    cohesive_law(&t)
}

/// The keys of the cohesive law (MPM's `[cohesive]`; the SPH path's adds its geometry).
pub(super) const LAW_KEYS: [&str; 5] = ["law", "toughness", "peak", "toughness_shear", "peak_shear"];

/// The traction law of each mode from a `[cohesive]` table (its keys already checked).
pub(super) fn cohesive_law(t: &Tab<'_>) -> Result<CohesiveSpec> {
    let g = "a positive toughness in J/m^2";
    let s = "a positive peak traction in Pa";
    let toughness = t.required("toughness", g, t.number("toughness", g, positive)?)?;
    let peak = t.required("peak", s, t.number("peak", s, positive)?)?;
    let toughness_shear = t.number("toughness_shear", g, positive)?.unwrap_or(toughness);
    let peak_shear = t.number("peak_shear", s, positive)?.unwrap_or(peak);
    let e = "\"cubic\" or \"triangular\"";
    let law = t.named("law", e, LawShape::from_name)?.unwrap_or(LawShape::Cubic);
    Ok(CohesiveSpec { law, toughness, peak, toughness_shear, peak_shear })
}

fn setup(root: &Tab<'_>) -> Result<Setup> {
    let ec = "a table [cut] (Nairn's cutting set-up)";
    let eb = "a table [bond] (a bonded block pulled apart)";
    match (root.table("cut", "cut", ec)?, root.table("bond", "bond", eb)?) {
        (Some(t), None) => cut(&t).map(Setup::Cut),
        (None, Some(t)) => bond(&t).map(Setup::Bond),
        (Some(_), Some(_)) => Err(root.invalid("bond", root.get("bond"), "no [bond] beside [cut]: one set-up a scene")),
        (None, None) => Err(root.invalid("cut", None, "a table [cut] or [bond]")),
    }
}

fn cut(t: &Tab<'_>) -> Result<CutSetup> {
    t.check_keys(
        &[
            "depth",
            "particles_across",
            "width",
            "crack",
            "starter",
            "base",
            "rake",
            "clearance",
            "speed",
            "ramp",
            "friction",
            "cut_length",
            "tool_height",
            "room",
        ],
        &[],
        "",
    )?;
    let h = "a positive depth of cut in m";
    let depth = t.required("depth", h, t.number("depth", h, positive)?)?;
    let n = t
        .integer("particles_across", "an odd particle count >= 3 (the cut plane then lies mid-cell)", |n| {
            n >= 3 && n % 2 == 1 && n <= 1001
        })?
        .unwrap_or(15) as u32;
    let l =
        |k: &str, d: f64| t.number(k, "a positive length in units of the depth h", positive).map(|x| x.unwrap_or(d));
    let (width, crack, starter, base) = (l("width", 30.0)?, l("crack", 18.0)?, l("starter", 2.0)?, l("base", 3.0)?);
    if crack >= width {
        return Err(t.invalid("crack", t.get("crack"), format!("a crack shorter than the width {width} h")));
    }
    if starter >= crack {
        return Err(t.invalid("starter", t.get("starter"), format!("a starter shorter than the crack {crack} h")));
    }
    let rake = t.number("rake", "a rake angle in degrees in [0, 60]", |x| (0.0..=60.0).contains(&x))?.unwrap_or(30.0);
    let clearance =
        t.number("clearance", "a clearance angle in degrees in (0, 30]", |x| x > 0.0 && x <= 30.0)?.unwrap_or(5.0);
    let speed = t.number("speed", "a positive speed in m/s", positive)?.unwrap_or(2.0);
    let ramp = t.number("ramp", "a fraction of the run in [0, 1)", |x| (0.0..1.0).contains(&x))?.unwrap_or(0.3);
    let friction = t.number("friction", "a friction coefficient >= 0", |x| x >= 0.0)?.unwrap_or(0.0);
    let cut_length = l("cut_length", 12.0)?;
    if cut_length + 1.0 > width {
        return Err(t.invalid(
            "cut_length",
            t.get("cut_length"),
            format!("a cut length below width - 1 = {} h", width - 1.0),
        ));
    }
    Ok(CutSetup {
        depth,
        particles_across: n,
        width,
        crack,
        starter,
        base,
        rake,
        clearance,
        speed,
        ramp,
        friction,
        cut_length,
        tool_height: l("tool_height", 6.0)?,
        room: l("room", 10.0)?,
    })
}

fn bond(t: &Tab<'_>) -> Result<BondSetup> {
    t.check_keys(&["width", "height", "cell", "pull", "ramp"], &[], "")?;
    let e = "a positive length in m";
    let width = t.required("width", e, t.number("width", e, positive)?)?;
    let height = t.required("height", e, t.number("height", e, positive)?)?;
    let ec = "a positive cell size in m, at most a quarter of the width and of the height";
    let cell = t.required("cell", ec, t.number("cell", ec, |c| c > 0.0 && 4.0 * c <= width && 4.0 * c <= height)?)?;
    let ep = "the grip's velocity [vx, vy] in m/s, not zero";
    let pull = t.required("pull", ep, t.vector("pull", 2, ep)?)?;
    if pull[0] == 0.0 && pull[1] == 0.0 {
        return Err(t.invalid("pull", t.get("pull"), ep));
    }
    let ramp = t.number("ramp", "a fraction of the run in [0, 1)", |x| (0.0..1.0).contains(&x))?.unwrap_or(0.1);
    Ok(BondSetup { width, height, cell, pull: [pull[0], pull[1]], ramp })
}

fn time(root: &Tab<'_>, setup: &Setup) -> Result<MpmTime> {
    let e = "a table [time] (end, cfl, samples, frames)";
    let t = root.table("time", "time", e)?;
    let end_of_cut = match setup {
        Setup::Cut(c) => Some(c.cut_length * c.depth / (c.speed * (1.0 - 0.5 * c.ramp))),
        Setup::Bond(_) => None,
    };
    let Some(t) = t else {
        let end = root.required("time", "a table [time] with end (a [bond] run's length)", end_of_cut)?;
        return Ok(MpmTime { end, ..TIME });
    };
    t.check_keys(&["end", "cfl", "samples", "frames"], &[], "")?;
    let es = "a positive time in seconds";
    let end = t.required("end", es, t.number("end", es, positive)?.or(end_of_cut))?;
    let cfl = t.number("cfl", "a CFL number in (0, 1]", |x| x > 0.0 && x <= 1.0)?.unwrap_or(TIME.cfl);
    let samples = t.integer("samples", "a sample count in [1, 1000000]", |n| (1..=1_000_000).contains(&n))?;
    let frames = t.integer("frames", "a frame count in [0, 10000]", |n| (0..=10_000).contains(&n))?;
    Ok(MpmTime {
        end,
        cfl,
        samples: samples.map_or(TIME.samples, |n| n as u32),
        frames: frames.map_or(TIME.frames, |n| n as u32),
    })
}

fn damping(root: &Tab<'_>) -> Result<Damping> {
    let e = "a table [damping] with pic, feedback and position_update";
    let Some(t) = root.table("damping", "damping", e)? else {
        return Ok(DAMPING);
    };
    t.check_keys(&["pic", "feedback", "position_update"], &[], "")?;
    let pic =
        t.number("pic", "a PIC fraction 1 - beta in [0, 1]", |x| (0.0..=1.0).contains(&x))?.unwrap_or(DAMPING.pic);
    let feedback = t
        .number("feedback", "a start-up feedback gain in [0, 1e6] (0: off)", |x| (0.0..=1e6).contains(&x))?
        .unwrap_or(DAMPING.feedback);
    let e = "\"second\", \"first\" or \"zeroth\"";
    let position_update = t.named("position_update", e, PositionUpdate::from_name)?.unwrap_or(DAMPING.position_update);
    Ok(Damping { pic, feedback, position_update })
}
