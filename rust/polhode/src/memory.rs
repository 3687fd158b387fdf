//! Fallible allocation of outputs whose size comes from the input: an error the caller can
//! act on ([`Error::OutOfMemory`]), never an abort.

use crate::{Error, Result};

/// `len` zeros, or [`Error::OutOfMemory`] (the whole output being `bytes`) if the allocation
/// fails, rather than an abort.
///
/// Allocated zeroed (`calloc`): a large block comes as fresh zero pages from the system, not
/// written here, so an output of gigabytes costs nothing before the run (writing the zeros
/// took seconds that Ctrl-C could not interrupt) and its pages are touched once, by the run.
/// Stable Rust has no safe fallible zeroed allocation (`Vec::try_reserve` leaves the memory
/// uninitialised, `vec![0.0; len]` aborts on failure): this is the one `unsafe` of the crate
/// outside its SIMD kernels.
pub(crate) fn zeros(len: usize, bytes: f64) -> Result<Vec<f64>> {
    if len == 0 {
        return Ok(Vec::new());
    }
    let layout = std::alloc::Layout::array::<f64>(len).map_err(|_| Error::OutOfMemory { bytes })?;
    // SAFETY: `layout` has a non-zero size (`len > 0` f64s).
    let data = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<f64>();
    if data.is_null() {
        return Err(Error::OutOfMemory { bytes });
    }
    // SAFETY: `data` was allocated by the global allocator with the layout of `len` f64s
    // (capacity `len`), and all of them are initialised: all-zero bits are the f64 0.0.
    Ok(unsafe { Vec::from_raw_parts(data, len, len) })
}
