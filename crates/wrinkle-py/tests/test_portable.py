"""The portable module (baseline x86-64, for CPUs without AVX2) gives the x86-64-v3 module's results bit for
bit, is the one the package loads on a CPU without AVX2 (qemu-user emulating a Sandy Bridge: AVX, no AVX2 or
FMA), and is chosen by WRINKLE_BUILD=portable on any CPU. (NumPy 2.4's wheels need x86-64-v2 as NumPy counts it,
more than qemu's Westmere model offers: NumPy itself stops there. The CLI's test runs on the Westmere.)"""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import wrinkle

WORKLOAD = Path(__file__).parent / "portable" / "workload.py"
# Heights from normals go through rustfft, which picks its butterflies (AVX, SSE4.1 or scalar) by the CPU
# it finds: equal on one CPU, within rounding between CPUs.
FFT_BY_CPU = {"heights"}

pytestmark = pytest.mark.skipif(
    os.environ.get("WRINKLE_PORTABLE_STAGED") != "1" and not os.environ.get("CI"),
    reason="the portable module was not built in this run",
)


def run_workload(tmp_path, name, prefix=(), **env):
    out = tmp_path / f"{name}.npz"
    p = subprocess.run(
        [*prefix, sys.executable, str(WORKLOAD), str(out)], env={**os.environ, **env}, capture_output=True, text=True
    )
    assert p.returncode == 0, p.stderr
    return np.load(out)


def assert_same_bits(a, b, exempt=()):
    assert sorted(a.files) == sorted(b.files)
    for k in a.files:
        if k == "build":
            continue
        assert a[k].dtype == b[k].dtype and a[k].shape == b[k].shape, k
        if k in exempt:
            np.testing.assert_allclose(a[k], b[k], rtol=0, atol=1e-5 * float(np.ptp(a[k])), err_msg=k)
        else:
            assert a[k].tobytes() == b[k].tobytes(), f"{k}: the builds differ"


def test_this_cpu_loads_the_x86_64_v3_module():
    if not wrinkle._wrinkle.cpu_runs_x86_64_v3():
        pytest.skip("this CPU lacks AVX2")
    assert wrinkle.build_level == "x86-64-v3"


def test_the_portable_module_gives_the_same_bits(tmp_path):
    native = run_workload(tmp_path, "native")
    portable = run_workload(tmp_path, "portable", WRINKLE_BUILD="portable")
    assert str(portable["build"]) == "x86-64"
    assert_same_bits(native, portable)


def test_a_cpu_without_avx2_loads_the_portable_module(tmp_path):
    if shutil.which("qemu-x86_64") is None:
        assert not os.environ.get("CI"), "CI must install qemu-user for this test"
        pytest.skip("qemu-x86_64 not found")
    native = run_workload(tmp_path, "native")
    old = run_workload(tmp_path, "sandybridge", prefix=("qemu-x86_64", "-cpu", "SandyBridge"))
    assert str(old["build"]) == "x86-64"
    assert_same_bits(native, old, exempt=FFT_BY_CPU)


def test_the_wheel_and_the_build_script_name_the_module_the_package_loads(repo):
    """One wheel carries both modules only where pyproject.toml's maturin `include` names the file that
    scripts/build-portable.sh writes, under the name the package imports. (Building the wheel here would
    compile the workspace again under another feature set: tried by hand, docs/python.md.)"""
    module = "python/wrinkle/_wrinkle_portable.abi3.so"
    assert f'path = "{module}", format = "wheel"' in (repo / "crates/wrinkle-py/pyproject.toml").read_text()
    assert f"crates/wrinkle-py/{module}" in (repo / "scripts/build-portable.sh").read_text()
    assert '"wrinkle._wrinkle_portable"' in (repo / "crates/wrinkle-py/python/wrinkle/_cpu.py").read_text()


def test_a_wrong_build_name_is_refused():
    p = subprocess.run(
        [sys.executable, "-c", "import wrinkle"], env={**os.environ, "WRINKLE_BUILD": "avx512"}, capture_output=True,
        text=True,
    )
    assert p.returncode != 0
    assert "WRINKLE_BUILD must be 'portable' or unset, got 'avx512'" in p.stderr
