//! `[cohesive]` of an SPH scene: the cohesive path's law (as an MPM scene's) and its geometry (docs/mpm.md, "The
//! cohesive path in SPH").

use super::mpm::{LAW_KEYS, cohesive_law};
use super::*;

/// `[cohesive]` (optional). The path's bonds and its pair exclusion have entries of their own without conduction
/// or damage (with or without CSPM), and its id map does not know the blanking's frozen particles: each is refused
/// beside it.
pub(super) fn path(root: &Tab<'_>, physics: &Physics, damage: bool, blanking: bool) -> Result<Option<CohesivePath>> {
    let e = "a table [cohesive] with toughness, peak, plane and extent (docs/mpm.md)";
    let Some(t) = root.table("cohesive", "cohesive", e)? else { return Ok(None) };
    let keys: Vec<&str> = LAW_KEYS.iter().copied().chain(["plane", "extent", "traction_free", "coupling"]).collect();
    t.check_keys(&keys, &[], "")?;
    let law = cohesive_law(&t)?;
    let pe = "the y of the cut plane in m, between two particle rows";
    let plane = t.required("plane", pe, t.number("plane", pe, f64::is_finite)?)?;
    let range = |k: &str, what: &str| -> Result<Option<[f64; 2]>> {
        let e = format!("[x_min, x_max] in m, x_min < x_max: {what}");
        match t.vector(k, 2, &e)? {
            Some([a, b, _]) if a < b => Ok(Some([a, b])),
            Some(_) => Err(t.invalid(k, t.get(k), e)),
            None => Ok(None),
        }
    };
    let extent_e = "the reference x over which the plane is cut";
    let extent = t.required("extent", extent_e, range("extent", extent_e)?)?;
    let traction_free = range("traction_free", "the starter crack, within the extent")?;
    if let Some([a, b]) = traction_free
        && (a < extent[0] || b > extent[1])
    {
        let e = format!("[x_min, x_max] within extent [{}, {}] m", extent[0], extent[1]);
        return Err(t.invalid("traction_free", t.get("traction_free"), e));
    }
    let ce = "\"bonds\" or \"continuum\"";
    let coupling = t.named("coupling", ce, Coupling::from_name)?.unwrap_or(Coupling::Bonds);
    if coupling == Coupling::Continuum && t.get("law").is_some() {
        let e = "no law with coupling = \"continuum\" (its bonds soften linearly from the onset; docs/mpm.md)";
        return Err(t.invalid("law", t.get("law"), e));
    }
    let refuse = |what: &str| Err(t.invalid("extent", t.get("extent"), format!("no cohesive path {what}")));
    if physics.conduction != Conduction::Off {
        return refuse("with heat conduction (physics.conduction = \"off\")");
    }
    if damage {
        return refuse("with [damage]");
    }
    if blanking {
        return refuse("with [blanking]");
    }
    Ok(Some(CohesivePath { law, plane, extent, traction_free, coupling }))
}
