//! The fixed order of the DSMC engine's floating-point sums over its grains: fixed chunks
//! of [`SUM_CHUNK`] grains of the storage order, each summed from zero in storage order,
//! then the chunks' sums added in order. The bits do not depend on the number of threads;
//! a decomposed engine reproduces them over its ranks (`Domain::ordered_fold`).

/// Fixed chunk length of the deterministic reductions (independent of the thread count).
pub(crate) const SUM_CHUNK: usize = 4096;
