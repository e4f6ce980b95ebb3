"""Independent reference: the slider-crank with a flywheel and an elastic link, one system of equations.

A monolithic model of the mechanism lubelink couples by relaxation (lubelink.coupling), written with no
use of lubelink's kinematics, modal loads or drive: the generalised coordinates are the crank angle and
the link's sine-mode amplitudes, ``Q = (phi, q_1 .. q_N)``, and the positions are typed here:

    crank pin  O = OA (cos phi, sin phi),   sin theta = (OA / L) sin phi,
    link axis  i = (cos theta, -sin theta),  j = (sin theta, cos theta),
    link point r(x) = O + x i + u(x) j,  u = sum_n q_n sin(n pi x / L),   slider X_C = OA cos phi + L cos theta.

Lagrange's equations, ``M(Q) Q_dd = F - sum_b m_b J_b^T gamma_b``, with the kinetic energy of the flywheel
``J_f phi_d^2 / 2``, of the link ``int rho A |r_dot|^2 / 2 dx`` (Gauss-Legendre in x) and of the slider
``m_s X_C_dot^2 / 2``; ``J = dr/dQ`` and ``gamma = d(J)/dt Q_d``, the part of the acceleration not in ``Q_dd``
(written out by hand below, checked against second differences of the positions in the test). The strain
energy is the bending energy ``EI/2 int u''^2 dx = sum_n (rho A L / 4) omega_n^2 q_n^2``, the modal damping
``2 zeta omega_n`` per unit modal mass, the generalised forces those of a constant motor torque and a
constant force on the slider along +X. The positions are exact (no linearisation in ``q``): the model
differs from lubelink's linear link by terms of second order in ``u / L``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["Mechanism", "positions", "jacobian_and_gamma", "rates", "solve"]


@dataclass(frozen=True)
class Mechanism:
    crank_length: float
    rod_length: float
    flywheel: float
    mass_per_length: float  # rho A [kg/m]
    bending_stiffness: float  # EI [N m^2]
    modes: int
    damping_ratio: float = 0.0
    slider_mass: float = 0.0
    slider_force: float = 0.0
    torque: float = 0.0
    nodes: int = 24

    @property
    def omega_n(self):
        beta = np.arange(1, self.modes + 1) * np.pi / self.rod_length
        return beta * beta * np.sqrt(self.bending_stiffness / self.mass_per_length)


def _theta(phi, mech):
    lam = mech.crank_length / mech.rod_length
    root = np.sqrt(1.0 - (lam * np.sin(phi)) ** 2)
    theta = np.arcsin(lam * np.sin(phi))
    d1 = lam * np.cos(phi) / root
    d2 = -lam * (1.0 - lam * lam) * np.sin(phi) / root ** 3
    return theta, d1, d2


def _shapes(x, mech):
    return np.sin(np.outer(x, np.arange(1, mech.modes + 1) * np.pi / mech.rod_length))  # (K, N)


def positions(Q, x, mech):
    """``(r (K, 2), X_C)``: the link points at ``x`` and the slider's position [m]."""
    phi, q = Q[0], np.asarray(Q[1:])
    theta, _, _ = _theta(phi, mech)
    i = np.array([np.cos(theta), -np.sin(theta)])
    j = np.array([np.sin(theta), np.cos(theta)])
    u = _shapes(x, mech) @ q
    O = mech.crank_length * np.array([np.cos(phi), np.sin(phi)])
    return O + np.outer(x, i) + np.outer(u, j), mech.crank_length * np.cos(phi) + mech.rod_length * np.cos(theta)


def jacobian_and_gamma(Q, Qd, x, mech):
    """``(J (K, 2, 1+N), gamma (K, 2), J_C (1+N,), gamma_C)`` of the link points at ``x`` and of the slider."""
    phi, q = Q[0], np.asarray(Q[1:])
    phid, qd = Qd[0], np.asarray(Qd[1:])
    OA, L = mech.crank_length, mech.rod_length
    theta, t1, t2 = _theta(phi, mech)
    i = np.array([np.cos(theta), -np.sin(theta)])
    j = np.array([np.sin(theta), np.cos(theta)])  # di/dtheta = -j, dj/dtheta = i
    S = _shapes(x, mech)
    u, ud = S @ q, S @ qd
    dO = OA * np.array([-np.sin(phi), np.cos(phi)])
    ddO = -OA * np.array([np.cos(phi), np.sin(phi)])
    J = np.empty((x.size, 2, 1 + mech.modes))
    J[:, :, 0] = dO + t1 * (np.outer(-x, j) + np.outer(u, i))
    J[:, :, 1:] = j[None, :, None] * S[:, None, :]
    w = t1 * phid  # the link's rotation rate d(theta)/dt
    gamma = (ddO * phid ** 2 + t2 * phid ** 2 * (np.outer(-x, j) + np.outer(u, i))
             + w * w * (np.outer(-x, i) - np.outer(u, j)) + 2.0 * w * np.outer(ud, i))
    J_C = np.zeros(1 + mech.modes)
    J_C[0] = -OA * np.sin(phi) - L * np.sin(theta) * t1
    gamma_C = (-OA * np.cos(phi) - L * np.cos(theta) * t1 ** 2 - L * np.sin(theta) * t2) * phid ** 2
    return J, gamma, J_C, gamma_C


def rates(t, y, mech):
    n = 1 + mech.modes
    Q, Qd = y[:n], y[n:]
    x, w = np.polynomial.legendre.leggauss(mech.nodes)
    x, w = 0.5 * mech.rod_length * (x + 1.0), 0.5 * mech.rod_length * w * mech.mass_per_length
    J, gamma, J_C, gamma_C = jacobian_and_gamma(Q, Qd, x, mech)
    M = np.einsum("k,kan,kam->nm", w, J, J) + mech.slider_mass * np.outer(J_C, J_C)
    M[0, 0] += mech.flywheel
    F = -np.einsum("k,kan,ka->n", w, J, gamma) - mech.slider_mass * J_C * gamma_C
    F[0] += mech.torque + mech.slider_force * J_C[0]
    modal_mass = 0.5 * mech.mass_per_length * mech.rod_length
    wn = mech.omega_n
    F[1:] -= modal_mass * (wn * wn * Q[1:] + 2.0 * mech.damping_ratio * wn * Qd[1:])
    return np.concatenate([Qd, np.linalg.solve(M, F)])


def solve(mech, crank_speed, t_eval, rtol=1e-11, atol=1e-13):
    """``(phi, phi_dot, q (T, N))`` at ``t_eval`` from ``phi = 0``, ``phi_dot = crank_speed``, the link at rest."""
    n = 1 + mech.modes
    y0 = np.zeros(2 * n)
    y0[n] = crank_speed
    sol = solve_ivp(rates, (0.0, float(t_eval[-1])), y0, method="DOP853", t_eval=t_eval, rtol=rtol, atol=atol,
                    args=(mech,))
    assert sol.success, sol.message
    return sol.y[0], sol.y[n], sol.y[1:n].T
