//! Software prefetch: one of the four places the crate uses `unsafe` (a hint to the
//! processor that cannot fault or change any state; the others are the AVX-512, AVX2 and
//! SSE2 contact searches in `candidates`).

/// Bytes per cache line (x86_64 and most other processors).
pub const CACHE_LINE: usize = 64;

/// Asks the processor to start loading the records of all `slots` at once, so that
/// their cache misses overlap instead of being met one candidate at a time: in large
/// systems the loads of the candidates' records are the largest cost of a prediction
/// (+18 % at 10^5 spheres, +30 % at 10^6; no effect while everything fits in cache).
/// Records whose size does not divide a cache line (48-byte disks) lie across two lines
/// one time in two, so their last byte is prefetched too (+11 % at 10^6 disks, +4 % at
/// 10^5, none at 10^4).
#[inline(always)]
#[allow(unsafe_code)]
pub fn prefetch_all<T>(records: &[T], slots: &[u32]) {
    #[cfg(target_arch = "x86_64")]
    for &j in slots {
        if let Some(r) = records.get(j as usize) {
            // SAFETY: `_mm_prefetch` needs SSE, which every x86_64 processor has; a
            // prefetch is only a hint (it never faults, reads nothing into the program
            // and changes no state), and the pointer is to a live element anyway.
            unsafe {
                let first = (r as *const T).cast::<i8>();
                std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(first);
                if !CACHE_LINE.is_multiple_of(std::mem::size_of::<T>()) {
                    std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
                        first.wrapping_add(std::mem::size_of::<T>() - 1),
                    );
                }
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (records, slots);
}
