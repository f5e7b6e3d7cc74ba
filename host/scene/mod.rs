//! Scene files (TOML): schema, loading, `--set` overrides, validation, and the particle sets they describe.
