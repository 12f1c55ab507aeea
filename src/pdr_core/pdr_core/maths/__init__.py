"""Attitude, angles, small matrices and gates, and the compiled kernels' cache.

Modules:
    rotations     Attitude conventions (ENU/FLU, ZYX Euler), conversions, the tilt from
                  specific force.
    angles        The angle wrap (plain and compiled), the axial wrap, the circular mean.
    small_matrix  Compiled (numba) kernels for 3 × 3 rotations and small symmetric
                  positive-definite matrices.
    lowpass       The gain of a first-order low-pass, spelled once for every kernel.
    chi2          χ² gate limits, shared by every gate of the project (Bar-Shalom et al.
                  2001, Section 5.4).
    kernel_cache  Keeps numba's on-disk cache valid when a kernel's callee in another
                  module changes, and says when kernels are being compiled.
"""
