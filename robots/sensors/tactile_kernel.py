"""Compiled tactile image of a sphere pressed on the array (thesis §2.3.2, Fig. 2.14).

:func:`sphere_image_add` is :meth:`robots.sensors.TactileArray.sphere_images` for one
contact, compiled with numba (the simulator computes one image per controller call: the
NumPy version cost ~170 us of array dispatch, this one ~5 us). It performs the reference's
floating-point operations in the reference's order, so the two images are equal to the bit
on this machine (tested on random centres, radii and forces in
``tests/test_gait_speed_tactile.py``):

* the Hertz contact radius ``a = cbrt(3 F R / (4 E*))`` and peak ``p0 = 3 F / (2 pi a^2)``;
* the sub-taxel samples ``p0 sqrt(max(1 - r^2/a^2, 0))``;
* the force-conserving rescale of ``TactileArray._conserve``, whose total is NumPy's
  pairwise sum (:func:`pairwise_sum`: NumPy's reduction of a contiguous block - 8
  accumulators, blocks of 128 - reproduced, so the totals match bitwise);
* the blur ``Bv @ P @ Bu^T`` by ``np.dot`` (BLAS ``dgemm`` as NumPy's ``@``; equal
  results need the same BLAS kernel - OpenBLAS here; elsewhere the images agree to ~1e-15
  relative) and the threshold.

The reference stays :meth:`TactileArray.sphere_images` (vectorized over contacts, with the
argument checks); this kernel checks nothing (the caller's inputs are valid by construction).
"""

from __future__ import annotations

import math

import numpy as np

from planner.jit import njit

__all__ = ["pairwise_sum", "sphere_image_add"]

#: NumPy's pairwise-summation block (``PW_BLOCKSIZE`` of its reduction loops)
_BLOCK = 128


@njit(cache=True)
def _block_sum(a, lo, n):  # pragma: no cover (compiled)
    """NumPy's sum of one block ``a[lo:lo+n]``, ``n <= 128``: 8 accumulators."""
    if n < 8:
        res = 0.0
        for i in range(lo, lo + n):
            res += a[i]
        return res
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    i = 8
    m = n - n % 8
    while i < m:
        j = lo + i
        r0 += a[j]
        r1 += a[j + 1]
        r2 += a[j + 2]
        r3 += a[j + 3]
        r4 += a[j + 4]
        r5 += a[j + 5]
        r6 += a[j + 6]
        r7 += a[j + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@njit(cache=True)
def pairwise_sum(a, lo, n):  # pragma: no cover (compiled)
    """Sum of ``a[lo:lo+n]`` (1-D) in NumPy's pairwise order (``np.add.reduce``): halves
    (rounded down to multiples of 8) summed separately down to blocks of <= 128.

    Iterative (a post-order walk of the halving tree with explicit stacks): numba's cache
    of a self-recursive function crashed when loaded in a new process.
    """
    if n <= _BLOCK:
        return _block_sum(a, lo, n)
    los = np.empty(64, np.int64)
    ns = np.empty(64, np.int64)
    phase = np.empty(64, np.int64)
    vals = np.empty(64)
    los[0], ns[0], phase[0] = lo, n, 0
    top, nv = 1, 0
    while top > 0:
        t = top - 1
        m = ns[t]
        if m <= _BLOCK:
            vals[nv] = _block_sum(a, los[t], m)
            nv += 1
            top -= 1
            continue
        n2 = m // 2
        n2 -= n2 % 8
        if phase[t] == 0:  # the left half first
            phase[t] = 1
            los[top], ns[top], phase[top] = los[t], n2, 0
            top += 1
        elif phase[t] == 1:  # then the right half
            phase[t] = 2
            los[top], ns[top], phase[top] = los[t] + n2, m - n2, 0
            top += 1
        else:  # left + right
            vals[nv - 2] = vals[nv - 2] + vals[nv - 1]
            nv -= 1
            top -= 1
    return vals[0]


@njit(cache=True)
def sphere_image_add(
    img, cu, cv, radius, force, fu, fv, Bv, BuT, modulus, cell, threshold
):  # pragma: no cover (compiled)
    """Add the image of a sphere pressed on the pad to ``img`` [Pa].

    Args:
        img: (rows, cols) image the contact's thresholded image is added to [Pa].
        cu, cv: contact centre on the pad [m]; radius: sphere radius R > 0 [m];
            force: normal force F >= 0 [N].
        fu, fv: (U,), (V,) sub-taxel sample points [m]; Bv: (rows, V) and BuT: (U, cols)
            average-and-spread matrices; modulus: E* [Pa]; cell: sub-taxel area [m^2];
            threshold: [Pa] (the :class:`TactileArray`'s ``_fv``, ``_fu``, ``_Bv``,
            ``_BuT``, ``modulus``, ``(pitch/oversample)**2``, ``threshold``).
    """
    if force == 0.0:  # the reference's image is exactly zero
        return
    a = np.cbrt(3.0 * force * radius / (4.0 * modulus))
    a_safe = a if a > 0 else 1.0
    p0 = 3.0 * force / (2.0 * np.pi * (a_safe * a_safe)) if a > 0 else 0.0
    nv, nu = fv.shape[0], fu.shape[0]
    P = np.empty((nv, nu))
    flat = P.reshape(nv * nu)
    for i in range(nv):
        dv = (fv[i] - cv) / a_safe
        for j in range(nu):
            du = (fu[j] - cu) / a_safe
            P[i, j] = p0 * math.sqrt(max(1.0 - (dv * dv + du * du), 0.0))
    tot = (0.0 + pairwise_sum(flat, 0, nv * nu)) * cell
    scale = force / tot if tot > 0 else 0.0
    for k in range(nv * nu):
        flat[k] = flat[k] * scale
    if tot <= 0 and force > 0:  # smaller than a sub-cell: all of F in the nearest one
        iu, iv = 0, 0
        for j in range(nu):
            if abs(fu[j] - cu) < abs(fu[iu] - cu):
                iu = j
        for i in range(nv):
            if abs(fv[i] - cv) < abs(fv[iv] - cv):
                iv = i
        P[iv, iu] = force / cell
    out = np.dot(np.dot(Bv, P), BuT)
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            v = out[i, j]
            img[i, j] += 0.0 if v < threshold else v
