//! A global allocator that counts the heap allocations of the current thread, for the tests
//! that a hot path does not allocate: the other tests of a binary run on other threads and are
//! not counted. A test binary includes this file from its `main.rs` with
//! `#[path = "../shared/counting_alloc.rs"] mod counting_alloc;`, and the module that counts
//! registers `counting_alloc::Counting` as the binary's `#[global_allocator]`.

/// Forwards to the system allocator and counts each allocation of the calling thread.
pub struct Counting;

thread_local! {
    static ALLOCS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Heap allocations made so far by the current thread.
pub fn allocs() -> usize {
    ALLOCS.with(|n| n.get())
}

// SAFETY: forwards to the system allocator; the counter is a const-initialised thread-local
// `Cell`, which does not allocate.
unsafe impl std::alloc::GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        let _ = ALLOCS.try_with(|n| n.set(n.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
}
