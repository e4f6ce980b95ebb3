"""Independent reference: finite-difference method of lines for the link PDE.

Solves, with no use of lubelink's modal machinery,

    EI u'''' + rho A u_tt - rho A omega(t)^2 u = -rho A (A_O2(t) + alpha(t) x),   0 < x < L,

pinned at both ends (u = u'' = 0 at x = 0 and x = L), from rest (u = u_t = 0).
Space: nodes x_i = i h, h = L / n_el; the unknowns are the interior nodes
i = 1 .. n_el - 1; u'''' by the 5-point stencil (1, -4, 6, -4, 1) / h^4 with
ghost nodes from u'' = 0 at the ends (u_{-1} = -u_1, u_{n_el+1} = -u_{n_el-1}).
The scheme is second-order accurate in h. Time: scipy's ``solve_ivp``
on the first-order system (u, u_t) with tight tolerances, so the error left is
the spatial O(h^2) one.

This is docs/model.md §1.3's transverse equation, written directly (the
reference for "an independent solution of the beam PDE ... converging as the
mesh is refined").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["FDSolution", "fourth_difference", "solve_fd"]


def fourth_difference(n_el, h):
    """Dense ``(n_el - 1, n_el - 1)`` matrix of d^4/dx^4 with pinned-end ghost nodes."""
    n = n_el - 1
    if n < 3:
        raise ValueError("need at least 4 elements")
    D = np.zeros((n, n))
    stencil = (1.0, -4.0, 6.0, -4.0, 1.0)
    for i in range(n):
        for k, c in zip(range(i - 2, i + 3), stencil):
            if 0 <= k < n:
                D[i, k] += c
            elif k == -1 or k == n:
                pass  # the pinned end node itself: u = 0
            elif k == -2:
                D[i, 0] -= c  # ghost u_{-1} = -u_1
            elif k == n + 1:
                D[i, n - 1] -= c  # ghost u_{n_el+1} = -u_{n_el-1}
    return D / h**4


@dataclass
class FDSolution:
    t: np.ndarray  # (T,)
    x: np.ndarray  # (n_el + 1,) nodes, ends included
    u: np.ndarray  # (T, n_el + 1) deflection, zero at the ends
    nfev: int

    def at(self, x):
        """Deflection history at a node (x must coincide with a node)."""
        i = int(round(x / (self.x[1] - self.x[0])))
        if not np.isclose(self.x[i], x, rtol=0, atol=1e-12):
            raise ValueError(f"x = {x} is not a node of the {len(self.x) - 1}-element grid")
        return self.u[:, i]


def solve_fd(n_el, *, EI, rho_A, L, motion, t_eval, method="LSODA", rtol=1e-9, atol=1e-14):
    """Integrate the pinned-pinned link PDE by finite differences from rest.

    Parameters
    ----------
    n_el : int
        Number of elements (grid intervals).
    EI, rho_A, L : float
        Bending stiffness [N m^2], mass per length [kg/m], length [m].
    motion : callable
        ``motion(t) -> (A_O2, omega, alpha)`` at a scalar time [s]: transverse
        acceleration of the end x = 0 [m/s^2], angular velocity [rad/s] and
        angular acceleration [rad/s^2] of the chord.
    t_eval : array_like
        Output times, starting at the initial time.
    method : str
        A ``solve_ivp`` method. The semi-discrete system is stiff (its highest
        frequency grows as 4 sqrt(EI/rho A)/h^2, ~1e5 rad/s at 40 elements),
        so a stiff-capable method with the exact Jacobian is the default (LSODA,
        the fastest here; Radau and BDF give the same answer).
    """
    h = L / n_el
    x = np.linspace(0.0, L, n_el + 1)
    xi = x[1:-1]
    K = -(EI / rho_A) * fourth_difference(n_el, h)
    n = n_el - 1
    t_eval = np.asarray(t_eval, dtype=float)

    def rhs(t, y):
        A_O2, omega, alpha = motion(t)
        u, v = y[:n], y[n:]
        acc = K @ u + omega**2 * u - (A_O2 + alpha * xi)
        return np.concatenate([v, acc])

    J = np.zeros((2 * n, 2 * n))
    J[:n, n:] = np.eye(n)
    J[n:, :n] = K
    diag = np.arange(n, 2 * n), np.arange(n)

    def jac(t, y):
        Jt = J.copy()
        Jt[diag] += motion(t)[1] ** 2
        return Jt

    kwargs = {"jac": jac} if method in ("Radau", "BDF", "LSODA") else {}
    sol = solve_ivp(rhs, (t_eval[0], t_eval[-1]), np.zeros(2 * n), method=method, t_eval=t_eval,
                    rtol=rtol, atol=atol, **kwargs)
    if not sol.success:
        raise RuntimeError(sol.message)
    u = np.zeros((t_eval.size, n_el + 1))
    u[:, 1:-1] = sol.y[:n].T
    return FDSolution(t=sol.t, x=x, u=u, nfev=sol.nfev)
