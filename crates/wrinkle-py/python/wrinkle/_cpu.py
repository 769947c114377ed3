"""The CPU check made before the extension module loads: the module is built for x86-64-v3 (AVX2, FMA,
BMI2; .cargo/config.toml), and on an older CPU its first such instruction would kill the interpreter with
SIGILL and no word of why. This reads the CPU's features from /proc/cpuinfo (Linux) and raises ImportError
instead; elsewhere it trusts the CPU."""

from __future__ import annotations

import platform
from typing import List

# x86-64-v3 as /proc/cpuinfo names its features ("abm" is LZCNT).
NEEDED = ("avx", "avx2", "bmi1", "bmi2", "f16c", "fma", "movbe", "abm", "xsave")


def missing_features(cpuinfo: str) -> List[str]:
    """The features of x86-64-v3 that the first processor in `cpuinfo` lacks (empty when none, or when
    the text names no features)."""
    for line in cpuinfo.splitlines():
        key, _, value = line.partition(":")
        if key.strip() == "flags":
            have = set(value.split())
            return [f for f in NEEDED if f not in have]
    return []


def check() -> None:
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as f:
            text = f.read()
    except OSError:
        return
    missing = missing_features(text)
    if missing:
        raise ImportError(
            "this build of wrinkle needs an x86-64-v3 CPU (AVX2, FMA, BMI2: Intel Haswell, AMD Excavator or later) "
            f"and this CPU lacks {', '.join(missing)}; build it for this machine with "
            'RUSTFLAGS="-C target-cpu=native" pip install ./crates/wrinkle-py'
        )
