//! What runs before anything else. The default build is for x86-64-v3 (.cargo/config.toml), and on an
//! older CPU its first AVX2 instruction would kill it with SIGILL and no word of why. There it hands the
//! command, as it was typed, to the portable build beside it (`wrinkle-portable`, made by
//! scripts/build-portable.sh; the same bits out), or says what is missing and exits.
//!
//! All of it runs on a CPU that may lack AVX, where any vector move would be fatal, and an x86-64-v3 build
//! moves even 16-byte values with AVX. So it runs from the C library's start-up list, before the standard
//! library's own start-up and `main`, and works byte by byte (volatile, so that nothing is vectorised)
//! with raw system calls. tests/end_to_end/portable.rs runs it on an emulated pre-AVX2 CPU.

#[cfg(all(target_os = "linux", target_env = "gnu", target_arch = "x86_64"))]
mod hand_over {
    use std::ffi::c_char;
    use std::ptr::{read_volatile, write_volatile};

    /// glibc calls the functions of `.init_array` with `(argc, argv, envp)` before `main`.
    #[used]
    #[link_section = ".init_array"]
    static START: extern "C" fn(i32, *const *const c_char, *const *const c_char) = start;

    /// The file name of the portable build, looked for beside this one.
    const PORTABLE: &str = "wrinkle-portable";

    const SYS_WRITE: usize = 1;
    const SYS_EXECVE: usize = 59;
    const SYS_READLINK: usize = 89;
    const SYS_EXIT_GROUP: usize = 231;
    const ENOENT: isize = 2;
    const PATH_MAX: usize = 4096;

    extern "C" fn start(_argc: i32, argv: *const *const c_char, envp: *const *const c_char) {
        if wrinkle::cpu::build_runs_here() {
            return;
        }
        let mut path = std::mem::MaybeUninit::<[u8; PATH_MAX]>::uninit();
        let path = path.as_mut_ptr().cast::<u8>();
        // SAFETY: the system calls get a buffer of PATH_MAX bytes, a NUL-terminated path in it and the
        // argument and environment vectors glibc passed; every byte access stays below PATH_MAX.
        unsafe {
            let exe = b"/proc/self/exe\0";
            let len = syscall3(SYS_READLINK, exe.as_ptr() as usize, path as usize, PATH_MAX);
            let name = PORTABLE.as_bytes();
            if len <= 0 || len as usize + name.len() + 1 >= PATH_MAX {
                explain(b"and its own path could not be read\n");
            }
            // The file name starts after the last '/'; the portable build is not to hand over to itself (a
            // copy of this build installed under its name).
            let mut start = 0;
            for k in 0..len as usize {
                if read_volatile(path.add(k)) == b'/' {
                    start = k + 1;
                }
            }
            let mut own_name_is_portable = len as usize - start == name.len();
            for (k, &b) in name.iter().enumerate() {
                own_name_is_portable &= start + k < len as usize && read_volatile(path.add(start + k)) == b;
                write_volatile(path.add(start + k), b);
            }
            write_volatile(path.add(start + name.len()), 0);
            if own_name_is_portable {
                explain(
                    b"and it is itself installed as the portable build: build the portable one with \
scripts/build-portable.sh\n",
                );
            }
            // Returns only when the portable build could not be started.
            let error = -syscall3(SYS_EXECVE, path as usize, argv as usize, envp as usize);
            if error == ENOENT {
                explain(
                    b"and there is no wrinkle-portable beside it: build the portable one with \
scripts/build-portable.sh\n",
                );
            }
            explain(b"and the wrinkle-portable beside it could not be started\n");
        }
    }

    /// Writes the message, `what_then` ending it, to the standard error and exits with status 1.
    fn explain(what_then: &[u8]) -> ! {
        let head: &[u8] = b"error: this build of wrinkle needs an x86-64-v3 CPU (AVX2, FMA, BMI2: Intel Haswell, \
AMD Excavator or later), which this one is not, ";
        // SAFETY: writes of static byte strings to descriptor 2, then the process ends.
        unsafe {
            syscall3(SYS_WRITE, 2, head.as_ptr() as usize, head.len());
            syscall3(SYS_WRITE, 2, what_then.as_ptr() as usize, what_then.len());
            syscall3(SYS_EXIT_GROUP, 1, 0, 0);
        }
        unreachable!("exit_group returned")
    }

    /// A Linux system call with three arguments; the result, or minus the error number.
    unsafe fn syscall3(number: usize, a: usize, b: usize, c: usize) -> isize {
        let result: isize;
        // SAFETY: the caller passes arguments valid for the call; the kernel clobbers rcx and r11.
        unsafe {
            std::arch::asm!(
                "syscall",
                inlateout("rax") number as isize => result,
                in("rdi") a, in("rsi") b, in("rdx") c,
                lateout("rcx") _, lateout("r11") _,
                options(nostack),
            );
        }
        result
    }
}
