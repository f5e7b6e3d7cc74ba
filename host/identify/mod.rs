//! Inverse identification (klippel-constitutive.md §6): the optimisers Klippel compared (Differential Evolution,
//! Nelder–Mead, Gaussian-process Bayesian optimisation; §6.1), behind one batch ask/tell interface so that an
//! ensemble of simulations can evaluate a whole batch of candidates at once, and the analytic flow-curve benchmark
//! he tested them on (§6.3).

pub mod bayes;
pub mod de;
pub mod flow_curve;
pub mod gp;
pub mod nelder_mead;
pub mod optimizer;

pub use bayes::{Bayes, BayesSettings};
pub use de::{DeSettings, DifferentialEvolution, Strategy};
pub use nelder_mead::{NelderMead, NelderMeadSettings};
pub use optimizer::{Bounds, Evaluation, Optimizer, minimise};
