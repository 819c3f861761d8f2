//! The fuzz binary's global allocator: the system allocator, counting the bytes live, and
//! refusing any allocation that would take them more than a cap above what was live when the
//! current execution started.
//!
//! A refused allocation returns null, as an exhausted allocator does: an infallible
//! allocation then aborts the process ("memory allocation of N bytes failed", which the
//! supervisor recognises as an out-of-memory finding), and a fallible one (`try_reserve`)
//! fails, which the worker sees in [`refused`] after the execution and records as a finding
//! too. Either way the input is kept. Without the cap, a decoder that trusts a declared size
//! would be killed by the kernel or swap for minutes instead.
//!
//! This is the project's one `unsafe` outside the Embree wrapper: implementing
//! [`GlobalAlloc`] is an unsafe trait by definition. It lives in the fuzz binary only.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Bytes allocated and not yet freed, by every thread.
static LIVE: AtomicUsize = AtomicUsize::new(0);
/// Allocations that would take [`LIVE`] above this are refused.
static LIMIT: AtomicUsize = AtomicUsize::new(usize::MAX);
/// The size of the first refused allocation since [`arm`], 0 if none.
static REFUSED: AtomicUsize = AtomicUsize::new(0);

/// The counting, capped allocator (install with `#[global_allocator]`).
pub struct Capped;

/// Counts `size` more bytes, or refuses them over the limit.
fn reserve(size: usize) -> bool {
    let before = LIVE.fetch_add(size, Ordering::Relaxed);
    let after = before.saturating_add(size);
    if after > LIMIT.load(Ordering::Relaxed) {
        LIVE.fetch_sub(size, Ordering::Relaxed);
        let _ = REFUSED.compare_exchange(0, size.max(1), Ordering::Relaxed, Ordering::Relaxed);
        return false;
    }
    true
}

fn release(size: usize) {
    LIVE.fetch_sub(size, Ordering::Relaxed);
}

// SAFETY: every method forwards to `System` with the caller's own pointer and layout (so
// `System`'s guarantees are what the caller gets), and returns null only where `GlobalAlloc`
// allows it (allocation failure). The counters are atomics; nothing here allocates, panics or
// unwinds.
unsafe impl GlobalAlloc for Capped {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !reserve(layout.size()) {
            return std::ptr::null_mut();
        }
        // SAFETY: the caller's layout has a non-zero size, as `GlobalAlloc::alloc` requires.
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            release(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !reserve(layout.size()) {
            return std::ptr::null_mut();
        }
        // SAFETY: as in `alloc`.
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            release(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was allocated by this allocator, i.e. by `System`, with `layout`.
        unsafe { System.dealloc(ptr, layout) };
        release(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = layout.size();
        if new_size > old && !reserve(new_size - old) {
            return std::ptr::null_mut();
        }
        // SAFETY: `ptr` and `layout` come from this allocator (i.e. `System`), and `new_size`
        // is the caller's, as `GlobalAlloc::realloc` requires.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            if new_size > old {
                release(new_size - old);
            }
        } else if new_size < old {
            release(old - new_size);
        }
        p
    }
}

/// Starts an execution: at most `cap` bytes more than are live now may be allocated.
pub fn arm(cap: usize) {
    let live = LIVE.load(Ordering::Relaxed);
    REFUSED.store(0, Ordering::Relaxed);
    LIMIT.store(live.saturating_add(cap), Ordering::Relaxed);
}

/// Ends an execution: no limit until the next [`arm`].
pub fn disarm() {
    LIMIT.store(usize::MAX, Ordering::Relaxed);
}

/// The size of the first allocation refused since [`arm`], if any.
pub fn refused() -> Option<usize> {
    match REFUSED.load(Ordering::Relaxed) {
        0 => None,
        n => Some(n),
    }
}
