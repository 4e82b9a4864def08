//! An allocator for programs that step large worlds or record long runs: large blocks in
//! memory the kernel may back with 2 MiB pages. The Python extension installs it; a Rust
//! program opts in with
//!
//! ```
#![doc = include_str!("../examples/huge_pages.rs")]
//! ```
//!
//! A block of at least [`LARGE`] bytes (a recording's column of 144,000 doubles, a million
//! particles' state) is mapped on its own, 2 MiB aligned and rounded up to whole 2 MiB, and
//! marked `MADV_HUGEPAGE`: where transparent huge pages are enabled ("always" or "madvise",
//! `/sys/kernel/mm/transparent_hugepage/enabled`), its first write faults in one 2 MiB page
//! instead of 512 pages of 4 KiB, and the kernels that sweep it miss the TLB 512 times less.
//! numpy does the same for its arrays of 4 MiB and more. Everything smaller, and every block
//! on other systems, is the system allocator's. The arithmetic does not see where its memory
//! lies: the same bits either way.
//!
//! A freed block is kept for the next block of its size (up to 16 blocks and 64 MiB in all),
//! so a program that records or steps again and again does not fault its pages in again at
//! every call: a kept block is handed out as it was left (zeroed first where zeroed memory was
//! asked for).
//!
//! Measured (docs/performance.md, "Recording a small world"): a `physstep.simulate` of 144,000
//! recorded steps faulted in some 1,400 pages of 4 KiB a call, about as long as the
//! recording's arithmetic on this project's VM.

use std::alloc::{GlobalAlloc, Layout, System};

/// Blocks of this many bytes or more are mapped on their own.
pub const LARGE: usize = 1 << 20;

/// The size of a huge page on x86-64 and AArch64 Linux.
const HUGE: usize = 2 << 20;

/// The system allocator, with blocks of [`LARGE`] bytes and more mapped as huge pages.
#[derive(Debug, Clone, Copy, Default)]
pub struct HugePages;

#[cfg(target_os = "linux")]
mod large {
    use super::HUGE;
    use std::cell::UnsafeCell;
    use std::sync::atomic::{AtomicBool, Ordering};

    /// The length of the mapping that holds `size` bytes.
    pub(super) fn span(size: usize) -> usize {
        size.div_ceil(HUGE) * HUGE
    }

    /// Freed mappings kept for the next blocks of the same span (a recording's columns, a
    /// step's scratch), up to [`KEEP_BYTES`] in all: unmapping them and mapping anew would
    /// fault their pages in again at every call.
    const KEEP: usize = 16;
    const KEEP_BYTES: usize = 64 << 20;

    struct Kept {
        busy: AtomicBool,
        slots: UnsafeCell<[(usize, usize); KEEP]>,
    }

    // SAFETY: `slots` is only touched while `busy` is held (`with`).
    unsafe impl Sync for Kept {}

    static KEPT: Kept = Kept { busy: AtomicBool::new(false), slots: UnsafeCell::new([(0, 0); KEEP]) };

    /// Runs `f` on the kept mappings (address, span; span 0 for an empty slot), holding them.
    fn with<R>(f: impl FnOnce(&mut [(usize, usize); KEEP]) -> R) -> R {
        while KEPT.busy.compare_exchange_weak(false, true, Ordering::Acquire, Ordering::Relaxed).is_err() {
            std::hint::spin_loop();
        }
        // SAFETY: `busy` is held: no other reference to the slots exists.
        let r = f(unsafe { &mut *KEPT.slots.get() });
        KEPT.busy.store(false, Ordering::Release);
        r
    }

    /// A block of `span(size)` bytes: a kept mapping of that span, else a fresh zeroed
    /// mapping at a 2 MiB boundary, marked for huge pages; null when the system has no room.
    /// `zeroed`: a kept mapping is cleared first.
    pub(super) unsafe fn take(size: usize, zeroed: bool) -> *mut u8 {
        let len = span(size);
        let kept = with(|slots| slots.iter_mut().find(|s| s.1 == len).map(|s| std::mem::take(s).0));
        if let Some(addr) = kept {
            let ptr = addr as *mut u8;
            if zeroed {
                // SAFETY: the kept mapping is `len >= size` bytes, ours alone now.
                unsafe { ptr.write_bytes(0, size) };
            }
            return ptr;
        }
        let Some(reserve) = len.checked_add(HUGE) else { return std::ptr::null_mut() };
        // SAFETY: an anonymous private mapping at an address of the kernel's choosing.
        let base = unsafe {
            libc::mmap(
                std::ptr::null_mut(),
                reserve,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
                -1,
                0,
            )
        };
        if base == libc::MAP_FAILED {
            return std::ptr::null_mut();
        }
        let addr = base as usize;
        let start = addr.next_multiple_of(HUGE);
        // SAFETY: the head and the tail lie within the mapping just made, outside
        // `start..start + len`, and are page aligned (the mapping's ends and `start` are).
        unsafe {
            if start > addr {
                libc::munmap(base, start - addr);
            }
            let end = start + len;
            if addr + reserve > end {
                libc::munmap(end as *mut libc::c_void, addr + reserve - end);
            }
            // Advice only: without transparent huge pages the block keeps small pages.
            libc::madvise(start as *mut libc::c_void, len, libc::MADV_HUGEPAGE);
        }
        start as *mut u8
    }

    /// Gives back a block made by [`take`] for `size` bytes: kept while there is room, else
    /// unmapped.
    pub(super) unsafe fn give(ptr: *mut u8, size: usize) {
        let len = span(size);
        let kept = with(|slots| {
            let held: usize = slots.iter().map(|s| s.1).sum();
            if held + len > KEEP_BYTES {
                return false;
            }
            slots.iter_mut().find(|s| s.1 == 0).map(|s| *s = (ptr as usize, len)).is_some()
        });
        if !kept {
            // SAFETY: the caller's block, mapped by `take` with this span.
            unsafe { libc::munmap(ptr.cast(), len) };
        }
    }
}

/// Whether a block of this layout is mapped on its own (a block's layout decides it, and the
/// same layout is handed back to free it).
#[cfg(target_os = "linux")]
fn is_large(size: usize, align: usize) -> bool {
    size >= LARGE && align <= HUGE
}

#[cfg(not(target_os = "linux"))]
fn is_large(_: usize, _: usize) -> bool {
    false
}

// SAFETY: every block is either the system allocator's or a mapping of its own, told apart by
// its layout ([`is_large`]), which the callers of `dealloc` and `realloc` hand back unchanged;
// a mapping is aligned to 2 MiB, at least any layout's alignment it takes.
unsafe impl GlobalAlloc for HugePages {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        #[cfg(target_os = "linux")]
        if is_large(layout.size(), layout.align()) {
            // SAFETY: see `large::take`.
            return unsafe { large::take(layout.size(), false) };
        }
        // SAFETY: the caller's layout, of non-zero size.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        #[cfg(target_os = "linux")]
        if is_large(layout.size(), layout.align()) {
            // SAFETY: see `large::take`.
            return unsafe { large::take(layout.size(), true) };
        }
        // SAFETY: as `alloc`.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        #[cfg(target_os = "linux")]
        if is_large(layout.size(), layout.align()) {
            // SAFETY: a large block comes from `large::take` with this size.
            return unsafe { large::give(ptr, layout.size()) };
        }
        // SAFETY: a small block comes from the system allocator with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let (old, new) = (is_large(layout.size(), layout.align()), is_large(new_size, layout.align()));
        if !old && !new {
            // SAFETY: the system allocator's block, resized by it.
            return unsafe { System.realloc(ptr, layout, new_size) };
        }
        #[cfg(target_os = "linux")]
        if old && new && large::span(new_size) == large::span(layout.size()) {
            return ptr; // the same mapping holds it
        }
        // SAFETY: `new_size` is non-zero and, rounded to the alignment, within isize (the
        // caller's contract); the old block is valid for `min(old, new)` bytes.
        unsafe {
            let fresh = self.alloc(Layout::from_size_align_unchecked(new_size, layout.align()));
            if !fresh.is_null() {
                std::ptr::copy_nonoverlapping(ptr, fresh, layout.size().min(new_size));
                self.dealloc(ptr, layout);
            }
            fresh
        }
    }
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    fn layout(size: usize) -> Layout {
        Layout::from_size_align(size, 8).unwrap()
    }

    /// Fills `n` bytes at `p` with a pattern of `seed`, or checks it.
    unsafe fn pattern(p: *mut u8, n: usize, seed: u8, check: bool) {
        for i in (0..n).step_by(4093) {
            let v = (i as u8).wrapping_mul(31).wrapping_add(seed);
            if check {
                assert_eq!(unsafe { *p.add(i) }, v, "byte {i}");
            } else {
                unsafe { *p.add(i) = v };
            }
        }
    }

    #[test]
    fn a_large_block_is_aligned_to_a_huge_page_and_advised_to_use_them() {
        let a = HugePages;
        let size = 3 * LARGE + 12_345;
        unsafe {
            let p = a.alloc(layout(size));
            assert!(!p.is_null());
            assert_eq!(p as usize % HUGE, 0);
            pattern(p, size, 7, false);
            // The kernel's record of the mapping: `hg` in its flags is MADV_HUGEPAGE.
            let smaps = std::fs::read_to_string("/proc/self/smaps").unwrap();
            let start = format!("{:x}-", p as usize);
            let entry =
                smaps.split('\n').skip_while(|l| !l.starts_with(&start)).take_while(|l| !l.is_empty());
            let flags: Vec<&str> = entry.filter(|l| l.starts_with("VmFlags:")).collect();
            assert!(flags.first().is_some_and(|f| f.split_whitespace().any(|w| w == "hg")), "{flags:?}");
            pattern(p, size, 7, true);
            a.dealloc(p, layout(size));
            // A small block is the system allocator's.
            let q = a.alloc(layout(LARGE - 8));
            assert!(!q.is_null());
            pattern(q, LARGE - 8, 3, false);
            pattern(q, LARGE - 8, 3, true);
            a.dealloc(q, layout(LARGE - 8));
        }
    }

    #[test]
    fn resizing_across_the_threshold_and_the_spans_keeps_the_contents() {
        let a = HugePages;
        unsafe {
            let mut size = 1000;
            let mut p = a.alloc(layout(size));
            pattern(p, size, 1, false);
            // Small -> large -> a larger span -> the same span -> a smaller span -> small.
            for new in [LARGE + 1, 5 * LARGE, 5 * LARGE + 100, 2 * LARGE, 4096] {
                p = a.realloc(p, layout(size), new);
                assert!(!p.is_null());
                pattern(p, size.min(new), 1, true);
                pattern(p, new, 1, false);
                size = new;
            }
            a.dealloc(p, layout(size));
        }
    }

    #[test]
    fn a_kept_block_asked_for_zeroed_is_zeroed() {
        let a = HugePages;
        let size = 2 * LARGE + 8;
        unsafe {
            // Freed blocks of this span are kept: asked for again, one may come back as it
            // was left, and zeroed it must be all zeros.
            for round in 0..4u8 {
                let p = a.alloc_zeroed(layout(size));
                assert!(!p.is_null());
                let bytes = std::slice::from_raw_parts(p, size);
                assert!(bytes.iter().all(|&b| b == 0), "round {round}");
                std::ptr::write_bytes(p, 0xA5, size);
                a.dealloc(p, layout(size));
            }
        }
    }

    #[test]
    fn threads_taking_and_giving_blocks_never_share_one() {
        let a = HugePages;
        let handles: Vec<_> = (0..4u8)
            .map(|t| {
                std::thread::spawn(move || unsafe {
                    for k in 0..50u8 {
                        let size = LARGE * (1 + usize::from(k % 3));
                        let p = a.alloc(layout(size));
                        assert!(!p.is_null());
                        let seed = t.wrapping_mul(61).wrapping_add(k);
                        pattern(p, size, seed, false);
                        std::thread::yield_now();
                        pattern(p, size, seed, true);
                        a.dealloc(p, layout(size));
                    }
                })
            })
            .collect();
        for h in handles {
            h.join().unwrap();
        }
    }
}
