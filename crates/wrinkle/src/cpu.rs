//! Which instruction set this build was made for, and whether this CPU runs it. The default build targets
//! x86-64-v3 (AVX2, FMA, BMI2; .cargo/config.toml); the portable build (scripts/build-portable.sh) baseline
//! x86-64. Both give the same bits (lanes::math); the front ends start the portable one on an older CPU.

/// Whether the code was compiled for x86-64-v3 (the default build on x86-64).
const BUILT_FOR_X86_64_V3: bool = cfg!(all(target_arch = "x86_64", target_feature = "avx2"));

/// The instruction set the code was compiled for: "x86-64-v3", "x86-64" or the architecture's name.
pub const BUILD_LEVEL: &str = if BUILT_FOR_X86_64_V3 {
    "x86-64-v3"
} else if cfg!(target_arch = "x86_64") {
    "x86-64"
} else {
    std::env::consts::ARCH
};

/// Whether this CPU (and its operating system, which must save the wide registers) runs what x86-64-v3
/// code may use. CPUID is asked directly: `is_x86_feature_detected!` answers `true` at compile time for
/// every feature the build enables, which is exactly what must not be assumed here.
///
/// Scalar on purpose, and never inlined: an x86-64-v3 build calls it before any other code runs, on a CPU
/// that may lack AVX, and with AVX enabled LLVM moves even 16-byte values with VEX instructions.
#[inline(never)]
pub fn runs_x86_64_v3() -> bool {
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
        false
    }
}

/// Whether this build can run here: a build for x86-64-v3 needs such a CPU; any other build runs anywhere
/// its architecture does.
#[inline(never)]
pub fn build_runs_here() -> bool {
    !BUILT_FOR_X86_64_V3 || runs_x86_64_v3()
}

/// Whether this CPU is AMD's (CPUID's vendor string): the texture lanes decode sRGB by arithmetic there,
/// where gathers issue slowly (`texture::rgba8`).
pub fn is_amd() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        let vendor = std::arch::x86_64::__cpuid(0);
        // "AuthenticAMD" in EBX, EDX, ECX.
        [vendor.ebx, vendor.edx, vendor.ecx] == [0x6874_7541, 0x6974_6E65, 0x444D_4163]
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn this_machine_runs_this_build() {
        // The tests themselves run, so the CPU runs the build; the check must agree.
        assert!(super::build_runs_here());
        assert!(["x86-64-v3", "x86-64"].contains(&super::BUILD_LEVEL) || !cfg!(target_arch = "x86_64"));
    }
}
