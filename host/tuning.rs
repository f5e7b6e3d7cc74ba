//! The tuning and checking switches (README, "Tuning and checking switches"): environment variables read once,
//! into one [`Tuning`], which the solver and the CUDA backend take their settings from, `swarf info` prints and
//! `summary.json` records (`tuning`). None changes a result bit except `SWARF_LANES` (the order of the pair sums,
//! the same on every backend) and `SWARF_FAST_MATH` (the `-fast` PTX).
//!
//! A value that is not one of the expected ones is an error naming the variable and what it accepts, not a
//! silent default.

use std::sync::OnceLock;

/// The order in which a kernel's blocks start (`ptx::ordered_index`; no bit changes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    Forward,
    Reverse,
}

/// Every `SWARF_*` tuning switch; `None` where the variable is unset and the built-in default applies (the
/// defaults live with what they tune: `solver::default_lanes`, the CUDA backend's block sizes, orders and
/// register caps).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tuning {
    /// `SWARF_LANES=1|2|4|8`: threads per particle in the neighbour passes.
    pub lanes: Option<u32>,
    /// `SWARF_NO_GRAPHS=1`: no CUDA graphs.
    pub no_graphs: bool,
    /// `SWARF_NO_FUSE=1`: the conduction in a pass of its own.
    pub no_fuse: bool,
    /// `SWARF_NO_FUSE_PREPARE=1`: the pre-pass in a pass of its own.
    pub no_fuse_prepare: bool,
    /// `SWARF_NO_FUSE_CONTACT=1`: the contact in a pass of its own.
    pub no_fuse_contact: bool,
    /// `SWARF_NO_CONDITIONAL=1`: a captured step's rebuild as gated launches instead of a conditional node.
    pub no_conditional: bool,
    /// `SWARF_MAXNREG=N`: register cap of every neighbour kernel (0: none).
    pub maxnreg: Option<u32>,
    /// `SWARF_PLASTIC_MAXNREG=N`: the plastic corrector's register cap (0: none).
    pub plastic_maxnreg: Option<u32>,
    /// `SWARF_PAIR_BLOCK=N`: threads per block of the neighbour passes (a multiple of 32 from 32 to 1024).
    pub pair_block: Option<u32>,
    /// `SWARF_PLASTIC_BLOCK=N`: threads per block of the plastic corrector.
    pub plastic_block: Option<u32>,
    /// `SWARF_PAIR_ORDER=forward|reverse`: the pair interaction's block order.
    pub pair_order: Option<Order>,
    /// `SWARF_PLASTIC_ORDER=forward|reverse`: the plastic corrector's block order.
    pub plastic_order: Option<Order>,
    /// `SWARF_PTX_TARGET=sm_XY`: load this embedded PTX target instead of the newest the device runs.
    pub ptx_target: Option<String>,
    /// `SWARF_FAST_MATH=1` (or `swarf --fast-math`): the `-fast` PTX.
    pub fast_math: bool,
}

/// A switch set to a value it does not accept.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{var} = {value:?}: expected {expected}")]
pub struct TuningError {
    pub var: &'static str,
    pub value: String,
    pub expected: &'static str,
}

const FLAG: &str = "1 (on) or 0 (off)";
const LANES: &str = "1, 2, 4 or 8";
const REGS: &str = "a register count (0: no cap)";
const BLOCK: &str = "a block size, a multiple of 32 from 32 to 1024";
const ORDER: &str = "\"forward\" or \"reverse\"";

impl Tuning {
    /// The switches of this process's environment.
    pub fn from_env() -> Result<Tuning, TuningError> {
        Tuning::from_vars(|k| std::env::var(k).ok())
    }

    /// The switches as `get` gives the variables (None: unset).
    pub fn from_vars(get: impl Fn(&str) -> Option<String>) -> Result<Tuning, TuningError> {
        let read = |var: &'static str, expected: &'static str, ok: &dyn Fn(&str) -> bool| match get(var) {
            None => Ok(None),
            Some(v) if ok(v.trim()) => Ok(Some(v.trim().to_string())),
            Some(v) => Err(TuningError { var, value: v, expected }),
        };
        let flag = |var| Ok::<_, TuningError>(read(var, FLAG, &|v| v == "0" || v == "1")?.is_some_and(|v| v == "1"));
        let number = |var, expected, ok: &dyn Fn(u32) -> bool| {
            Ok::<_, TuningError>(read(var, expected, &|v| v.parse::<u32>().is_ok_and(ok))?.and_then(|v| v.parse().ok()))
        };
        let block = |b: u32| (32..=1024).contains(&b) && b.is_multiple_of(32);
        let order = |var| {
            Ok::<_, TuningError>(
                read(var, ORDER, &|v| v == "forward" || v == "reverse")?
                    .map(|v| if v == "reverse" { Order::Reverse } else { Order::Forward }),
            )
        };
        Ok(Tuning {
            lanes: number("SWARF_LANES", LANES, &|l| matches!(l, 1 | 2 | 4 | 8))?,
            no_graphs: flag("SWARF_NO_GRAPHS")?,
            no_fuse: flag("SWARF_NO_FUSE")?,
            no_fuse_prepare: flag("SWARF_NO_FUSE_PREPARE")?,
            no_fuse_contact: flag("SWARF_NO_FUSE_CONTACT")?,
            no_conditional: flag("SWARF_NO_CONDITIONAL")?,
            maxnreg: number("SWARF_MAXNREG", REGS, &|_| true)?,
            plastic_maxnreg: number("SWARF_PLASTIC_MAXNREG", REGS, &|_| true)?,
            pair_block: number("SWARF_PAIR_BLOCK", BLOCK, &block)?,
            plastic_block: number("SWARF_PLASTIC_BLOCK", BLOCK, &block)?,
            pair_order: order("SWARF_PAIR_ORDER")?,
            plastic_order: order("SWARF_PLASTIC_ORDER")?,
            ptx_target: read("SWARF_PTX_TARGET", "an embedded target such as sm_80", &|v| !v.is_empty())?,
            fast_math: flag("SWARF_FAST_MATH")?,
        })
    }

    /// The process's switches, read from the environment on first use and kept (the backend, the solver and the
    /// reports all see the same values).
    pub fn current() -> Result<&'static Tuning, TuningError> {
        static CURRENT: OnceLock<Result<Tuning, TuningError>> = OnceLock::new();
        CURRENT.get_or_init(Tuning::from_env).as_ref().map_err(Clone::clone)
    }

    /// The switches as `summary.json` records them (`null`: unset, the default applies).
    pub fn json(&self) -> serde_json::Value {
        let order = |o: Option<Order>| o.map(|o| if o == Order::Reverse { "reverse" } else { "forward" });
        serde_json::json!({
            "lanes": self.lanes,
            "no_graphs": self.no_graphs,
            "no_fuse": self.no_fuse,
            "no_fuse_prepare": self.no_fuse_prepare,
            "no_fuse_contact": self.no_fuse_contact,
            "no_conditional": self.no_conditional,
            "maxnreg": self.maxnreg,
            "plastic_maxnreg": self.plastic_maxnreg,
            "pair_block": self.pair_block,
            "plastic_block": self.plastic_block,
            "pair_order": order(self.pair_order),
            "plastic_order": order(self.plastic_order),
            "ptx_target": self.ptx_target,
            "fast_math": self.fast_math,
        })
    }

    /// One line for `swarf info`: the switches that are set, or "defaults".
    pub fn line(&self) -> String {
        let set: Vec<String> = match self.json() {
            serde_json::Value::Object(m) => m
                .into_iter()
                .filter(|(_, v)| !v.is_null() && *v != serde_json::Value::Bool(false))
                .map(|(k, v)| format!("{k} = {v}"))
                .collect(),
            _ => Vec::new(),
        };
        if set.is_empty() { "defaults (no SWARF_* switch set)".to_string() } else { set.join(", ") }
    }
}
