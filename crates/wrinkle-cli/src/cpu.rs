//! The CPU check that runs before anything else: the binary is built for x86-64-v3 (.cargo/config.toml),
//! and on an older CPU its first AVX2 instruction would kill it with SIGILL and no word of why.
//!
//! Both functions stay scalar on purpose: with AVX enabled, LLVM moves even 16-byte values with VEX
//! instructions, which a CPU without AVX cannot run. So they test feature bits, write one static message
//! through the standard library (built for baseline x86-64) and exit.

/// Whether this CPU (and its operating system, which must save the wide registers) runs what x86-64-v3
/// code may use. CPUID is asked directly: `is_x86_feature_detected!` answers `true` at compile time for
/// every feature the build enables, which is exactly what must not be assumed here.
#[inline(never)]
pub fn supported() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__cpuid, __cpuid_count, _xgetbv};
        let bit = |word: u32, n: u32| word >> n & 1 == 1;
        // SAFETY: CPUID exists on every x86-64 CPU; leaf 7 and 0x8000_0001 are asked only where the highest
        // leaves say they exist; XGETBV only where CPUID says the OS enabled it (OSXSAVE).
        unsafe {
            let basic = __cpuid(0);
            let extended = __cpuid(0x8000_0000);
            if basic.eax < 7 || extended.eax < 0x8000_0001 {
                return false;
            }
            let leaf1 = __cpuid(1).ecx;
            let leaf7 = __cpuid_count(7, 0).ebx;
            let ext1 = __cpuid(0x8000_0001).ecx;
            // FMA 12, MOVBE 22, OSXSAVE 27, AVX 28, F16C 29; BMI1 3, AVX2 5, BMI2 8; LZCNT 5.
            let features = [12, 22, 27, 28, 29].iter().all(|&n| bit(leaf1, n))
                && [3, 5, 8].iter().all(|&n| bit(leaf7, n))
                && bit(ext1, 5);
            // The OS saves SSE (bit 1) and AVX (bit 2) state on a context switch.
            features && _xgetbv(0) & 0b110 == 0b110
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        true
    }
}

#[inline(never)]
pub fn explain_and_exit() -> ! {
    use std::io::Write;
    const MESSAGE: &[u8] = b"error: this build of wrinkle needs an x86-64-v3 CPU (AVX2, FMA, BMI2: Intel Haswell, \
AMD Excavator or later), and this CPU lacks them; build it for this machine with \
RUSTFLAGS=\"-C target-cpu=native\" cargo build --release\n";
    let _ = std::io::stderr().write_all(MESSAGE);
    std::process::exit(1)
}
