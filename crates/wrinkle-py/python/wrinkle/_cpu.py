"""Chooses the extension module this CPU runs, before any other part of the package loads it.

The default module is built for x86-64-v3 (AVX2, FMA, BMI2; .cargo/config.toml): on an older CPU its
first such instruction would kill the interpreter with SIGILL and no word of why. An installation made
after scripts/build-portable.sh also holds a portable module (wrinkle._wrinkle_portable, baseline x86-64,
the same bits out); it asks the CPU itself (CPUID) and the package loads the module the CPU runs. Without the
portable module the CPU's features are read from /proc/cpuinfo (Linux), and an older CPU gets ImportError.

WRINKLE_BUILD=portable in the environment loads the portable module on any CPU."""

from __future__ import annotations

import importlib
import os
import platform
import sys
from types import ModuleType
from typing import List, Optional

# x86-64-v3 as /proc/cpuinfo names its features ("abm" is LZCNT).
NEEDED = ("avx", "avx2", "bmi1", "bmi2", "f16c", "fma", "movbe", "abm", "xsave")

BUILD_PORTABLE = "scripts/build-portable.sh, then pip install ./crates/wrinkle-py again"


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
    """ImportError when /proc/cpuinfo says the CPU lacks what x86-64-v3 code uses."""
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
            f"and this CPU lacks {', '.join(missing)}; add the portable module with {BUILD_PORTABLE}"
        )


def _portable() -> Optional[ModuleType]:
    try:
        return importlib.import_module("wrinkle._wrinkle_portable")
    except ImportError:
        return None


def load() -> ModuleType:
    """The extension module for this CPU, registered as `wrinkle._wrinkle` for the rest of the package."""
    forced = os.environ.get("WRINKLE_BUILD", "")
    if forced not in ("", "portable"):
        raise ImportError(f"WRINKLE_BUILD must be 'portable' or unset, got {forced!r}")
    portable = _portable()
    if portable is not None and (forced == "portable" or not portable.cpu_runs_x86_64_v3()):
        module = portable
    elif forced == "portable":
        raise ImportError(f"WRINKLE_BUILD=portable, but this installation has no portable module: run {BUILD_PORTABLE}")
    else:
        if portable is None:
            check()
        module = importlib.import_module("wrinkle._wrinkle")
    sys.modules["wrinkle._wrinkle"] = module
    return module
