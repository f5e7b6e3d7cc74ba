//! The PTX that `build.rs` embedded, by target, or the reason there is none.

include!(concat!(env!("OUT_DIR"), "/ptx_embed.rs"));

/// The embedded targets, e.g. `["sm_80", "sm_80-fast"]` (`-fast`: built with the f32 LLVM flags, `build.rs`).
pub fn targets() -> Vec<&'static str> {
    PTX.iter().map(|(t, _)| *t).collect()
}

/// The PTX for the newest embedded target the device can run (`sm_XY` with XY ≤ its compute capability), or the
/// one named by `SWARF_PTX_TARGET`; with `fast`, its `-fast` build (the f32 LLVM flags; `swarf --fast-math`).
pub fn select(cc_major: i32, cc_minor: i32, fast: bool) -> Option<(&'static str, &'static str)> {
    let suffix = if fast { "-fast" } else { "" };
    if let Some(forced) = crate::tuning::Tuning::current().ok().and_then(|t| t.ptx_target.as_deref()) {
        let want = format!("{}{suffix}", forced.trim_end_matches("-fast"));
        return PTX.iter().find(|(t, _)| *t == want).copied();
    }
    let cc = (cc_major * 10 + cc_minor) as u32;
    let base = PTX
        .iter()
        .filter(|(t, _)| t.trim_start_matches("sm_").parse::<u32>().is_ok_and(|v| v <= cc))
        .max_by_key(|(t, _)| t.trim_start_matches("sm_").parse::<u32>().unwrap_or(0))?
        .0;
    let want = format!("{base}{suffix}");
    PTX.iter().find(|(t, _)| *t == want).copied()
}

/// Whether this process loads the `-fast` PTX: `swarf --fast-math`, or `SWARF_FAST_MATH=1`.
pub fn fast_math() -> bool {
    crate::tuning::Tuning::current().is_ok_and(|t| t.fast_math)
}
