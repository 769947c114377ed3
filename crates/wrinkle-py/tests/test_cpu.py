"""The import-time CPU check: a CPU without AVX2 gets ImportError naming what it lacks, not SIGILL."""

from wrinkle._cpu import NEEDED, missing_features

HASWELL = "processor : 0\nflags : fpu sse sse2 ssse3 fma cx16 sse4_1 sse4_2 movbe popcnt xsave avx f16c abm bmi1 avx2 bmi2\n"
WESTMERE = "processor : 0\nflags : fpu sse sse2 ssse3 cx16 sse4_1 sse4_2 popcnt aes\n"


def test_a_v3_cpu_passes():
    assert missing_features(HASWELL) == []


def test_an_older_cpu_is_named_what_it_lacks():
    assert missing_features(WESTMERE) == list(NEEDED)
    assert missing_features(HASWELL.replace(" avx2", "")) == ["avx2"]


def test_text_without_flags_is_trusted():
    assert missing_features("processor : 0\n") == []
