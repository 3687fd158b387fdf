//! Running a kernel with the widest vector instructions the CPU has, chosen at run time.
//!
//! The wheel is built for the x86-64 baseline (SSE2), so a kernel shaped for vectorisation
//! (structure-of-arrays blocks, fixed-width lanes, `#[inline(always)]` helpers) is compiled twice
//! through [`dispatch`]: once for the baseline and once with AVX2 enabled, and the AVX2 copy runs
//! where `is_x86_feature_detected!` finds it. FMA is deliberately not enabled, and Rust never
//! contracts `a * b + c` on its own, so both copies perform the same IEEE operations in the same
//! order: a result does not depend on the CPU it was computed on. [`dispatch_wide`] adds a third
//! copy with AVX-512 (32 vector registers, 512-bit vectors), for the kernels measured faster
//! with it.

/// Runs `kernel`, compiled with AVX2 when the CPU supports it (checked once per call; the check
/// is a cached load). The closure and every function it calls that should be vectorised must be
/// inlined into it (`#[inline(always)]`), since the wider instructions are enabled only inside
/// the dispatched copy.
#[inline(always)]
pub(crate) fn dispatch<R>(kernel: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { avx2(kernel) };
        }
    }
    kernel()
}

/// `kernel` compiled with AVX2.
///
/// # Safety
/// The CPU supports AVX and AVX2 (the caller checks it: [`dispatch`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
// SAFETY: a contract, not an operation: callable only where the CPU has these features.
unsafe fn avx2<R>(kernel: impl FnOnce() -> R) -> R {
    kernel()
}

/// [`dispatch`] with a third copy compiled for AVX-512 (F, VL, DQ) where the CPU has it: the
/// same 256-bit vectors, with 32 registers rather than 16 (fewer spills in kernels with many
/// live vectors) and the same IEEE operations in the same order (no FMA).
#[inline(always)]
pub(crate) fn dispatch_wide<R>(kernel: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl")
            && std::arch::is_x86_feature_detected!("avx512dq")
        {
            // SAFETY: the CPU supports these, checked just above.
            return unsafe { avx512(kernel) };
        }
    }
    dispatch(kernel)
}

/// `kernel` compiled with AVX-512 (F, VL, DQ).
///
/// # Safety
/// The CPU supports these features (the caller checks it: [`dispatch_wide`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,avx512f,avx512vl,avx512dq")]
// SAFETY: a contract, not an operation: callable only where the CPU has these features.
unsafe fn avx512<R>(kernel: impl FnOnce() -> R) -> R {
    kernel()
}
