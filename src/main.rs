//! The `strider` binary: everything lives in the library's [`strider::cli`]. The binary adds
//! one thing the library may not own: an allocator that counts the bytes each thread holds,
//! which the script host reads to bound what a script may hold
//! ([`strider::script::set_memory_probe`]).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// The system allocator, counting per thread the bytes allocated less those freed.
struct Counting;

thread_local! {
    /// Bytes this thread allocated less those it freed (negative when it frees what another
    /// thread allocated). No destructor, so it is there while the thread lives.
    static HELD: Cell<i64> = const { Cell::new(0) };
}

fn count(bytes: i64) {
    let _ = HELD.try_with(|h| h.set(h.get().wrapping_add(bytes)));
}

fn held() -> i64 {
    HELD.try_with(Cell::get).unwrap_or(0)
}

// SAFETY: every call is passed on to `System` unchanged; the counting only reads sizes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is `System`'s.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            count(layout.size() as i64);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as above.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            count(layout.size() as i64);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) };
        count(-(layout.size() as i64));
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as above.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            count(new_size as i64 - layout.size() as i64);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn main() -> std::process::ExitCode {
    strider::script::set_memory_probe(held);
    strider::cli::main()
}
