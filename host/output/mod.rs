//! Output: binary VTU frames with a PVD index, CSV time series, all written atomically.
