"""Print the NPY_DISABLE_CPU_FEATURES value that switches off numpy's widest SIMD level on this CPU.

Another CPU rounds differently: numpy dispatches its kernels by the CPU's SIMD level (AVX-512
against AVX2 on x86-64), and sums and reductions then round in another order. CI runs the fast
suite a second time with this level off, so a test that assumed one rounding path fails here
and not on a user's machine. Prints nothing where numpy dispatches no such level.
"""
try:  # numpy >= 2
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
except ImportError:  # numpy 1.x
    from numpy.core._multiarray_umath import __cpu_dispatch__, __cpu_features__

found = [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]
if "X86_V4" in found:  # AVX-512 and the levels built on it
    print(" ".join(f for f in found if f == "X86_V4" or f.startswith("AVX512")))
elif "X86_V3" in found:  # AVX2
    print("X86_V3")
