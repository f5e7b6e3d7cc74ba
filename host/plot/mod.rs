//! PNG plots of a run's time series (energies, momenta; later forces and temperatures).
