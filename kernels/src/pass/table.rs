//! The one table of passes and their variants. [`for_each_entry!`] names every PTX entry point the host loads,
//! once, with the pass it runs and its variant: dimension × precision, the stabiliser combination, the flow
//! model, the fused conduction. The PTX entries (`ptx::sph`, `ptx::neighbour`), the list of names the host loads
//! and the CUDA backend's kernel slots (`host/backend/cuda.rs`) all expand from it, so a pass or a variant is
//! added here and nowhere else is a name spelled.

/// Calls `$cb!(kind, "entry_name", R, D, variant parameters...)` for every entry point the host loads, in item or
/// statement position. The kinds and their variant parameters:
/// - `single` (no R, D: `$cb!(single, "name", slot)`, `slot` the host's name for it): the entries without
///   variants, written by hand in `ptx`;
/// - `contact` (R, D, the tool: `prism`, the parametric tool, in 2D and 3D; `mesh`, a triangle mesh, in 3D);
///   `density`, `finish`, `hash`, `hash_count`, `neighbour_list`, `verlet_build` (R, D);
/// - `mpm_p2g`, `mpm_crack`, `mpm_nodes`, `mpm_ke`, `mpm_feedback`, `mpm_g2p` (R, Dim2): the MPM step's passes
///   (`mpm::step`);
/// - `correction` (R, D): the kernel-gradient correction B⁻¹ (`sph::correction`);
/// - `heat` (R, D, PSE); `predict` (R, D, DMG); `prepare` (R, D, AV, AS, DMG); `rates` (R, D, AV, AS, XSPH, fused
///   conduction, DMG, CSPM, CUT). DMG: the damage's degradation and interaction mask (docs/damage.md), entries of their
///   own (`_dmg` ending the name, so that prefixes such as the register caps' see them as their plain twins) so
///   that a run without damage runs the code it ran before; CSPM (`_cspm`): the corrected kernel gradient, without
///   damage (the scene refuses both at once); CUT (`_cut`): no continuum pair across the cohesive path (docs/mpm.md
///   "The cohesive path in SPH"), without conduction or damage, with or without CSPM (`_cspm_cut`);
/// - `bond`, `bond_index`, `bond_open` (R, D): the cohesive path's bonds, the map from a particle's id to its sorted
///   index, and the columns' opening under `coupling = "continuum"` (`sph::bond`);
/// - `plastic`, `finish_plastic` (R, D, flow model type, its tag, DMG): one per model of [`for_each_flow_model!`],
///   without and with the damage's update after the return.
///
/// `for_each_entry!(@models [tokens])` expands `tokens (Type, tag), ...` with the model list.
#[macro_export]
macro_rules! for_each_entry {
    ($cb:ident) => {
        $cb!(single, "swarf_zero_gated", zero_gated);
        $cb!(single, "swarf_scan_reduce", scan_reduce);
        $cb!(single, "swarf_scan_apply", scan_apply);
        $cb!(single, "swarf_scatter", scatter);
        $cb!(single, "swarf_sort_cells", sort_cells);
        $cb!(single, "swarf_gather_b4", gather_b4);
        $cb!(single, "swarf_gather_b8", gather_b8);
        $cb!(single, "swarf_gather_b16", gather_b16);
        $cb!(single, "swarf_gather_fields", gather_fields);
        $cb!(contact, "swarf_contact_2d_f32", f32, Dim2, prism);
        $cb!(contact, "swarf_contact_2d_f64", f64, Dim2, prism);
        $cb!(contact, "swarf_contact_3d_f32", f32, Dim3, prism);
        $cb!(contact, "swarf_contact_3d_f64", f64, Dim3, prism);
        $cb!(contact, "swarf_contact_mesh_3d_f32", f32, Dim3, mesh);
        $cb!(contact, "swarf_contact_mesh_3d_f64", f64, Dim3, mesh);
        $crate::for_each_entry!(@mpm $cb, f32, "f32");
        $crate::for_each_entry!(@mpm $cb, f64, "f64");
        $crate::for_each_entry!(@variant $cb, f32, Dim2, "2d_f32");
        $crate::for_each_entry!(@variant $cb, f64, Dim2, "2d_f64");
        $crate::for_each_entry!(@variant $cb, f32, Dim3, "3d_f32");
        $crate::for_each_entry!(@variant $cb, f64, Dim3, "3d_f64");
    };
    (@variant $cb:ident, $r:ident, $d:ident, $v:literal) => {
        $cb!(hash, concat!("swarf_hash_", $v), $r, $d);
        $cb!(hash_count, concat!("swarf_hash_count_", $v), $r, $d);
        $cb!(neighbour_list, concat!("swarf_neighbour_list_", $v), $r, $d);
        $cb!(verlet_build, concat!("swarf_verlet_build_", $v), $r, $d);
        $cb!(density, concat!("swarf_density_", $v), $r, $d);
        $cb!(correction, concat!("swarf_sph_correction_", $v), $r, $d);
        $cb!(predict, concat!("swarf_step_predict_", $v), $r, $d, false);
        $cb!(predict, concat!("swarf_step_predict_", $v, "_dmg"), $r, $d, true);
        $cb!(finish, concat!("swarf_step_finish_", $v), $r, $d);
        $cb!(heat, concat!("swarf_heat_brookshaw_", $v), $r, $d, false);
        $cb!(heat, concat!("swarf_heat_pse_", $v), $r, $d, true);
        $cb!(bond, concat!("swarf_sph_bond_", $v), $r, $d);
        $cb!(bond_index, concat!("swarf_sph_bond_index_", $v), $r, $d);
        $cb!(bond_open, concat!("swarf_sph_bond_open_", $v), $r, $d);
        $crate::for_each_entry!(@prepare $cb, $r, $d, $v, (v0s0, false, false), (v0s1, false, true),
            (v1s0, true, false), (v1s1, true, true));
        $crate::for_each_entry!(@rates $cb, $r, $d, $v, (v0s0x0, false, false, false), (v0s0x1, false, false, true),
            (v0s1x0, false, true, false), (v0s1x1, false, true, true), (v1s0x0, true, false, false),
            (v1s0x1, true, false, true), (v1s1x0, true, true, false), (v1s1x1, true, true, true));
        $crate::for_each_entry!(@models [@model_entries $cb, $r, $d, $v;]);
    };
    // The MPM passes (2D only; `mpm::step`).
    (@mpm $cb:ident, $r:ident, $v:literal) => {
        $cb!(mpm_p2g, concat!("swarf_mpm_p2g_2d_", $v), $r, Dim2);
        $cb!(mpm_crack, concat!("swarf_mpm_crack_2d_", $v), $r, Dim2);
        $cb!(mpm_nodes, concat!("swarf_mpm_nodes_2d_", $v), $r, Dim2);
        $cb!(mpm_ke, concat!("swarf_mpm_ke_2d_", $v), $r, Dim2);
        $cb!(mpm_feedback, concat!("swarf_mpm_feedback_2d_", $v), $r, Dim2);
        $cb!(mpm_g2p, concat!("swarf_mpm_g2p_2d_", $v), $r, Dim2);
    };
    (@prepare $cb:ident, $r:ident, $d:ident, $v:literal, $(($s:ident, $av:literal, $as:literal)),*) => {
        $(
            $cb!(prepare, concat!("swarf_sph_prepare_", $v, "_", stringify!($s)), $r, $d, $av, $as, false);
            $cb!(prepare, concat!("swarf_sph_prepare_", $v, "_", stringify!($s), "_dmg"), $r, $d, $av, $as, true);
        )*
    };
    (@rates $cb:ident, $r:ident, $d:ident, $v:literal, $(($s:ident, $av:literal, $as:literal, $xs:literal)),*) => {
        $(
            $cb!(rates, concat!("swarf_sph_rates_", $v, "_", stringify!($s)), $r, $d, $av, $as, $xs, false, false,
                false, false);
            $cb!(rates, concat!("swarf_sph_rates_heat_", $v, "_", stringify!($s)), $r, $d, $av, $as, $xs, true, false,
                false, false);
            $cb!(rates, concat!("swarf_sph_rates_", $v, "_", stringify!($s), "_dmg"), $r, $d, $av, $as, $xs, false, true,
                false, false);
            $cb!(rates, concat!("swarf_sph_rates_heat_", $v, "_", stringify!($s), "_dmg"), $r, $d, $av, $as, $xs, true,
                true, false, false);
            $cb!(rates, concat!("swarf_sph_rates_", $v, "_", stringify!($s), "_cspm"), $r, $d, $av, $as, $xs, false,
                false, true, false);
            $cb!(rates, concat!("swarf_sph_rates_heat_", $v, "_", stringify!($s), "_cspm"), $r, $d, $av, $as, $xs, true,
                false, true, false);
            $cb!(rates, concat!("swarf_sph_rates_", $v, "_", stringify!($s), "_cut"), $r, $d, $av, $as, $xs, false,
                false, false, true);
            $cb!(rates, concat!("swarf_sph_rates_", $v, "_", stringify!($s), "_cspm_cut"), $r, $d, $av, $as, $xs,
                false, false, true, true);
        )*
    };
    (@model_entries $cb:ident, $r:ident, $d:ident, $v:literal; $(($t:ident, $tag:ident)),* $(,)?) => {
        $(
            $cb!(plastic, concat!("swarf_plastic_", stringify!($tag), "_", $v), $r, $d, $t, $tag, false);
            $cb!(finish_plastic, concat!("swarf_step_finish_", stringify!($tag), "_", $v), $r, $d, $t, $tag, false);
            $cb!(plastic, concat!("swarf_plastic_", stringify!($tag), "_", $v, "_dmg"), $r, $d, $t, $tag, true);
            $cb!(finish_plastic, concat!("swarf_step_finish_", stringify!($tag), "_", $v, "_dmg"), $r, $d, $t, $tag,
                true);
        )*
    };
    // The flow-stress models the kernels are built for: the kernel type (in `crate::material`) and the tag of
    // its entry names. Adding a model to the kernels means adding its line here (and its arm to the host's
    // `with_model!`, host/backend/cpu.rs, which maps `FlowModel` to the kernel type).
    (@models [$($pre:tt)*]) => {
        $crate::for_each_entry! {
            $($pre)*
            (JohnsonCook, jc),
            (Calamaz2008, calamaz_2008),
            (Calamaz2010, calamaz_2010),
            (Calamaz2011, calamaz_2011),
            (SimaOzel1, sima_ozel_1),
            (SimaOzel2, sima_ozel_2),
            (SimaOzel3, sima_ozel_3),
            (Scgl, scgl),
            (Bilinear, bilinear),
        }
    };
    (@call $callback:ident $($list:tt)*) => {
        $callback! { $($list)* }
    };
}

/// The argument type of a contact entry's tool (`for_each_entry!`'s `contact` kind): `prism` the parametric tool,
/// `mesh` a triangle mesh ([`crate::contact::ToolArg`]).
#[macro_export]
macro_rules! contact_tool {
    (prism) => {
        *const $crate::contact::Tool2d
    };
    (mesh) => {
        *const $crate::contact::MeshTool<'static>
    };
}

/// How many entry points the table names.
pub const ENTRY_COUNT: usize = {
    let mut i = 0;
    macro_rules! count {
        ($kind:ident, $name:expr $(, $rest:tt)*) => {
            i += 1;
        };
    }
    for_each_entry!(count);
    i
};

/// Every entry point the host loads, in table order (the PTX test checks that each is present).
pub const ENTRY_NAMES: [&str; ENTRY_COUNT] = {
    let mut v: [&str; ENTRY_COUNT] = [""; ENTRY_COUNT];
    let mut i = 0;
    macro_rules! push {
        ($kind:ident, $name:expr $(, $rest:tt)*) => {
            v[i] = $name;
            i += 1;
        };
    }
    for_each_entry!(push);
    let _ = i;
    v
};

/// An entry's place in the table as a pass names it: the kind, the dimension and the real type's size (0 for the
/// entries without variants) and the variant's number (the stabiliser bits, the flow model's index).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct EntryKey {
    pub kind: &'static str,
    pub dim: u32,
    pub real: u32,
    pub variant: u32,
}

/// The variant number of a prepare entry (AV, AS, DMG).
pub const fn prepare_variant(av: bool, r#as: bool, dmg: bool) -> u32 {
    4 * dmg as u32 + 2 * av as u32 + r#as as u32
}

/// The variant number of a rates entry (AV, AS, XSPH, fused conduction, DMG, CSPM, CUT).
pub const fn rates_variant(av: bool, r#as: bool, xs: bool, heat: bool, dmg: bool, cspm: bool, cut: bool) -> u32 {
    64 * cut as u32 + 32 * cspm as u32 + 16 * dmg as u32 + 8 * heat as u32 + 4 * av as u32 + 2 * r#as as u32 + xs as u32
}

/// The variant number of a plastic or plastic-corrector entry (the flow model's index, DMG).
pub const fn model_variant(index: usize, dmg: bool) -> u32 {
    index as u32 + 256 * dmg as u32
}

/// Every entry's key, in table order (with [`ENTRY_NAMES`]).
// A const, not a static: `entry_index`, a const fn, reads it at compile time (a run never copies it).
#[allow(clippy::large_const_arrays)]
pub const ENTRY_KEYS: [EntryKey; ENTRY_COUNT] = {
    use crate::pass::ModelEntry;
    use crate::vector::{Dim, Dim2, Dim3};
    let mut v = [EntryKey { kind: "", dim: 0, real: 0, variant: 0 }; ENTRY_COUNT];
    let mut i = 0;
    macro_rules! key {
        (@at $kind:ident, $r:ident, $d:ident, $variant:expr) => {
            v[i] = EntryKey {
                kind: stringify!($kind),
                dim: <$d as Dim>::D as u32,
                real: size_of::<$r>() as u32,
                variant: $variant,
            };
            i += 1;
        };
        (single, $name:expr, $slot:ident) => {
            v[i] = EntryKey { kind: stringify!($slot), dim: 0, real: 0, variant: 0 };
            i += 1;
        };
        (heat, $name:expr, $r:ident, $d:ident, $pse:literal) => {
            key!(@at heat, $r, $d, $pse as u32);
        };
        (contact, $name:expr, $r:ident, $d:ident, $tool:ident) => {
            key!(@at contact, $r, $d, <$crate::contact_tool!($tool) as crate::contact::ToolArg>::VARIANT);
        };
        (predict, $name:expr, $r:ident, $d:ident, $dmg:literal) => {
            key!(@at predict, $r, $d, $dmg as u32);
        };
        (prepare, $name:expr, $r:ident, $d:ident, $av:literal, $as:literal, $dmg:literal) => {
            key!(@at prepare, $r, $d, prepare_variant($av, $as, $dmg));
        };
        (rates, $name:expr, $r:ident, $d:ident, $av:literal, $as:literal, $xs:literal, $heat:literal, $dmg:literal,
            $cs:literal, $cut:literal) => {
            key!(@at rates, $r, $d, rates_variant($av, $as, $xs, $heat, $dmg, $cs, $cut));
        };
        ($kind:ident, $name:expr, $r:ident, $d:ident, $t:ident, $tag:ident, $dmg:literal) => {
            key!(@at $kind, $r, $d, model_variant(<crate::material::$t as ModelEntry>::INDEX, $dmg));
        };
        ($kind:ident, $name:expr, $r:ident, $d:ident) => {
            key!(@at $kind, $r, $d, 0);
        };
    }
    for_each_entry!(key);
    let _ = (i, Dim3::D, Dim2::D);
    v
};

const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The position in the table of the entry of `kind` for dimension `dim`, a real type of `real` bytes and
/// variant `variant`; a pass's [`crate::pass::launch::Pass::ENTRY`], evaluated at compile time, so a key the
/// table does not list stops the build.
pub const fn entry_index(kind: &str, dim: usize, real: usize, variant: u32) -> usize {
    let mut i = 0;
    while i < ENTRY_COUNT {
        let k = &ENTRY_KEYS[i];
        if same(k.kind, kind) && k.dim as usize == dim && k.real as usize == real && k.variant == variant {
            return i;
        }
        i += 1;
    }
    panic!("the pass table (kernels/src/pass/table.rs) has no entry of this kind and variant")
}

/// The position in the table of an entry without variants (`single`), by its slot name.
pub const fn single_index(slot: &str) -> usize {
    entry_index(slot, 0, 0, 0)
}
