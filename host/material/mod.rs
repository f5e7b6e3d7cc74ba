//! The material library (cases/materials/): loading, listing and evaluating named parameter sets.
