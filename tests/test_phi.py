"""The phi-functions of a 2x2 oscillator block against the matrix exponential of an augmented matrix
(``phi_k(M)`` is a block of ``expm([[M, I, 0], [0, 0, I], ...])``, Saad 1992), for small and large
``h omega``, undamped, damped, critically damped and overdamped, and a rigid mode."""

import numpy as np
import pytest
from scipy.linalg import expm

from lubelink.integrate.phi import phi_block


def phi_reference(M, k):
    """``phi_k(M)`` from the exponential of the augmented matrix ``[[M, I, 0..], [0, 0, I..], ..., 0]``."""
    n = M.shape[0]
    big = np.zeros((n * (k + 1), n * (k + 1)))
    big[:n, :n] = M
    for j in range(k):
        big[n * j:n * (j + 1), n * (j + 1):n * (j + 2)] = np.eye(n) if j == 0 else 0.0
    for j in range(1, k):
        big[n * j:n * (j + 1), n * (j + 1):n * (j + 2)] = np.eye(n)
    return expm(big)[:n, n * k:n * (k + 1)] if k else expm(M)


@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.7, 1.0, 2.5])
@pytest.mark.parametrize("h_omega", [1e-6, 0.3, 0.999, 1.001, 2.0, 40.0])
def test_phi_functions_of_a_block_against_the_augmented_exponential(zeta, h_omega):
    omega = 150.0
    ch = h_omega / omega
    A = np.array([[0.0, 1.0], [-omega**2, -2 * zeta * omega]])
    a, b = np.empty(7), np.empty(7)  # phi_0 .. phi_6: the sixth-order Adams method's
    phi_block(omega, zeta, ch, a, b)
    for k in range(7):
        got = a[k] * np.eye(2) + b[k] * ch * A
        want = phi_reference(ch * A, k)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-13 * max(1.0, np.abs(want).max()))


def test_phi_functions_of_a_rigid_mode():
    """``omega = 0``: the block is nilpotent, ``phi_k(M) = I/k! + M/(k+1)!``."""
    a, b = np.empty(7), np.empty(7)
    phi_block(0.0, 0.0, 0.01, a, b)
    fact = [1, 1, 2, 6, 24, 120, 720, 5040]
    np.testing.assert_allclose(a, [1 / fact[k] for k in range(7)], rtol=1e-15)
