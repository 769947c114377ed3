//! Large buffers in 2 MB pages where the system offers them (Linux's transparent huge pages, on request).
//!
//! A random texture lookup on a level larger than the caches misses the TLB as well as the caches: a 4096^2
//! RGBA8 level spans 16,384 pages of 4 KB, far more than a core's TLB holds, and in a virtual machine each
//! page walk is itself a walk through the host's tables. In 2 MB pages the same level is 32 pages.

use std::alloc::{self, Layout};
use std::ops::{Deref, DerefMut};
use std::ptr::NonNull;

/// Values whose every byte being zero is a valid value: a `PageBuffer` starts out as zeroed memory.
///
/// # Safety
/// The all-zero bit pattern must be a valid `Self`, and `Self` must own nothing (no `Drop`).
pub(crate) unsafe trait Zeroable: Copy {}

/// The size from which a buffer asks for 2 MB pages: below it the pages would be mostly partial (a 2 MB page
/// backs only a whole aligned 2 MB of the buffer), and small buffers fit in the TLB anyway.
const HUGE_FROM_BYTES: usize = 4 << 20;

/// A 2 MB page.
const HUGE_PAGE: usize = 2 << 20;

/// A fixed number of zero-initialised values in memory of their own: from `HUGE_FROM_BYTES` on Linux a
/// mapping aligned to 2 MB and advised into 2 MB pages (the kernel then backs each whole aligned 2 MB with
/// one page when it is first written), elsewhere the global allocator's zeroed memory.
pub(crate) struct PageBuffer<T: Zeroable> {
    ptr: NonNull<T>,
    len: usize,
    /// Whether the memory is a mapping of its own (unmapped on drop) rather than the allocator's.
    mapped: bool,
}

// SAFETY: the buffer owns its values as a `Vec` does; `T: Zeroable` owns nothing else.
unsafe impl<T: Zeroable + Send> Send for PageBuffer<T> {}
// SAFETY: shared access only reads, as through a `&[T]`.
unsafe impl<T: Zeroable + Sync> Sync for PageBuffer<T> {}

impl<T: Zeroable> PageBuffer<T> {
    /// `len` zero values. Panics as a `Vec` does where `len` values overflow the address space, and aborts
    /// where the memory cannot be had.
    pub fn zeroed(len: usize) -> Self {
        let layout = Layout::array::<T>(len).expect("a page buffer larger than the address space");
        if layout.size() == 0 {
            return PageBuffer { ptr: NonNull::dangling(), len, mapped: false };
        }
        if let Some(ptr) = map_huge(layout.size()) {
            return PageBuffer { ptr: ptr.cast(), len, mapped: true };
        }
        // SAFETY: the layout's size is not zero.
        let ptr = unsafe { alloc::alloc_zeroed(layout) };
        let ptr = NonNull::new(ptr.cast()).unwrap_or_else(|| alloc::handle_alloc_error(layout));
        PageBuffer { ptr, len, mapped: false }
    }
}

impl<T: Zeroable> Deref for PageBuffer<T> {
    type Target = [T];
    #[inline]
    fn deref(&self) -> &[T] {
        // SAFETY: `len` initialised (zeroed, then written) values of T at an aligned, owned pointer.
        unsafe { std::slice::from_raw_parts(self.ptr.as_ptr(), self.len) }
    }
}

impl<T: Zeroable> DerefMut for PageBuffer<T> {
    #[inline]
    fn deref_mut(&mut self) -> &mut [T] {
        // SAFETY: as in `deref`, borrowed exclusively.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.as_ptr(), self.len) }
    }
}

impl<T: Zeroable> Clone for PageBuffer<T> {
    fn clone(&self) -> Self {
        let mut copy = PageBuffer::zeroed(self.len);
        copy.copy_from_slice(self);
        copy
    }
}

impl<T: Zeroable> std::fmt::Debug for PageBuffer<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PageBuffer of {} values", self.len)
    }
}

impl<T: Zeroable> Drop for PageBuffer<T> {
    fn drop(&mut self) {
        let layout = Layout::array::<T>(self.len).expect("checked when made");
        if layout.size() == 0 {
            return;
        }
        if self.mapped {
            unmap(self.ptr.as_ptr().cast(), layout.size());
        } else {
            // SAFETY: allocated by `alloc_zeroed` with this layout.
            unsafe { alloc::dealloc(self.ptr.as_ptr().cast(), layout) };
        }
    }
}

/// `bytes` of zeroed memory starting on a 2 MB boundary, advised into 2 MB pages: `None` below
/// `HUGE_FROM_BYTES`, off Linux, or where the system refuses the mapping (the allocator is asked then).
#[cfg(target_os = "linux")]
fn map_huge(bytes: usize) -> Option<NonNull<u8>> {
    if bytes < HUGE_FROM_BYTES {
        return None;
    }
    // Mapped with a page's slack, then trimmed to start on a boundary: the kernel places mappings on 4 KB
    // boundaries only.
    let span = bytes.checked_add(HUGE_PAGE)?;
    // SAFETY: an anonymous private mapping at an address of the kernel's choosing touches no existing memory.
    let base = unsafe {
        libc::mmap(
            std::ptr::null_mut(),
            span,
            libc::PROT_READ | libc::PROT_WRITE,
            libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
            -1,
            0,
        )
    };
    if base == libc::MAP_FAILED {
        return None;
    }
    let start = (base as usize).next_multiple_of(HUGE_PAGE);
    let head = start - base as usize;
    let end = (start + bytes).next_multiple_of(page_size());
    let tail = base as usize + span - end;
    if head > 0 {
        unmap(base.cast(), head);
    }
    if tail > 0 {
        unmap(end as *mut u8, tail);
    }
    // Advice only: where transparent huge pages are off, the memory stays in small pages and works the same.
    // SAFETY: [start, start + bytes) lies within the mapping kept above.
    unsafe { libc::madvise(start as *mut libc::c_void, bytes, libc::MADV_HUGEPAGE) };
    NonNull::new(start as *mut u8)
}

#[cfg(not(target_os = "linux"))]
fn map_huge(_bytes: usize) -> Option<NonNull<u8>> {
    None
}

/// The system's page size.
#[cfg(target_os = "linux")]
fn page_size() -> usize {
    // SAFETY: sysconf only reads a system value.
    let size = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    usize::try_from(size).ok().filter(|&s| s > 0).unwrap_or(4096)
}

/// Unmaps `bytes` (rounded up to whole pages) at `ptr`, a part of a mapping made by `map_huge`.
#[cfg(target_os = "linux")]
fn unmap(ptr: *mut u8, bytes: usize) {
    // SAFETY: the range is a part of a mapping this module made and no longer uses.
    unsafe { libc::munmap(ptr.cast(), bytes) };
}

#[cfg(not(target_os = "linux"))]
fn unmap(_ptr: *mut u8, _bytes: usize) {
    unreachable!("nothing is mapped off Linux")
}

#[cfg(test)]
mod tests {
    use super::*;

    // SAFETY: zero bytes are the integer 0.
    unsafe impl Zeroable for u64 {}

    /// Small and large buffers start zeroed, keep what is written, clone and drop.
    #[test]
    fn buffers_start_zeroed_and_hold_their_values() {
        for len in [0, 1, 1000, (HUGE_FROM_BYTES / 8) + 12_345] {
            let mut b = PageBuffer::<u64>::zeroed(len);
            assert_eq!(b.len(), len);
            assert!(b.iter().all(|&v| v == 0));
            for (k, v) in b.iter_mut().enumerate() {
                *v = k as u64 * 3;
            }
            let c = b.clone();
            drop(b);
            assert!(c.iter().enumerate().all(|(k, &v)| v == k as u64 * 3));
        }
    }

    /// A large buffer starts on a 2 MB boundary on Linux, where the pages may be 2 MB ones.
    #[test]
    #[cfg(target_os = "linux")]
    fn large_buffers_are_aligned_to_huge_pages() {
        let b = PageBuffer::<u64>::zeroed(HUGE_FROM_BYTES / 8);
        assert_eq!(b.as_ptr() as usize % HUGE_PAGE, 0);
    }
}
