//! The embedded PTX must load on a driver: no unresolved `.extern` symbol (a panic path or an un-inlined call
//! into another crate leaves one, ../shared/GPU.md "Rules for kernel code") but the device runtime's
//! `cudaGraphSetConditional`, which the driver resolves (and the backend strips where it cannot), and every entry
//! point the CUDA backend loads must be present, for every embedded target.

use swarf::backend::cuda::{kernel_names, strip_graph_conditional};

#[test]
fn ptx_is_embedded_for_every_target() {
    assert!(
        !swarf::ptx::PTX.is_empty(),
        "no PTX embedded: {}",
        swarf::ptx::PTX_MISSING.unwrap_or("(no reason recorded)")
    );
    let targets = swarf::ptx::targets();
    assert!(targets.contains(&"sm_80"), "the portable sm_80 target must be embedded, got {targets:?}");
    // --fast-math: the same kernels with the f32 LLVM flags (build.rs FAST_FLAGS): approximate f32 division and
    // FMA contraction, which the default build never emits (IEEE div.rn, no contraction: ../shared/GPU.md).
    let get = |t: &str| swarf::ptx::PTX.iter().find(|(n, _)| *n == t).map(|(_, p)| *p).expect(t);
    let (plain, fast) = (get("sm_80"), get("sm_80-fast"));
    for op in ["div.approx.f32", "div.full.f32", "fma.rn.f64", "fma.rn.f32"] {
        assert!(!plain.contains(op), "the default PTX has {op}");
    }
    assert!(fast.contains("fma.rn.f64") && fast.contains("fma.rn.f32"), "the fast PTX has no contracted FMA");
    assert!(fast.contains("div.approx.f32") || fast.contains("div.full.f32"), "the fast PTX divides exactly");
}

#[test]
fn ptx_has_no_extern_and_every_entry() {
    for (target, ptx) in swarf::ptx::PTX {
        let sm = target.trim_end_matches("-fast");
        assert!(ptx.contains(&format!(".target {sm}")), "{target}: wrong .target line");
        // The one extern: the device runtime's cudaGraphSetConditional, which the driver resolves (the predictor
        // sets the IF node of a captured rebuild); stripped, the PTX has none and keeps every entry point.
        let externs: Vec<&str> = ptx.lines().filter(|l| l.contains(".extern")).collect();
        assert!(
            externs.iter().all(|l| l.contains(".extern .func cudaGraphSetConditional")) && externs.len() == 1,
            "{target}: PTX has unresolved symbols other than cudaGraphSetConditional: {externs:?}"
        );
        let stripped = strip_graph_conditional(ptx);
        assert!(
            !stripped.contains(".extern") && !stripped.contains("cudaGraphSetConditional"),
            "{target}: the stripped PTX still calls the device runtime"
        );
        assert!(ptx.matches("call.uni").count() > stripped.matches("call.uni").count(), "{target}: no call removed");
        let count = |p: &str| p.matches(".visible .entry ").count();
        assert_eq!(count(&stripped), count(ptx), "{target}: stripping lost entry points");
        assert_eq!(stripped.matches('{').count(), stripped.matches('}').count(), "{target}: unbalanced braces");
        let entries: Vec<&str> = ptx
            .lines()
            .filter_map(|l| l.trim().strip_prefix(".visible .entry "))
            .map(|l| l.trim_end_matches('(').trim())
            .collect();
        let names = kernel_names();
        assert!(names.len() > 70, "the kernel table lists every entry point");
        for name in names {
            assert!(entries.contains(name), "{target}: entry point {name} missing (have {entries:?})");
        }
        // No entry may reach a trap: a Rust panic path (a bounds check, an unwrap) or code LLVM proved undefined
        // (it once turned a shuffle over struct padding into a trap). The brief: no panics in kernels.
        for body in ptx.split(".visible .entry ").skip(1) {
            let name = body.split('(').next().unwrap_or("?").trim();
            let end = body.find("\n}\n").unwrap_or(body.len());
            assert!(!body[..end].contains("trap;"), "{target}: entry point {name} can trap (a panic path or UB)");
        }
    }
}

/// `SWARF_MAXNREG` (host/backend/cuda.rs `cap_registers`): a `.maxnreg` directive right after the parameter list
/// of every neighbour-walking entry point, and on no other entry.
#[test]
fn register_cap_marks_exactly_the_neighbour_kernels() {
    use swarf::backend::cuda::cap_registers;
    for (target, ptx) in swarf::ptx::PTX {
        let capped = cap_registers(ptx, &["swarf_sph_rates_", "swarf_heat_"], 72);
        let mut marked = 0;
        for body in capped.split(".visible .entry ").skip(1) {
            let name = body.split('(').next().unwrap_or("?").trim();
            let want = name.starts_with("swarf_sph_rates_") || name.starts_with("swarf_heat_");
            let params_end = body.find("\n)\n").map(|e| e + 3).expect("parameter list");
            let has = body[params_end..].starts_with(".maxnreg 72\n");
            assert_eq!(has, want, "{target}: {name}: .maxnreg {}", if has { "present" } else { "missing" });
            marked += has as usize;
        }
        assert!(marked >= 40, "{target}: only {marked} entries capped");
        assert_eq!(capped.matches(".maxnreg").count(), marked, "{target}: a directive outside an entry's head");
    }
}

/// The caps the CUDA backend loads by default (host/backend/cuda.rs `register_caps`): `.maxnreg 128` on the 2D
/// neighbour kernels (the interaction, fused or not, and the conduction passes) and on the plastic corrector, 80 on
/// the 2D Johnson–Cook corrector, one cap per entry, none on the 3D neighbour kernels or any other entry;
/// `SWARF_MAXNREG=0` and `SWARF_PLASTIC_MAXNREG=0` remove them.
#[test]
fn default_register_caps_mark_the_2d_neighbour_kernels_and_the_plastic_corrector() {
    use swarf::backend::cuda::register_caps;
    for (target, ptx) in swarf::ptx::PTX {
        let capped = register_caps(ptx, None, None);
        let (mut neighbour_2d, mut plastic) = (0, 0);
        for body in capped.split(".visible .entry ").skip(1) {
            let name = body.split('(').next().unwrap_or("?").trim();
            let is_2d_neighbour =
                (name.starts_with("swarf_sph_rates_") || name.starts_with("swarf_heat_")) && name.contains("_2d_");
            let is_plastic = name.starts_with("swarf_step_finish_") || name.starts_with("swarf_plastic_");
            let is_jc_2d = name.starts_with("swarf_step_finish_jc_2d_") || name.starts_with("swarf_plastic_jc_2d_");
            let params_end = body.find("\n)\n").map(|e| e + 3).expect("parameter list");
            let want = if is_jc_2d { ".maxnreg 80\n" } else { ".maxnreg 128\n" };
            let has = body[params_end..].starts_with(want);
            assert_eq!(has, is_2d_neighbour || is_plastic, "{target}: {name}: {want:?} {has}");
            assert_eq!(body.matches(".maxnreg").count(), has as usize, "{target}: {name}: one cap at most");
            neighbour_2d += (has && is_2d_neighbour) as usize;
            plastic += (has && is_plastic) as usize;
        }
        // 2 precisions × (8 plain + 8 fused stabiliser variants) × (plain, with damage, with CSPM) + Brookshaw and
        // PSE conduction in 2 precisions + the cohesive path's 8 variants, plain (`_cut`) and with CSPM
        // (`_cspm_cut`), in 2 precisions.
        assert_eq!(neighbour_2d, 132, "{target}: 2D neighbour entries capped");
        assert!(plastic >= 4, "{target}: only {plastic} plastic entries capped");
        assert_eq!(register_caps(ptx, Some(0), Some(0)), *ptx, "{target}: caps 0 must leave the PTX as built");
    }
}

/// The PTX's view of each entry's parameter list: (size, alignment) of every `.param`, in order.
fn entry_params(ptx: &str) -> Vec<(String, Vec<(usize, usize)>)> {
    let mut out = Vec::new();
    for body in ptx.split(".visible .entry ").skip(1) {
        let name = body.split('(').next().unwrap_or("?").trim().to_string();
        let head = &body[..body.find("\n)").expect("parameter list")];
        let params = head
            .lines()
            .filter_map(|l| l.trim().strip_prefix(".param "))
            .map(|p| {
                if let Some(rest) = p.strip_prefix(".align ") {
                    // `.align N .b8 name[size]`: a struct by value.
                    let align: usize = rest.split_whitespace().next().and_then(|a| a.parse().ok()).expect("align");
                    let size = p.split('[').nth(1).and_then(|s| s.split(']').next()).and_then(|s| s.parse().ok());
                    (size.expect("size"), align)
                } else {
                    let bytes =
                        if p.starts_with(".u64") || p.starts_with(".b64") || p.starts_with(".f64") { 8 } else { 4 };
                    (bytes, bytes)
                }
            })
            .collect();
        out.push((name, params));
    }
    out
}

/// Every entry that takes a pass's argument struct (`kernels::pass`) declares one parameter of exactly the host's
/// `size_of` and `align_of` of that struct for its dimension and precision: the launch copies the host struct's
/// bytes, so any difference would shift every field after it.
#[test]
fn argument_structs_match_the_entries_parameter_blocks() {
    use swarf::kernels::material::*;
    use swarf::kernels::pass::{
        BondArgs, BondIndexArgs, BondOpenArgs, ContactArgs, CorrectionArgs, DensityArgs, FinishArgs, FinishPlasticArgs,
        GatherArgs, GatherFieldsArgs, HashArgs, HashCountArgs, HeatArgs, NeighbourListArgs, PlasticArgs, PredictArgs,
        PrepareArgs, RatesArgs, ScanApplyArgs, ScanReduceArgs, ScatterArgs, SortArgs, VerletArgs, ZeroArgs,
    };
    use swarf::kernels::{Dim2, Dim3};
    fn block<T>() -> Vec<(usize, usize)> {
        vec![(size_of::<T>(), align_of::<T>())]
    }
    /// The host's block of a generic struct `$s<R, D, ...>` for the variant `$v`.
    macro_rules! by_variant {
        ($v:expr, $s:ident $(, $m:ty)?) => {
            match $v {
                "2d_f32" => block::<$s<f32, Dim2 $(, $m)?>>(),
                "2d_f64" => block::<$s<f64, Dim2 $(, $m)?>>(),
                "3d_f32" => block::<$s<f32, Dim3 $(, $m)?>>(),
                _ => block::<$s<f64, Dim3 $(, $m)?>>(),
            }
        };
    }
    /// The plastic corrector's and the plastic pass's blocks of the model tagged `tag` (the kernels' one model
    /// list).
    macro_rules! by_model {
        ($(($t:ident, $tag:ident)),* $(,)?) => {
            fn finish_plastic(tag: &str, variant: &str) -> Option<Vec<(usize, usize)>> {
                $(if tag == stringify!($tag) {
                    return Some(by_variant!(variant, FinishPlasticArgs, $t));
                })*
                None
            }
            fn plastic(tag: &str, variant: &str) -> Option<Vec<(usize, usize)>> {
                $(if tag == stringify!($tag) {
                    return Some(by_variant!(variant, PlasticArgs, $t));
                })*
                None
            }
        };
    }
    swarf::kernels::for_each_flow_model!(by_model);
    let want = |name: &str| -> Option<Vec<(usize, usize)>> {
        // The entries without a dimension × precision variant.
        match name {
            "swarf_zero_gated" => return Some(block::<ZeroArgs>()),
            "swarf_scatter" => return Some(block::<ScatterArgs>()),
            "swarf_sort_cells" => return Some(block::<SortArgs>()),
            "swarf_gather_b4" | "swarf_gather_b8" | "swarf_gather_b16" => return Some(block::<GatherArgs<u32>>()),
            "swarf_gather_fields" => return Some(block::<GatherFieldsArgs>()),
            "swarf_scan_reduce" => return Some(block::<ScanReduceArgs>()),
            "swarf_scan_apply" => return Some(block::<ScanApplyArgs>()),
            _ => {}
        }
        let variant = ["2d_f32", "2d_f64", "3d_f32", "3d_f64"].into_iter().find(|v| name.contains(v))?;
        // The MPM passes (2D only), generic in the precision alone.
        use swarf::kernels::pass::mpm::{CrackArgs, FeedbackArgs, G2pArgs, KeArgs, NodesArgs, P2gArgs};
        macro_rules! by_real {
            ($s:ident) => {
                if variant == "2d_f32" { block::<$s<f32>>() } else { block::<$s<f64>>() }
            };
        }
        if let Some(pass) = name.strip_prefix("swarf_mpm_") {
            return match pass.trim_end_matches(&format!("_{variant}")) {
                "p2g" => Some(by_real!(P2gArgs)),
                "crack" => Some(by_real!(CrackArgs)),
                "nodes" => Some(by_real!(NodesArgs)),
                "ke" => Some(by_real!(KeArgs)),
                "feedback" => Some(by_real!(FeedbackArgs)),
                "g2p" => Some(by_real!(G2pArgs)),
                _ => None,
            };
        }
        if name == format!("swarf_hash_{variant}") {
            Some(by_variant!(variant, HashArgs))
        } else if name == format!("swarf_hash_count_{variant}") {
            Some(by_variant!(variant, HashCountArgs))
        } else if name == format!("swarf_neighbour_list_{variant}") {
            Some(by_variant!(variant, NeighbourListArgs))
        } else if name == format!("swarf_verlet_build_{variant}") {
            Some(by_variant!(variant, VerletArgs))
        } else if name == format!("swarf_sph_bond_{variant}") {
            Some(by_variant!(variant, BondArgs))
        } else if name == format!("swarf_sph_bond_index_{variant}") {
            Some(by_variant!(variant, BondIndexArgs))
        } else if name == format!("swarf_sph_bond_open_{variant}") {
            Some(by_variant!(variant, BondOpenArgs))
        } else if name.starts_with("swarf_sph_rates_") {
            Some(by_variant!(variant, RatesArgs))
        } else if name.starts_with("swarf_sph_prepare_") {
            Some(by_variant!(variant, PrepareArgs))
        } else if name.starts_with("swarf_heat_") {
            Some(by_variant!(variant, HeatArgs))
        } else if name == format!("swarf_density_{variant}") {
            Some(by_variant!(variant, DensityArgs))
        } else if name == format!("swarf_sph_correction_{variant}") {
            Some(by_variant!(variant, CorrectionArgs))
        } else if name == format!("swarf_step_predict_{variant}") || name == format!("swarf_step_predict_{variant}_dmg")
        {
            Some(by_variant!(variant, PredictArgs))
        } else if name == format!("swarf_contact_{variant}") {
            Some(by_variant!(variant, ContactArgs, *const swarf::kernels::contact::Tool2d))
        } else if name == format!("swarf_contact_mesh_{variant}") {
            Some(by_variant!(variant, ContactArgs, *const swarf::kernels::contact::MeshTool<'static>))
        } else if let Some(tag) = name.strip_prefix("swarf_plastic_") {
            plastic(tag.trim_end_matches("_dmg").trim_end_matches(&format!("_{variant}")), variant)
        } else if name == format!("swarf_step_finish_{variant}") {
            Some(by_variant!(variant, FinishArgs))
        } else if let Some(tag) = name.strip_prefix("swarf_step_finish_") {
            finish_plastic(tag.trim_end_matches("_dmg").trim_end_matches(&format!("_{variant}")), variant)
        } else {
            None
        }
    };
    for (target, ptx) in swarf::ptx::PTX {
        // Every entry the backend loads (the material tests' return-map entries keep positional parameters).
        let loaded = kernel_names();
        let mut checked = 0;
        for (name, params) in entry_params(ptx).into_iter().filter(|(name, _)| loaded.contains(&name.as_str())) {
            let w = want(&name).unwrap_or_else(|| panic!("{target}: {name}: no argument struct"));
            assert_eq!(params, w, "{target}: {name}: (size, align) of the parameters against the host's");
            checked += 1;
        }
        assert_eq!(checked, loaded.len(), "{target}: every loaded entry checked");
        // 4 variants × (8 stabiliser combinations × plain and fused × without damage, with damage and with the
        // CSPM correction + the 8 across a cohesive path, plain and with CSPM, + its bonds, id map and opening + the elastic corrector + one plastic corrector and one plastic pass per flow-stress model
        // without and with damage + density, 4 pre-passes and the predictor each without and with damage, 2
        // conductions + hash, hash-count, neighbour list, Verlet list, the correction) + the contact with the parametric tool in 2D and 3D and with a mesh tool in 3D,
        // each in 2 precisions + 9
        // neighbour entries without variants (zero, scatter, sort, 3 gathers, gather_fields, 2 scans) + the 6 MPM
        // passes in 2 precisions.
        let models = swarf::kernels::pass::FLOW_MODEL_TAGS.len();
        assert_eq!(checked, 4 * (48 + 16 + 3 + 1 + 4 * models + 13 + 5) + 6 + 9 + 12, "{target}: entries checked");
    }
}

/// Lazy loading (host/backend/cuda/split.rs): the module of each entry the backend loads is the header, the
/// shared items it reaches and that entry alone; every shared item an entry names is in that entry's module,
/// and every shared item but the panic handler (reached by none) is in some module. The register caps and the
/// stripped `cudaGraphSetConditional` survive the split.
#[test]
fn per_entry_modules_keep_every_entry_and_shared_item() {
    use swarf::backend::cuda::register_caps;
    use swarf::backend::cuda::split::SplitPtx;
    for (target, ptx) in swarf::ptx::PTX {
        let capped = register_caps(ptx, None, None);
        let split = SplitPtx::parse(&capped).expect("the PTX splits");
        let items: Vec<_> = split.items(&capped).collect();
        let entries: Vec<&str> = items.iter().filter(|i| i.entry).map(|i| i.name).collect();
        assert_eq!(entries.len(), capped.matches(".visible .entry ").count(), "{target}: entries found");
        let mut reached_any = vec![false; items.len()];
        for name in &entries {
            let reached = split.reached(&capped, name).expect("entry");
            for &k in &reached {
                reached_any[k] = true;
            }
            let module = split.module(&capped, name).expect("module");
            let sm = target.trim_end_matches("-fast");
            assert!(module.contains(".version") && module.contains(&format!(".target {sm}\n")), "{target}: header");
            assert_eq!(module.matches(".visible .entry ").count(), 1, "{target}: {name}: one entry per module");
            assert!(module.contains(&format!(".visible .entry {name}(")), "{target}: {name} missing from its module");
            assert_eq!(module.matches('{').count(), module.matches('}').count(), "{target}: {name}: braces");
            let entry = items.iter().find(|i| i.entry && i.name == *name).expect("entry");
            for (k, it) in items.iter().enumerate() {
                if !it.entry && entry.text.contains(it.name) {
                    assert!(reached.contains(&k), "{target}: {name} names {} but its module lacks it", it.name);
                }
            }
            if name.starts_with("swarf_sph_rates_2d_") {
                assert!(module.contains(".maxnreg 128\n"), "{target}: {name}: register cap lost");
            }
            if name.starts_with("swarf_step_predict_") {
                assert!(module.contains(".extern .func cudaGraphSetConditional"), "{target}: {name}");
                let stripped = strip_graph_conditional(&module);
                assert!(!stripped.contains("cudaGraphSetConditional"), "{target}: {name}: not stripped");
            }
        }
        for name in kernel_names() {
            assert!(entries.contains(name), "{target}: {name} has no module");
        }
        for (k, it) in items.iter().enumerate() {
            if !it.entry && !it.name.contains("rust_begin_unwind") {
                assert!(reached_any[k], "{target}: shared item {} is in no module", it.name);
            }
        }
    }
}

/// Every pass's marker type (`kernels::pass::Pass`) names the table entry of its own kind and variant: for each
/// entry of the table with a pass, `ENTRY` is the entry's position, and the pass's argument struct is the one the
/// entry takes (the same size and alignment as checked against the PTX above). The launch on both backends
/// goes through `ENTRY`, so a wrong key would run another variant on the GPU than its twin on the CPU.
#[test]
fn every_pass_names_its_own_entry() {
    use swarf::kernels::pass::*;
    use swarf::kernels::{Dim2, Dim3};
    let mut position = 0usize;
    let mut passes = 0usize;
    macro_rules! check {
        ($p:ty, $name:expr) => {{
            assert_eq!(
                <$p as Pass>::ENTRY,
                position,
                "{}: the pass names entry {}",
                $name,
                ENTRY_NAMES[<$p as Pass>::ENTRY]
            );
            passes += 1;
        }};
    }
    macro_rules! entry {
        (single, $name:expr, $slot:ident) => {
            position += 1;
        };
        (hash_count, $name:expr, $r:ident, $d:ident) => {
            position += 1;
        };
        (hash, $name:expr, $r:ident, $d:ident) => {
            check!(Hash<$r, $d>, $name);
            position += 1;
        };
        (neighbour_list, $name:expr, $r:ident, $d:ident) => {
            check!(NeighbourList<$r, $d>, $name);
            position += 1;
        };
        (verlet_build, $name:expr, $r:ident, $d:ident) => {
            check!(Verlet<$r, $d>, $name);
            position += 1;
        };
        (density, $name:expr, $r:ident, $d:ident) => {
            check!(Density<$r, $d>, $name);
            position += 1;
        };
        (correction, $name:expr, $r:ident, $d:ident) => {
            check!(CorrectionPass<$r, $d>, $name);
            position += 1;
        };
        (predict, $name:expr, $r:ident, $d:ident, $dmg:literal) => {
            check!(Predict<$r, $d, $dmg>, $name);
            position += 1;
        };
        (finish, $name:expr, $r:ident, $d:ident) => {
            check!(Finish<$r, $d>, $name);
            position += 1;
        };
        (contact, $name:expr, $r:ident, $d:ident, $tool:ident) => {
            check!(Contact<$r, $d, swarf::kernels::contact_tool!($tool)>, $name);
            position += 1;
        };
        (heat, $name:expr, $r:ident, $d:ident, $pse:literal) => {
            check!(Heat<$r, $d, $pse>, $name);
            position += 1;
        };
        (prepare, $name:expr, $r:ident, $d:ident, $av:literal, $as:literal, $dmg:literal) => {
            check!(Prepare<$r, $d, $av, $as, $dmg>, $name);
            position += 1;
        };
        (rates, $name:expr, $r:ident, $d:ident, $av:literal, $as:literal, $xs:literal, $heat:literal, $dmg:literal,
            $cs:literal, $cut:literal) => {
            check!(RatesPass<$r, $d, $av, $as, $xs, $heat, $dmg, $cs, $cut>, $name);
            position += 1;
        };
        (plastic, $name:expr, $r:ident, $d:ident, $t:ident, $tag:ident, $dmg:literal) => {
            check!(Plastic<$r, $d, swarf::kernels::material::$t, $dmg>, $name);
            position += 1;
        };
        (finish_plastic, $name:expr, $r:ident, $d:ident, $t:ident, $tag:ident, $dmg:literal) => {
            check!(FinishPlastic<$r, $d, swarf::kernels::material::$t, $dmg>, $name);
            position += 1;
        };
        (bond, $name:expr, $r:ident, $d:ident) => {
            check!(Bond<$r, $d>, $name);
            position += 1;
        };
        (bond_index, $name:expr, $r:ident, $d:ident) => {
            check!(BondIndex<$r, $d>, $name);
            position += 1;
        };
        (bond_open, $name:expr, $r:ident, $d:ident) => {
            check!(BondOpen<$r, $d>, $name);
            position += 1;
        };
        (mpm_p2g, $name:expr, $r:ident, $d:ident) => {
            check!(mpm::P2g<$r>, $name);
            position += 1;
        };
        (mpm_crack, $name:expr, $r:ident, $d:ident) => {
            check!(mpm::CrackPass<$r>, $name);
            position += 1;
        };
        (mpm_nodes, $name:expr, $r:ident, $d:ident) => {
            check!(mpm::NodesPass<$r>, $name);
            position += 1;
        };
        (mpm_ke, $name:expr, $r:ident, $d:ident) => {
            check!(mpm::KePass<$r>, $name);
            position += 1;
        };
        (mpm_feedback, $name:expr, $r:ident, $d:ident) => {
            check!(mpm::FeedbackPass<$r>, $name);
            position += 1;
        };
        (mpm_g2p, $name:expr, $r:ident, $d:ident) => {
            check!(mpm::G2p<$r>, $name);
            position += 1;
        };
    }
    swarf::kernels::for_each_entry!(entry);
    assert_eq!(position, ENTRY_COUNT);
    // Every entry but the 9 without variants and the 4 fused hash-counts of the backend's own counting sort.
    assert_eq!(passes, ENTRY_COUNT - 9 - 4);
}

// The PTX split per entry (host/backend/cuda/split.rs), on a hand-written module.
use swarf::backend::cuda::split::SplitPtx;

const SPLIT_PTX: &str = ".version 7.0\n.target sm_80\n.address_size 64\n\n\t// .globl\tk1\n\
    .extern .func ext\n(\n\t.param .b64 ext_param_0\n)\n;\n\
    .global .align 8 .b8 anon_$_0[16] = {0};\n\n\
    .func helper(\n\t.param .b64 helper_param_0\n)\n{\n\tld.global.f64 %fd1, [anon_$_0];\n}\n\t// .globl\tk1\n\
    .visible .entry k1(\n\t.param .u32 k1_param_0\n)\n{\n\tcall.uni helper, (x);\n\tret;\n}\n\t// .globl\tk2\n\
    .visible .entry k2(\n\t.param .u32 k2_param_0\n)\n{\n\tcall.uni ext, (x);\n\tret;\n}\n";

/// Each entry's module has the header, the items it reaches through its calls (the data a called function
/// reads included) and no other entry.
#[test]
fn a_module_holds_its_entry_and_what_it_reaches() {
    let s = SplitPtx::parse(SPLIT_PTX).expect("split");
    let names: Vec<&str> = s.items(SPLIT_PTX).map(|i| i.name).collect();
    assert_eq!(names, ["ext", "anon_$_0", "helper", "k1", "k2"]);
    let k1 = s.module(SPLIT_PTX, "k1").expect("k1");
    assert!(k1.starts_with(".version 7.0\n.target sm_80\n.address_size 64\n"));
    assert!(k1.contains(".func helper(") && k1.contains("anon_$_0[16]") && !k1.contains(".extern"));
    assert!(k1.find("anon_$_0[16]") < k1.find(".func helper(") && !k1.contains("k2"));
    let k2 = s.module(SPLIT_PTX, "k2").expect("k2");
    assert!(k2.contains(".extern .func ext") && !k2.contains("helper") && !k2.contains("anon_$_0"));
    assert!(s.module(SPLIT_PTX, "k3").is_none());
}
