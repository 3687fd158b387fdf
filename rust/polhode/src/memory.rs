//! Fallible allocation of everything whose size comes from the input: an error the caller can
//! act on ([`Error::OutOfMemory`], saying what the memory was for and what to ask for instead),
//! never an abort of the process.
//!
//! Rust's `vec![x; n]`, `Vec::with_capacity`, `collect` and a `push` that grows a vector abort
//! the process when the allocator refuses (`memory allocation of N bytes failed`): under a
//! memory limit, or with the machine's memory taken, a call on a large input would end the
//! Python interpreter rather than raise `MemoryError`. Every allocation of the crate whose size
//! depends on the input goes through this module instead (and so do the Python binding's); the
//! allocations left as they are have a size fixed by the code (a few rows, one per thread).
//!
//! ```
//! use polhode::memory::{zeros, Purpose};
//! use polhode::Error;
//!
//! let fits: Vec<f64> = zeros(1000, Purpose::Outputs).unwrap();
//! assert_eq!(fits.len(), 1000);
//! // More than any machine has: an error, not an abort.
//! let error = zeros::<f64>(usize::MAX / 16, Purpose::PrincipalAxes).unwrap_err();
//! assert!(matches!(error, Error::OutOfMemory { purpose: Purpose::PrincipalAxes, .. }));
//! assert!(error.to_string().contains("fewer tensors"));
//! ```

use std::collections::TryReserveError;
use std::mem::size_of;

use rayon::iter::IndexedParallelIterator;

use crate::{Error, Result};

pub use crate::error::Purpose;

/// Types whose all-zero bit pattern is a value (allocated zeroed by [`zeros`]).
///
/// # Safety
///
/// A value of the type must be valid with every byte zero, and the type must not be
/// zero-sized.
pub unsafe trait Zeroable: Copy {}

// SAFETY: all-zero bits are 0.0, 0 and `false`.
unsafe impl Zeroable for f64 {}
// SAFETY: as above.
unsafe impl Zeroable for f32 {}
// SAFETY: as above.
unsafe impl Zeroable for u8 {}
// SAFETY: as above.
unsafe impl Zeroable for u32 {}
// SAFETY: as above.
unsafe impl Zeroable for u64 {}
// SAFETY: as above.
unsafe impl Zeroable for i64 {}
// SAFETY: as above.
unsafe impl Zeroable for usize {}
// SAFETY: as above.
unsafe impl Zeroable for bool {}
// SAFETY: three zeroable values.
unsafe impl Zeroable for [f64; 3] {}

/// `len * size_of::<T>()` as a number of bytes (for the error).
fn bytes_of<T>(len: usize) -> f64 {
    len as f64 * size_of::<T>() as f64
}

/// `len` zeros, or [`Error::OutOfMemory`] for `purpose` if the allocation fails.
///
/// Allocated zeroed (`calloc`): a large block comes as fresh zero pages from the system, not
/// written here, so an output of gigabytes costs nothing before the run (writing the zeros
/// took seconds that Ctrl-C could not interrupt) and its pages are touched once, by the run:
/// what `vec![0; len]` does, without its abort on failure.
pub fn zeros<T: Zeroable>(len: usize, purpose: Purpose) -> Result<Vec<T>> {
    if len == 0 {
        return Ok(Vec::new());
    }
    let layout =
        std::alloc::Layout::array::<T>(len).map_err(|_| purpose.error(bytes_of::<T>(len)))?;
    // SAFETY: `layout` has a non-zero size (`len > 0` values of a `Zeroable` type, none of
    // which is zero-sized).
    let data = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<T>();
    if data.is_null() {
        return Err(purpose.error(bytes_of::<T>(len)));
    }
    // SAFETY: `data` was allocated by the global allocator with the layout of `len` values of
    // `T` (capacity `len`), and all of them are initialised: all-zero bits are a `T`
    // (`Zeroable`).
    Ok(unsafe { Vec::from_raw_parts(data, len, len) })
}

/// `len` copies of `value` (`vec![value; len]`), or [`Error::OutOfMemory`].
pub fn filled<T: Clone>(len: usize, value: T, purpose: Purpose) -> Result<Vec<T>> {
    let mut out = with_capacity(len, purpose)?;
    out.resize(len, value);
    Ok(out)
}

/// An empty vector with room for `len` values (`Vec::with_capacity`), or
/// [`Error::OutOfMemory`].
pub fn with_capacity<T>(len: usize, purpose: Purpose) -> Result<Vec<T>> {
    let mut out = Vec::new();
    out.try_reserve_exact(len)
        .map_err(|e| failed::<T>(&e, len, purpose))?;
    Ok(out)
}

/// A copy of `values` (`values.to_vec()`), or [`Error::OutOfMemory`].
pub fn copied<T: Clone>(values: &[T], purpose: Purpose) -> Result<Vec<T>> {
    let mut out = with_capacity(values.len(), purpose)?;
    out.extend_from_slice(values);
    Ok(out)
}

/// The values of `iter` collected, room for them reserved first: exactly `len()` for an exact
/// size, or the lower bound of its size hint and then as it grows (by [`push`]).
pub fn collect<T>(iter: impl IntoIterator<Item = T>, purpose: Purpose) -> Result<Vec<T>> {
    let iter = iter.into_iter();
    let mut out = with_capacity(iter.size_hint().0, purpose)?;
    for value in iter {
        push(&mut out, value, purpose)?;
    }
    Ok(out)
}

/// The items of an indexed parallel iterator, in order (`collect` of rayon), the vector
/// reserved first.
pub fn collect_parallel<I>(iter: I, purpose: Purpose) -> Result<Vec<I::Item>>
where
    I: IndexedParallelIterator,
{
    let mut out = with_capacity(iter.len(), purpose)?;
    // Writes into the room reserved: no further allocation.
    iter.collect_into_vec(&mut out);
    Ok(out)
}

/// `vector.push(value)`, or [`Error::OutOfMemory`] if it must grow and cannot (growing as
/// `push` does, by doubling).
#[inline]
pub fn push<T>(vector: &mut Vec<T>, value: T, purpose: Purpose) -> Result<()> {
    if vector.len() == vector.capacity() {
        grow(vector, purpose)?;
    }
    vector.push(value);
    Ok(())
}

#[cold]
#[inline(never)]
fn grow<T>(vector: &mut Vec<T>, purpose: Purpose) -> Result<()> {
    vector
        .try_reserve(1)
        .map_err(|e| failed::<T>(&e, vector.len() + 1, purpose))
}

/// `values` appended to `vector`, or [`Error::OutOfMemory`].
pub fn extend<T: Clone>(vector: &mut Vec<T>, values: &[T], purpose: Purpose) -> Result<()> {
    vector
        .try_reserve(values.len())
        .map_err(|e| failed::<T>(&e, vector.len() + values.len(), purpose))?;
    vector.extend_from_slice(values);
    Ok(())
}

/// The error for a vector of `len` values that could not be reserved.
fn failed<T>(_: &TryReserveError, len: usize, purpose: Purpose) -> Error {
    purpose.error(bytes_of::<T>(len))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_helper_refuses_what_cannot_be_allocated() {
        let huge = usize::MAX / 64;
        let is_oom = |r: Result<()>| matches!(r, Err(Error::OutOfMemory { .. }));
        assert!(is_oom(zeros::<f64>(huge, Purpose::Outputs).map(drop)));
        assert!(is_oom(zeros::<[f64; 3]>(huge, Purpose::Mesh).map(drop)));
        assert!(is_oom(filled(huge, 1u32, Purpose::Mesh).map(drop)));
        assert!(is_oom(with_capacity::<u64>(huge, Purpose::Mesh).map(drop)));
        assert!(is_oom(collect(0..huge, Purpose::Mesh).map(drop)));
    }

    #[test]
    fn the_helpers_give_what_the_standard_library_gives() {
        assert_eq!(zeros::<u32>(5, Purpose::Mesh).unwrap(), vec![0u32; 5]);
        assert_eq!(
            zeros::<[f64; 3]>(2, Purpose::Mesh).unwrap(),
            vec![[0.0; 3]; 2]
        );
        assert!(zeros::<f64>(0, Purpose::Mesh).unwrap().is_empty());
        assert_eq!(filled(3, 7u32, Purpose::Mesh).unwrap(), vec![7u32; 3]);
        assert_eq!(copied(&[1, 2, 3], Purpose::Mesh).unwrap(), vec![1, 2, 3]);
        let odd = (0..100).filter(|i| i % 2 == 1);
        assert_eq!(
            collect(odd.clone(), Purpose::Mesh).unwrap(),
            odd.collect::<Vec<_>>()
        );
        let mut v = Vec::new();
        for i in 0..1000 {
            push(&mut v, i, Purpose::Mesh).unwrap();
        }
        assert_eq!(v, (0..1000).collect::<Vec<_>>());
        extend(&mut v, &[5, 6], Purpose::Mesh).unwrap();
        assert_eq!(&v[998..], &[998, 999, 5, 6]);
        use rayon::prelude::*;
        let sevens = collect_parallel(
            (0..10_000u32).into_par_iter().map(|i| u64::from(i) * 7),
            Purpose::Mesh,
        );
        assert_eq!(
            sevens.unwrap(),
            (0..10_000u64).map(|i| i * 7).collect::<Vec<_>>()
        );
    }

    #[test]
    fn the_message_says_what_the_memory_was_for_and_what_to_ask_instead() {
        let message = Purpose::Outputs.error(3.36e9).to_string();
        assert_eq!(
            message,
            "Cannot allocate 3.360e9 bytes for the outputs: ask for fewer output times or bodies, \
             without the orientation, or in chunks (polhode.dask)."
        );
    }
}
