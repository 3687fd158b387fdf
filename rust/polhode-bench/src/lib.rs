//! Criterion benchmarks of polhode's kernels, in `benches/kernels.rs`:
//! `cargo bench -p polhode-bench --bench kernels`. This library is empty; the crate exists so
//! that criterion is a dependency of the benchmarks alone.
