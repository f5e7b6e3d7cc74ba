//! Inverse identification (klippel-constitutive.md §6): the optimisers Klippel compared (Differential Evolution,
//! Nelder–Mead, Gaussian-process Bayesian optimisation; §6.1), behind one batch ask/tell interface so that an
//! ensemble of simulations can evaluate a whole batch of candidates at once, and the analytic flow-curve benchmark
//! he tested them on (§6.3); and `swarf identify` ([`campaign`]): an identification file ([`file`]) of experiments
//! (measured or from Klippel's database, [`data`]), parameters and an optimiser, run batch by batch against
//! Klippel's objective ([`objective`]).

pub mod bayes;
pub mod campaign;
pub mod data;
pub mod de;
pub mod extends;
pub mod file;
pub mod flow_curve;
pub mod gp;
pub mod history;
pub mod holdout;
pub mod material_key;
pub mod nelder_mead;
pub mod objective;
pub mod optimizer;
pub mod report;
pub mod scenes;

pub use bayes::{Bayes, BayesSettings, Noise};
pub use campaign::{Identification, IdentifyOptions, identify};
pub use de::{DeSettings, DifferentialEvolution, Strategy};
pub use nelder_mead::{NelderMead, NelderMeadSettings};
pub use optimizer::{Bounds, Evaluation, Optimizer, minimise};
