//! Nothing but a home for the engine's criterion benchmarks (`benches/kernels.rs`, run by
//! `cargo bench -p physstep-bench`): criterion is a dev-dependency here, not of `physstep`,
//! so `cargo test -p physstep` does not build it. Not published.
