//! Hot loops compiled for the widest vector instructions the processor has, picked at run time.
//!
//! The baseline x86-64 build uses SSE2, whose two-operand encoding spends many instructions on
//! register copies; AVX2's three-operand (VEX) encoding and 256-bit lanes run the same
//! arithmetic in fewer instructions. Rust never contracts `a * b + c` into a fused
//! multiply–add, so both builds give the same bytes.

/// Calls `f`, compiled for AVX2 where the processor has it and as the baseline build
/// elsewhere. Only code inlined into the AVX2 copy is compiled for AVX2, so mark the closure
/// `#[inline(always)]` (a large closure is otherwise called, not inlined) and keep its hot loop
/// in `#[inline(always)]` functions: `with_avx2(#[inline(always)] || kernel(x))`.
#[inline(always)]
pub fn with_avx2<R>(f: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2, checked just above.
        return unsafe { avx2(f) };
    }
    f()
}

/// `f` compiled with AVX2 enabled.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn avx2<R>(f: impl FnOnce() -> R) -> R {
    f()
}
