//! Large buffers in 2 MB pages where the system offers them (Linux's transparent huge pages, on request):
//! texture levels in buffers of their own that start on a 2 MB boundary (`PageBuffer`), and every other
//! large allocation of a program that makes `HugePageAllocator` its global allocator.
//!
//! A random texture lookup on a level larger than the caches misses the TLB as well as the caches: a 4096^2
//! RGBA8 level spans 16,384 pages of 4 KB, far more than a core's TLB holds, and in a virtual machine each
//! page walk is itself a walk through the host's tables. In 2 MB pages the same level is 32 pages.

use std::alloc::{self, GlobalAlloc, Layout, System};
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

/// The system's allocator, with every allocation of `HUGE_FROM_BYTES` or more advised into 2 MB pages
/// where it covers whole aligned ones: a program's global allocator (`#[global_allocator]`), so that a
/// large mesh's arrays, a frame's set-up triangles and projected vertices, and the frame itself are in 2 MB
/// pages without each being made by its own allocator. The advice is given before the caller writes, so
/// fresh memory is backed by 2 MB pages as it is first touched. Measured on a 1M-triangle mesh frame: about
/// 2 ms of 37 (BENCHMARKS.md).
pub struct HugePageAllocator;

// SAFETY: every call is the system allocator's own; the advice changes how pages back the memory, never its
// contents or whether it is mapped.
unsafe impl GlobalAlloc for HugePageAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's layout, as `GlobalAlloc::alloc` asks.
        let ptr = unsafe { System.alloc(layout) };
        advise_huge(ptr, layout.size());
        ptr
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as in `alloc`.
        let ptr = unsafe { System.alloc_zeroed(layout) };
        advise_huge(ptr, layout.size());
        ptr
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System` with this layout (every allocation here is the system's).
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as in `dealloc`; the caller's new size.
        let ptr = unsafe { System.realloc(ptr, layout, new_size) };
        advise_huge(ptr, new_size);
        ptr
    }
}

/// Advises the whole 2 MB pages within `bytes` at `ptr` into 2 MB pages, from `HUGE_FROM_BYTES` on Linux.
/// A refusal (no transparent huge pages) leaves the memory as it was.
fn advise_huge(ptr: *mut u8, bytes: usize) {
    #[cfg(target_os = "linux")]
    if !ptr.is_null() && bytes >= HUGE_FROM_BYTES {
        let start = (ptr as usize).next_multiple_of(HUGE_PAGE);
        let end = (ptr as usize + bytes) / HUGE_PAGE * HUGE_PAGE;
        if end > start {
            // SAFETY: the range lies within one live allocation; advice neither maps nor unmaps memory.
            unsafe { libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE) };
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (ptr, bytes);
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
    advise_huge(start as *mut u8, bytes);
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

    /// The VmFlags of the mapping of this process that holds `address`, from /proc/self/smaps.
    #[cfg(target_os = "linux")]
    fn vm_flags_at(address: usize) -> Vec<String> {
        let smaps = std::fs::read_to_string("/proc/self/smaps").expect("/proc/self/smaps");
        let mut inside = false;
        for line in smaps.lines() {
            let range = line.split_whitespace().next().and_then(|r| r.split_once('-'));
            if let Some((Ok(lo), Ok(hi))) =
                range.map(|(a, b)| (usize::from_str_radix(a, 16), usize::from_str_radix(b, 16)))
            {
                inside = (lo..hi).contains(&address);
            } else if let Some(flags) = line.strip_prefix("VmFlags:").filter(|_| inside) {
                return flags.split_whitespace().map(str::to_owned).collect();
            }
        }
        panic!("no mapping holds {address:#x}");
    }

    /// The allocator advises a large allocation's whole 2 MB pages (the kernel marks their mapping `hg`),
    /// and a reallocation's; the memory keeps what is written through the reallocation.
    #[test]
    #[cfg(target_os = "linux")]
    fn the_allocator_advises_large_allocations_into_huge_pages() {
        let thp = std::fs::read_to_string("/sys/kernel/mm/transparent_hugepage/enabled").unwrap_or_default();
        let advisable = thp.contains("[madvise]") || thp.contains("[always]");
        let alloc = HugePageAllocator;
        let large = Layout::from_size_align(3 * HUGE_PAGE + 12_345, 8).unwrap();
        // SAFETY: the layout has a size; the block is freed once, after its reallocation, with the new size.
        unsafe {
            let l = alloc.alloc(large);
            assert!(!l.is_null());
            let middle = (l as usize).next_multiple_of(HUGE_PAGE);
            if advisable {
                assert!(vm_flags_at(middle).iter().any(|f| f == "hg"), "{:?}", vm_flags_at(middle));
            }
            std::ptr::write_bytes(l, 7, large.size());
            let grown = alloc.realloc(l, large, 2 * large.size());
            assert!((0..large.size()).step_by(4093).all(|k| *grown.add(k) == 7));
            if advisable {
                let middle = (grown as usize + large.size()).next_multiple_of(HUGE_PAGE);
                assert!(vm_flags_at(middle).iter().any(|f| f == "hg"));
            }
            alloc.dealloc(grown, Layout::from_size_align(2 * large.size(), 8).unwrap());
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
