"""The extension module built for baseline x86-64 (scripts/build-portable.sh puts `_wrinkle` here), for CPUs
without AVX2; wrinkle._cpu loads it where the CPU needs it."""
