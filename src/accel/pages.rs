//! Large arrays of the tree on 2 MiB pages. A walk through a million-object tree touches
//! its nodes and leaves all over tens of megabytes; with 4 KiB pages nearly every such
//! load also misses the TLB (the processor's cache of address translations), and the page
//! walk that follows waits on memory too. On Linux, whose transparent huge pages are often
//! enabled only for memory that asks (`madvise` mode), the tree asks for them.

/// Asks the kernel to back the 2 MiB-aligned part of `v`'s allocation with huge pages:
/// called on a fresh allocation before its pages are first written, so that they are
/// faulted in as huge pages. Only a hint: nothing changes but the page size, and nothing
/// happens elsewhere than on Linux.
pub fn advise_huge_pages<T>(v: &Vec<T>) {
    #[cfg(target_os = "linux")]
    {
        const HUGE: usize = 2 << 20;
        let start = v.as_ptr() as usize;
        let end = start + v.capacity() * size_of::<T>();
        let (lo, hi) = (start.next_multiple_of(HUGE), end / HUGE * HUGE);
        if hi > lo {
            // SAFETY: the range lies within `v`'s allocation, and the advice changes no
            // content; its result (unsupported, or disabled) is of no consequence.
            unsafe {
                libc::madvise(lo as *mut libc::c_void, hi - lo, libc::MADV_HUGEPAGE);
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = v;
}
