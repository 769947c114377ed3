//! Large texture buffers on 2 MB pages. Random lookups in a texture larger than the TLB's reach (a few MB
//! of 4 KB pages) otherwise walk the page table on most reads; on Linux with transparent huge pages in
//! "madvise" mode (the common default) a buffer gets 2 MB pages only when asked.

/// Asks for `buffer` to be backed by 2 MB pages where it can be: call it before the buffer is first
/// written, so the pages are huge when they are faulted in. A hint: elsewhere, or when the kernel
/// refuses, nothing changes.
pub fn advise_huge_pages<T>(buffer: &mut [T]) {
    #[cfg(target_os = "linux")]
    {
        const HUGE_PAGE: usize = 2 << 20;
        const MADV_HUGEPAGE: i32 = 14;
        extern "C" {
            fn madvise(addr: *mut std::ffi::c_void, len: usize, advice: i32) -> i32;
        }
        // Only whole huge pages inside the buffer: the advice covers no memory the buffer does not own.
        let start = buffer.as_mut_ptr() as usize;
        let end = start + std::mem::size_of_val(buffer);
        let (first, last) = (start.next_multiple_of(HUGE_PAGE), end / HUGE_PAGE * HUGE_PAGE);
        if last > first {
            // SAFETY: the range lies inside `buffer`, which this call borrows mutably; MADV_HUGEPAGE
            // changes how the pages are backed, never their contents. The result is ignored: a hint.
            unsafe { madvise(first as *mut std::ffi::c_void, last - first, MADV_HUGEPAGE) };
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = buffer;
}
