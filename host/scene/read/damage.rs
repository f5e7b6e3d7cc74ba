//! `[damage]`: the model and its constants (the library material's `[damage]` unless given here), the reference
//! temperatures, G_f, the mask, deletion and the pre-cracks (docs/damage.md).

use super::*;

const DAMAGE_KEYS: &[&str] = &[
    "model",
    "mask",
    "mask_form",
    "delete",
    "fracture_energy",
    "fracture_toughness",
    "reference_strain_rate",
    "reference_temperature",
    "melt_temperature",
    "pre_crack",
    "enabled",
];
const D_KEYS: [&str; 8] = ["D1", "D2", "D3", "D4", "D5", "D6", "D7", "D8"];

/// The library material's damage constants.
type LibDamage = crate::material::DamageConstants;

/// `[damage]`; `None` for `enabled = false` (every key still checked, as the stabilisers').
pub(super) fn damage(t: &Tab<'_>, dim: usize, material: &Material, physics: &Physics) -> Result<Option<Damage>> {
    let keys: Vec<&str> = DAMAGE_KEYS.iter().chain(D_KEYS.iter()).copied().collect();
    t.check_keys(&keys, &[], "")?;
    let enabled = t.boolean("enabled", "true or false")?.unwrap_or(true);
    if enabled && !physics.plasticity {
        return Err(t.invalid(
            "model",
            t.get("model"),
            "no [damage] without plasticity (damage grows with the plastic strain: a material with [flow_stress])",
        ));
    }
    let lib = material.library.as_ref().and_then(|m| m.damage);
    let model = model_name(t, lib.as_ref())?;
    // The library's constants apply only to the library's own model.
    let lib_same = lib.filter(|l| l.model_name() == model);
    let constants = constants(t, &model, lib_same.as_ref())?;
    let (reference_strain_rate, reference_temperature, melt_temperature) =
        references(t, &model, material, physics, lib_same.as_ref())?;
    let fracture_energy = fracture_energy(t, material, lib.as_ref())?;
    let mask = t.boolean("mask", "true or false")?.unwrap_or(false);
    let mask_printed = t.string("mask_form", "\"printed\" or \"invariant\"", |s| s == "printed" || s == "invariant")?
        != Some("invariant");
    let delete = t.boolean("delete", "true or false")?.unwrap_or(false);
    let pre_cracks = pre_cracks(t, dim)?;
    Ok(enabled.then_some(Damage {
        model,
        constants,
        reference_strain_rate,
        reference_temperature,
        melt_temperature,
        fracture_energy,
        mask,
        mask_printed,
        delete,
        pre_cracks,
    }))
}

/// `model`, or the library material's when absent.
fn model_name(t: &Tab<'_>, lib: Option<&LibDamage>) -> Result<String> {
    use crate::material::DAMAGE_MODEL_NAMES;
    let names =
        format!("one of: {}", DAMAGE_MODEL_NAMES.iter().map(|n| format!("\"{n}\"")).collect::<Vec<_>>().join(", "));
    match t.string("model", &names, |s| DAMAGE_MODEL_NAMES.contains(&s))? {
        Some(m) => Ok(m.to_string()),
        None => match lib {
            Some(l) => Ok(l.model_name().to_string()),
            None => Err(t.invalid("model", None, format!("{names} (the material has no [damage] constants)"))),
        },
    }
}

/// D1..Dk of `model` (k = 5 for JC, 8 for JC-GG, 2 otherwise): given keys over the library's; a key beyond k is
/// refused.
fn constants(t: &Tab<'_>, model: &str, lib_same: Option<&LibDamage>) -> Result<[f64; 8]> {
    let count = match model {
        "jc" => 5,
        "jc_gg" => 8,
        _ => 2,
    };
    let mut constants = [0.0; 8];
    for (k, key) in D_KEYS.iter().enumerate() {
        let given = t.number(key, "a finite number", any)?;
        if k >= count {
            if given.is_some() {
                return Err(t.invalid(key, t.get(key), format!("no {key} for model \"{model}\" ({count} constants)")));
            }
            continue;
        }
        constants[k] = match (given, lib_same) {
            (Some(v), _) => v,
            (None, Some(l)) => l.d[k],
            (None, None) => {
                return Err(t.invalid(
                    key,
                    None,
                    format!("a number: model \"{model}\" needs D1..D{count} (the material gives none for it)"),
                ));
            }
        };
    }
    Ok(constants)
}

/// The reference strain rate, the reference temperature and the melt temperature: the key, else the library's
/// damage constants, else the material's thermal data, else a default (1/s; the initial temperature; none for the
/// melt temperature except for Rice–Tracey, which has no temperature term).
fn references(
    t: &Tab<'_>,
    model: &str,
    material: &Material,
    physics: &Physics,
    lib_same: Option<&LibDamage>,
) -> Result<(f64, f64, f64)> {
    let thermal = material.library.as_ref().and_then(|m| m.thermal);
    let rate = t.number("reference_strain_rate", "a strain rate in 1/s > 0", positive)?;
    let reference_strain_rate = rate.or(lib_same.map(|l| l.reference_strain_rate)).unwrap_or(1.0);
    let t_ref = t.number("reference_temperature", "a temperature in K >= 0", non_negative)?;
    let reference_temperature = t_ref
        .or(lib_same.map(|l| l.reference_temperature))
        .or(thermal.and_then(|th| th.reference_temperature))
        .unwrap_or(physics.initial_temperature);
    let melt_expected = format!("a temperature in K above the reference temperature {reference_temperature} K");
    let melt = t.number("melt_temperature", &melt_expected, |x| x > reference_temperature)?;
    let melt_temperature =
        match melt.or(lib_same.map(|l| l.melt_temperature)).or(thermal.and_then(|th| th.melt_temperature)) {
            Some(m) if m > reference_temperature => m,
            _ if model == "rice_tracey" => reference_temperature + 1.0,
            _ => return Err(t.invalid("melt_temperature", None, melt_expected)),
        };
    Ok((reference_strain_rate, reference_temperature, melt_temperature))
}

/// G_f: `fracture_energy`, or from `fracture_toughness` (plane strain, `damage::fracture_energy_from_toughness`),
/// not both; else the library's; else 0 (no regularisation).
fn fracture_energy(t: &Tab<'_>, material: &Material, lib: Option<&LibDamage>) -> Result<f64> {
    let gf = t.number("fracture_energy", "a fracture energy G_f in J/m^2 > 0", positive)?;
    let k1c = t.number("fracture_toughness", "a fracture toughness K_1C in Pa m^0.5 > 0", positive)?;
    Ok(match (gf, k1c) {
        (Some(_), Some(_)) => {
            return Err(t.invalid(
                "fracture_toughness",
                t.get("fracture_toughness"),
                "either fracture_energy or fracture_toughness, not both",
            ));
        }
        (Some(g), None) => g,
        (None, Some(k)) => {
            swarf_kernels::damage::fracture_energy_from_toughness(k, material.youngs_modulus, material.poisson_ratio)
        }
        (None, None) => lib.and_then(|l| l.fracture_energy).unwrap_or(0.0),
    })
}

/// `[[damage.pre_crack]]`: boxes min..max whose particles start with damage D (default full) and ω (default 1).
fn pre_cracks(t: &Tab<'_>, dim: usize) -> Result<Vec<PreCrack>> {
    let crack_tables = t.tables("pre_crack", "[[damage.pre_crack]] tables with min and max")?;
    let paths: Vec<String> = (0..crack_tables.len()).map(|i| format!("damage.pre_crack.{i}")).collect();
    let mut pre_cracks = Vec::new();
    for (i, &(node, entries)) in crack_tables.iter().enumerate() {
        let c = Tab { doc: t.doc, path: &paths[i], node, entries };
        c.check_keys(&["min", "max", "damage", "omega"], &[], "")?;
        let (min, max) = c.min_max(dim)?;
        let full = swarf_kernels::damage::FULL_DAMAGE;
        let d_expected = format!("a damage D in [0, {full}] (−ln 0.01: full damage)");
        let damage = c.number("damage", &d_expected, |x| (0.0..=full).contains(&x))?.unwrap_or(full);
        let omega = c.number("omega", "an initiation ω in [0, 1]", |x| (0.0..=1.0).contains(&x))?.unwrap_or(1.0);
        if damage > 0.0 && omega < 1.0 {
            return Err(c.invalid("omega", c.get("omega"), "1 where damage > 0 (evolution starts at initiation)"));
        }
        pre_cracks.push(PreCrack { min, max, damage, omega });
    }
    Ok(pre_cracks)
}
