//! The vector code paths: kernels compiled for AVX2 run where the CPU has it (run-time
//! dispatch), the baseline build elsewhere. Only `+ - * / sqrt` of IEEE doubles are used, and
//! a multiply-add is fused only where the code says so (Rust never contracts `a * b + c`): in
//! the sparse Cholesky factorisation, whose kernels write `mul_add` and take their vector path
//! where the CPU has AVX2 and FMA. `mul_add` is one correctly rounded operation on either
//! path (an FMA instruction, or the C library's `fma` in the baseline build, slower there but
//! the same result), so both paths give bitwise the same results; [`set_vector_paths`]
//! switches the vector paths off to check that.

use std::sync::atomic::{AtomicBool, Ordering};

/// Whether the kernels may take their AVX2 code path (see [`set_vector_paths`]).
static VECTOR_PATHS: AtomicBool = AtomicBool::new(true);

/// Allows (the default) or forbids the vector code paths (the particle kernels' and n-body
/// gravity's AVX2 paths, the contact solver's four-lane passes), for the whole process. Both
/// paths give bitwise the same results; this switch exists to check that, and to measure what
/// the vector code gains.
pub fn set_vector_paths(enabled: bool) {
    VECTOR_PATHS.store(enabled, Ordering::Relaxed);
}

/// Whether the vector code paths are allowed ([`set_vector_paths`]; the contact solver's
/// four-lane passes take it, compiled for AVX2 or not).
#[inline]
pub(crate) fn enabled() -> bool {
    VECTOR_PATHS.load(Ordering::Relaxed)
}

/// Whether the AVX2 path runs: the CPU has AVX2 and it is allowed.
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn avx2() -> bool {
    VECTOR_PATHS.load(Ordering::Relaxed) && std::arch::is_x86_feature_detected!("avx2")
}

/// Whether the AVX2 path with fused multiply-adds runs: the CPU has AVX2 and FMA and it is
/// allowed.
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn fma() -> bool {
    avx2() && std::arch::is_x86_feature_detected!("fma")
}
