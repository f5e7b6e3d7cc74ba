//! SPH entry points.

use super::{global_index, ordered_index};

macro_rules! density_entry {
    ($sym:expr, $r:ty, $d:ty) => {
        /// rho[i] = Σ_j m_j W(|x_i − x_j|) (pass::DensityArgs).
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: DensityArgs<$r, $d>) {
            let i = global_index();
            if unsafe { args.n.live(i) } {
                unsafe { args.particle(i as usize) };
            }
        }
    };
}

use super::intrinsics::{graph_set_conditional, shfl_xor};
use crate::pass::{
    BondArgs, BondIndexArgs, BondOpenArgs, ContactArgs, CorrectionArgs, DensityArgs, FinishArgs, FinishPlasticArgs,
    HeatArgs, PlasticArgs, PredictArgs, PrepareArgs, RatesArgs,
};
use crate::sph::correction::{CorrectionSum, correction_finish, correction_share};
use crate::sph::heat::{heat_finish, heat_sum};
use crate::sph::interact::{HeatPairSums, PairSums, finish_rates, pair_sums, pair_sums_heat};
use crate::sph::lanes::{LaneSum, clamp_lanes};
use crate::sph::step::is_finite_vec;
use crate::vector::{Dim, Dim2, Dim3};

type Vec_<R, D> = <D as Dim>::Vec<R>;

/// Pre-pass: sig = σ/ρ², art = artificial stress (AS), sound = √(K/ρ) (AV), vol = m/ρ (`mass` the full masses).
/// Gated on a step's rebuild flag (null: always) where the predictor runs the pre-pass: it then runs again only
/// after a rebuild's reorder.
/// One thread per sorted particle below `args.n` running `args.particle(i)` (the bonds, their index).
macro_rules! item_entry {
    ($sym:expr, $args:ty) => {
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: $args) {
            let i = global_index();
            if i < args.n {
                unsafe { args.particle(i as usize) };
            }
        }
    };
}

macro_rules! prepare_entry {
    ($sym:expr, $r:ty, $d:ty, $av:literal, $as:literal, $dmg:literal) => {
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: PrepareArgs<$r, $d>) {
            let i = global_index() as usize;
            if unsafe { args.n.live(i as u32) && super::neighbour::open(args.gate) } {
                unsafe { args.particle::<$av, $as, $dmg>(i) };
            }
        }
    };
}

/// The pair interaction: rates of every sorted particle, `$lanes` threads per particle, each summing its share of
/// the neighbours (sph::interact::pair_sums); the shares are combined by a shuffle butterfly in the order of
/// sph::lanes::combine and the particle's first lane writes the rates (sph::interact::finish_rates). With `$heat`
/// the same walk also sums the Brookshaw conduction (sph::interact::pair_sums_heat) and writes Ṫ to `temp_t`
/// (`heat_vol`, `temp`, `materials`, `hp` are its inputs; the plain entries ignore them).
macro_rules! rates_entry {
    ($sym:expr, $r:ty, $d:ty, $av:literal, $as:literal, $xs:literal, $heat:literal, $dmg:literal, $cs:literal,
        $cut:literal) => {
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: RatesArgs<$r, $d>) {
            let RatesArgs { n, lanes, reverse, params, hp, .. } = args;
            let t = ordered_index(reverse);
            let lanes = clamp_lanes(lanes);
            let (i, lane) = (t / lanes, t % lanes);
            let a = args.arrays;
            let h = args.heat_arrays();
            let nb = unsafe { args.neighbours() };
            // Every lane takes part in the shuffles, also past the last particle.
            let live = unsafe { n.live(i) };
            unsafe {
                let (mech, heat) = if $heat {
                    let s = if live {
                        pair_sums_heat::<$r, $d, $av, $as, $xs, $dmg, $cs>(&params, &hp, &nb, &a, &h, i, lane, lanes)
                    } else {
                        HeatPairSums::default()
                    };
                    let s = butterfly(s, lanes);
                    (s.mech, s.heat)
                } else {
                    let s = if live {
                        pair_sums::<$r, $d, $av, $as, $xs, $dmg, $cs, $cut>(&params, &nb, &a, i, lane, lanes)
                    } else {
                        PairSums::default()
                    };
                    (butterfly(s, lanes), 0.0)
                };
                if live && lane == 0 {
                    let o = finish_rates::<$r, $d, $xs, $dmg>(&params, &a, i, &mech);
                    args.store(i as usize, &o);
                    if $heat {
                        *args.temp_t.add(i as usize) = heat_finish(&hp, &h, i, heat);
                    }
                }
            }
        }
    };
}

/// The kernel-gradient correction: B_i⁻¹ of every sorted particle (sph::correction), `lanes` threads per particle
/// summing their shares, combined by the butterfly as in the pair interaction; the first lane inverts and stores.
macro_rules! correction_entry {
    ($sym:expr, $r:ty, $d:ty) => {
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: CorrectionArgs<$r, $d>) {
            let t = ordered_index(args.reverse);
            let lanes = clamp_lanes(args.lanes);
            let (i, lane) = (t / lanes, t % lanes);
            let nb = unsafe { args.neighbours() };
            // Every lane takes part in the shuffles, also past the last particle.
            let live = unsafe { args.n.live(i) };
            let s = if live {
                unsafe {
                    correction_share::<$r, $d>(
                        &args.kernel,
                        args.min_r2,
                        args.path_only != 0,
                        &nb,
                        &args.arrays,
                        i,
                        lane,
                        lanes,
                    )
                }
            } else {
                CorrectionSum::default()
            };
            let s = butterfly(s, lanes);
            if live && lane == 0 {
                unsafe {
                    *args.out.add(i as usize) = correction_finish::<$r, $d>(&s, args.min_det, args.path_only != 0)
                };
            }
        }
    };
}

/// Every lane's `x` combined by the shuffle butterfly (sph::lanes::combine's order; every lane gets the result).
#[inline(always)]
fn butterfly<T: LaneSum>(mut x: T, lanes: u32) -> T {
    let mut s = 1;
    while s < lanes {
        x = x.add(&shuffle_xor(&x, s));
        s <<= 1;
    }
    x
}

/// The value of lane (lane ^ mask), word by word (`LaneSum::map_words`: never the padding).
#[inline(always)]
fn shuffle_xor<T: LaneSum>(x: &T, mask: u32) -> T {
    x.map_words(&mut |w| shfl_xor(w, mask))
}

/// The predictor (sph::step::predict_particle) with the skin test of the predicted position against where the
/// cell list binned it (`GridParams::beyond_skin`) and the blanking's box (`PredictArgs::rebuilds`): a particle beyond
/// the skin or outside the box sets the step's rebuild flag (every
/// such thread stores the same 1). With a non-null `sig` the same thread then runs the pre-pass of the predicted
/// particle (sph::interact::prepare_particle; `params` by value, `art`/`sound` null where off), so that a step that
/// does not rebuild needs no pre-pass launch. In a captured step `condition` is the handle of the IF node that
/// holds the step's rebuild (0 otherwise; created with default 0 at each graph launch): the predictor sets it to 1
/// where it sets the rebuild flag, so that no launch of its own has to read the flag for the node.
macro_rules! predict_entry {
    ($sym:expr, $r:ty, $d:ty, $dmg:literal) => {
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: PredictArgs<$r, $d>) {
            let i = global_index();
            let (scalars, condition) = (args.scalars, args.condition);
            let flag = unsafe { core::ptr::addr_of_mut!((*scalars).rebuild) };
            // A rebuild the host asked for (thread 0 also when blanking left no particle active; a thread that set
            // the flag before this read set the node too).
            if i == 0 && condition != 0 && unsafe { core::ptr::read_volatile(flag) } != 0 {
                unsafe { graph_set_conditional(condition, 1) };
            }
            if unsafe { args.n.live(i) } {
                unsafe {
                    let x = args.particle::<$dmg>(i as usize);
                    if args.rebuilds(i as usize, &x) {
                        core::ptr::write_volatile(flag, 1);
                        if condition != 0 {
                            graph_set_conditional(condition, 1);
                        }
                        if !is_finite_vec::<$r, Vec_<$r, $d>>(&x) {
                            core::ptr::write_volatile(core::ptr::addr_of_mut!((*scalars).non_finite), 1);
                        }
                    }
                }
            }
        }
    };
}

/// The fused corrector (sph::step::correct_particle) of an elastic run.
macro_rules! finish_entry {
    ($sym:expr, $r:ty, $d:ty) => {
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: FinishArgs<$r, $d>) {
            let i = global_index();
            if unsafe { args.n.live(i) } {
                unsafe { args.particle(i as usize) };
            }
        }
    };
}

/// The fused corrector and plastic update (sph::plastic::plastic_particle) of the same particle, one entry per
/// flow-stress model (pass::FinishPlasticArgs). The model's parameters come by value: in the constant bank,
/// operands of the return map's instructions, not loads and registers held across its Newton iterations. With a
/// non-null `contact` the same thread then runs the tool's contact pass for the particle
/// (contact::penalty::contact_particle: it reads only the particle's own corrected state, its temperature and
/// yield stress after the plastic update), so that the step needs no launch of its own for it.
macro_rules! finish_plastic_entry {
    ($sym:expr, $m:ty, $r:ty, $d:ty, $dmg:literal) => {
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: FinishPlasticArgs<$r, $d, $m>) {
            let i = ordered_index(args.reverse);
            if unsafe { args.n.live(i) } {
                // The model alone goes to the flow-stress functions (a local copy, as the by-value parameter was).
                let model = args.model;
                unsafe { args.particle::<$dmg>(&model, i as usize) };
            }
        }
    };
}

/// Conduction: temp_t[i] = Ṫ_i (sph::heat::heat_rate), Brookshaw or PSE (PSE with a null `list`).
macro_rules! heat_entry {
    ($sym:expr, $r:ty, $d:ty, $pse:literal) => {
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: HeatArgs<$r, $d>) {
            let t = global_index();
            let lanes = clamp_lanes(args.lanes);
            let (i, lane) = (t / lanes, t % lanes);
            let a = args.arrays();
            let nb = unsafe { args.neighbours() };
            // Every lane takes part in the shuffles, also past the last particle.
            let live = unsafe { args.n.live(i) };
            unsafe {
                let mut sum = if live {
                    heat_sum::<$r, Vec_<$r, $d>, $pse>(&args.hp, &args.params.kernel, &nb, &a, i, lane, lanes)
                } else {
                    0.0
                };
                sum = butterfly(sum, lanes);
                if live && lane == 0 {
                    *args.temp_t.add(i as usize) = heat_finish(&args.hp, &a, i, sum);
                }
            }
        }
    };
}

/// The plastic update (radial return + heating) of every particle, one entry per flow-stress model (its parameters
/// by value, as in finish_plastic_entry).
macro_rules! plastic_entry {
    ($sym:expr, $m:ty, $r:ty, $d:ty, $dmg:literal) => {
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: PlasticArgs<$r, $d, $m>) {
            let i = global_index() as usize;
            if unsafe { args.n.live(i as u32) } {
                // The model alone goes to the flow-stress functions (a local copy, as the by-value parameter was).
                let model = args.model;
                unsafe { args.particle::<$dmg>(&model, i) };
            }
        }
    };
}

/// The contact pass with a rigid tool (contact::penalty::contact_particle; the tool's argument type from
/// `contact_tool!`).
macro_rules! contact_entry {
    ($sym:expr, $r:ty, $d:ty, $tool:ident) => {
        #[unsafe(export_name = $sym)]
        pub unsafe extern "ptx-kernel" fn entry(args: ContactArgs<$r, $d, crate::contact_tool!($tool)>) {
            let i = global_index() as usize;
            if unsafe { args.n.live(i as u32) } {
                unsafe { args.particle(i) };
            }
        }
    };
}

/// The SPH entries of the pass table (pass::table), each in its own anonymous scope: its exported name is the
/// table's.
macro_rules! sph_entry {
    (bond, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
    item_entry!($sym, BondArgs<$r, $d>);
        };
    };
    (bond_index, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
    item_entry!($sym, BondIndexArgs<$r, $d>);
        };
    };
    (bond_open, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
    item_entry!($sym, BondOpenArgs<$r, $d>);
        };
    };
    (correction, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
            correction_entry!($sym, $r, $d);
        };
    };
    (density, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
            density_entry!($sym, $r, $d);
        };
    };
    (predict, $sym:expr, $r:ident, $d:ident, $dmg:literal) => {
        const _: () = {
            predict_entry!($sym, $r, $d, $dmg);
        };
    };
    (finish, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
            finish_entry!($sym, $r, $d);
        };
    };
    (contact, $sym:expr, $r:ident, $d:ident, $tool:ident) => {
        const _: () = {
            contact_entry!($sym, $r, $d, $tool);
        };
    };
    (heat, $sym:expr, $r:ident, $d:ident, $pse:literal) => {
        const _: () = {
            heat_entry!($sym, $r, $d, $pse);
        };
    };
    (prepare, $sym:expr, $r:ident, $d:ident, $av:literal, $as:literal, $dmg:literal) => {
        const _: () = {
            prepare_entry!($sym, $r, $d, $av, $as, $dmg);
        };
    };
    (rates, $sym:expr, $r:ident, $d:ident, $av:literal, $as:literal, $xs:literal, $heat:literal, $dmg:literal,
        $cs:literal, $cut:literal) => {
        const _: () = {
            rates_entry!($sym, $r, $d, $av, $as, $xs, $heat, $dmg, $cs, $cut);
        };
    };
    (plastic, $sym:expr, $r:ident, $d:ident, $t:ident, $tag:ident, $dmg:literal) => {
        const _: () = {
            plastic_entry!($sym, crate::material::$t, $r, $d, $dmg);
        };
    };
    (finish_plastic, $sym:expr, $r:ident, $d:ident, $t:ident, $tag:ident, $dmg:literal) => {
        const _: () = {
            finish_plastic_entry!($sym, crate::material::$t, $r, $d, $dmg);
        };
    };
    ($kind:ident, $($rest:tt)*) => {};
}

crate::for_each_entry!(sph_entry);
