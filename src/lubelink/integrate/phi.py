"""The phi-functions of a damped oscillator's 2x2 block, for exponential integrators.

``phi_0(z) = exp(z)``, ``phi_(k+1)(z) = (phi_k(z) - 1/k!) / z`` (``phi_k(0) = 1/k!``), of the matrix
``M = c h [[0, 1], [-omega^2, -2 zeta omega]]`` (used by :mod:`.exponential`, which holds the tables).

For this ``M``, with eigenvalues ``l1, l2 = c h omega (-zeta +- sqrt(zeta^2 - 1))``, any
analytic ``f`` gives ``f(M) = a I + b M`` with ``b = (f(l1) - f(l2)) / (l1 - l2)`` and
``a = f(l1) - b l1`` (Cayley-Hamilton), real for the conjugate eigenvalues of an underdamped
block. Near a double eigenvalue (critical damping, ``omega = 0``) the divided difference is
replaced by ``f'(mu) = phi_k(mu) - k phi_{k+1}(mu)`` at the mean eigenvalue. ``phi_k(z)`` is
summed as a series for ``|z| < 1`` and from ``exp(z)`` by ``phi_{k+1} = (phi_k - 1/k!) / z``
otherwise, so small and large ``h omega`` are both accurate.
"""

import math

import numpy as np

from lubelink._jit import jitable

__all__ = ["phi_functions", "phi_block"]

_INV_FACTORIAL = tuple(1.0 / math.factorial(k) for k in range(7))

#: ``1 / (j + 5)!``, j = 0..16: the series of ``phi_5``; for ``|z| < 1`` its remainder is below ``1 / 22! < 1e-21``.
_SERIES5 = tuple(1.0 / math.factorial(j + 5) for j in range(17))
#: ``1 / (j + 7)!``, j = 0..16: the series of ``phi_7``, the same way.
_SERIES7 = tuple(1.0 / math.factorial(j + 7) for j in range(17))


@jitable
def phi_functions(z):
    """``(phi_0(z), ..., phi_7(z))`` for complex ``z``.

    For ``|z| < 1`` ``phi_5`` and ``phi_7`` are summed as their series (Horner), ``phi_4 .. phi_0``
    follow downwards from ``phi_5`` and ``phi_6`` from ``phi_7`` (``phi_k = z phi_{k+1} + 1/k!``,
    stable there); otherwise ``phi_0 = exp(z)`` and upwards (``phi_{k+1} = (phi_k - 1/k!) / z``,
    stable for ``|z| >= 1``). (``phi_0 .. phi_5`` are the same numbers whether or not a caller
    uses the two highest: the fourth-order methods need ``phi_0 .. phi_4``, the sixth-order Adams
    method ``phi_0 .. phi_6``, a double eigenvalue one more.)
    """
    if z.real * z.real + z.imag * z.imag < 1.0:
        p5 = 0.0 + 0.0j
        p7 = 0.0 + 0.0j
        for j in range(16, -1, -1):
            p5 = p5 * z + _SERIES5[j]
            p7 = p7 * z + _SERIES7[j]
        p6 = z * p7 + _INV_FACTORIAL[6]
        p4 = z * p5 + _INV_FACTORIAL[4]
        p3 = z * p4 + _INV_FACTORIAL[3]
        p2 = z * p3 + _INV_FACTORIAL[2]
        p1 = z * p2 + 1.0
        p0 = z * p1 + 1.0
        return p0, p1, p2, p3, p4, p5, p6, p7
    w = 1.0 / z
    p0 = np.exp(z)
    p1 = (p0 - 1.0) * w
    p2 = (p1 - 1.0) * w
    p3 = (p2 - _INV_FACTORIAL[2]) * w
    p4 = (p3 - _INV_FACTORIAL[3]) * w
    p5 = (p4 - _INV_FACTORIAL[4]) * w
    p6 = (p5 - _INV_FACTORIAL[5]) * w
    p7 = (p6 - _INV_FACTORIAL[6]) * w
    return p0, p1, p2, p3, p4, p5, p6, p7


@jitable
def phi_block(omega, zeta, ch, out_a, out_b):
    """``phi_k(M) = a_k I + b_k M`` for ``M = ch [[0, 1], [-omega^2, -2 zeta omega]]``, ``k < out_a.size <= 7``."""
    K = out_a.shape[0]
    r = np.sqrt(complex(zeta * zeta - 1.0))
    l1 = ch * omega * (-zeta + r)
    l2 = ch * omega * (-zeta - r)
    if abs(l1 - l2) > 1e-7 * max(1.0, abs(l1)):
        f1 = phi_functions(l1)
        if zeta < 1.0:  # conjugate eigenvalues of a real matrix: phi_k(l2) = conj(phi_k(l1)), b = Im / Im
            inv = 1.0 / l1.imag
            for k in range(K):
                b = f1[k].imag * inv
                out_b[k] = b
                out_a[k] = f1[k].real - b * l1.real
            return
        f2 = phi_functions(l2)
        for k in range(K):
            b = (f1[k] - f2[k]) / (l1 - l2)
            out_b[k] = b.real
            out_a[k] = (f1[k] - b * l1).real
        return
    mu = 0.5 * (l1 + l2)
    f1 = phi_functions(mu)
    for k in range(K):
        d = f1[k] - k * f1[k + 1]  # phi_k' = phi_k - k phi_{k+1}
        out_b[k] = d.real
        out_a[k] = (f1[k] - d * mu).real
