//! The flow-stress models the kernels are built for, listed once. From this list come each model's index and
//! entry-name tag ([`ModelEntry`]) and [`FLOW_MODEL_TAGS`] (the PTX entries and the names the host loads come
//! from the pass table, pass::table, which holds the list); the host's `FlowModel` reaches a model's entries through its kernel type, so its
//! own order does not matter.

/// A flow-stress model's place in the pass table.
pub trait ModelEntry {
    /// Its position in [`for_each_flow_model!`] (the host's kernel tables are indexed by it).
    const INDEX: usize;
    /// Its part of the entry names: `swarf_plastic_<TAG>_2d_f64`, `swarf_step_finish_<TAG>_2d_f64`.
    const TAG: &'static str;
}

/// Calls `$callback! { (Type, tag), ... }` with every flow-stress model: the kernel type (in `crate::material`)
/// and the tag of its entry names. The list itself is the pass table's (`for_each_entry!(@models ..)`,
/// pass::table): adding a model to the kernels means adding its line there (and its arm to the host's
/// `with_model!`, host/backend/cpu.rs, which maps `FlowModel` to the kernel type).
#[macro_export]
macro_rules! for_each_flow_model {
    ($callback:ident) => {
        $crate::for_each_entry! { @models [@call $callback] }
    };
}

macro_rules! model_table {
    ($(($t:ident, $tag:ident)),* $(,)?) => {
        /// The models' positions, in the order of the list.
        #[allow(non_camel_case_types, clippy::enum_variant_names)]
        enum Position {
            $($tag),*
        }
        $(
            impl ModelEntry for crate::material::$t {
                const INDEX: usize = Position::$tag as usize;
                const TAG: &'static str = stringify!($tag);
            }
        )*
        /// Every model's tag, by [`ModelEntry::INDEX`].
        pub const FLOW_MODEL_TAGS: &[&str] = &[$(stringify!($tag)),*];
    };
}

for_each_flow_model!(model_table);
