//! The binary's global allocator: the system allocator, counting the heap
//! in use into [`genom_model::limits::heap`] (which the parsers and engines
//! look at to stop cleanly with `incomplete` under `--max-memory`), and
//! refusing to grow it past [`genom_model::limits::heap_bound`].
//!
//! Past that bound no phase got the chance to stop cleanly (a single step
//! asked for more than the margin): the process prints one line and exits
//! with status 1 at once, so that its resident size never passes
//! `--max-memory`. This is the only `unsafe` code of genom-check: a
//! `GlobalAlloc` cannot be implemented without it.

#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Write as _;
use std::sync::atomic::{AtomicUsize, Ordering};

use genom_model::limits::{heap, heap_bound};

/// The system allocator, counted and bounded.
pub struct Bounded;

/// The heap bound in bytes (no bound until [`limit`] is called).
static BOUND: AtomicUsize = AtomicUsize::new(usize::MAX);

/// Bounds the heap for `--max-memory` = `max_memory` bytes.
pub fn limit(max_memory: usize) {
    BOUND.store(heap_bound(max_memory), Ordering::Relaxed);
}

/// Counts `bytes` more; past the bound, stops the process.
fn grow(bytes: usize) {
    if heap::allocated(bytes) > BOUND.load(Ordering::Relaxed) {
        stop();
    }
}

/// Ends the process: nothing may be allocated here (stderr is unbuffered).
fn stop() -> ! {
    let _ = std::io::stderr().write_all(
        b"error[incomplete]: verification is incomplete: the memory limit (--max-memory) was \
          reached in a step that could not stop cleanly; nothing was reported; raise \
          --max-memory\n",
    );
    std::process::exit(1)
}

// SAFETY: every call is forwarded to `System` with the same arguments; the
// counter only observes sizes.
unsafe impl GlobalAlloc for Bounded {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        grow(layout.size());
        // SAFETY: the caller's contract, forwarded.
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            heap::freed(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        grow(layout.size());
        // SAFETY: the caller's contract, forwarded.
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            heap::freed(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract, forwarded.
        unsafe { System.dealloc(ptr, layout) };
        heap::freed(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = layout.size();
        if new_size > old {
            grow(new_size - old);
        }
        // SAFETY: the caller's contract, forwarded.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            if new_size > old {
                heap::freed(new_size - old);
            }
        } else if new_size < old {
            heap::freed(old - new_size);
        }
        p
    }
}
