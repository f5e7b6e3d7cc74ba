//! The PTX that `build.rs` embedded, by target, or the reason there is none.

include!(concat!(env!("OUT_DIR"), "/ptx_embed.rs"));

/// The embedded targets, e.g. `["sm_80", "sm_90"]`.
pub fn targets() -> Vec<&'static str> {
    PTX.iter().map(|(t, _)| *t).collect()
}

/// The PTX for the newest embedded target the device can run (`sm_XY` with XY ≤ its compute capability), or the
/// one named by `SWARF_PTX_TARGET`.
pub fn select(cc_major: i32, cc_minor: i32) -> Option<(&'static str, &'static str)> {
    if let Ok(forced) = std::env::var("SWARF_PTX_TARGET") {
        return PTX.iter().find(|(t, _)| *t == forced).copied();
    }
    let cc = (cc_major * 10 + cc_minor) as u32;
    PTX.iter()
        .filter(|(t, _)| t.trim_start_matches("sm_").parse::<u32>().is_ok_and(|v| v <= cc))
        .max_by_key(|(t, _)| t.trim_start_matches("sm_").parse::<u32>().unwrap_or(0))
        .copied()
}
