"""The film's viscous shear on the link and the power it dissipates (Couette and Poiseuille flow).

Across a film of thickness ``xi`` between the link face (at rest in the link frame) and the collar
face (sliding at ``V_r`` along +i), the velocity along the pad is ``u(y) = V_r y / xi + p' (y^2 - xi y) /
(2 mu)``, ``y`` from the link face, ``p'`` the pressure gradient of the Reynolds equation. So

    tau = mu du/dy (y = 0) = mu V_r / xi - xi p' / 2                    [Pa]    (shear on the link, along +i)
    D = int_0^xi mu (du/dy)^2 dy = mu V_r^2 / xi + xi^3 p'^2 / (12 mu)  [W/m^2] (dissipated per unit pad area)

and the film's friction force on the link and its power loss are ``B int tau dX`` and ``B int D dX`` over the
pad of width ``B``. Where the film cavitates the pressure is flat and the shear is the Couette term of a
full film (an upper bound: a ruptured film carries less). :func:`film_losses_many` takes the pressure
the results computed on the pad (every cavitation option of the 1-D film) and integrates both by the
midpoint rule between its points.
"""

from __future__ import annotations

import numpy as np

from .._jit import jitable, kernel
from ..beam import add_deflection, deflection_at, wavenumber, wavenumbers
from .reynolds import NO_FILM, effective_film, pad_start

__all__ = ["wall_shear", "dissipation", "film_losses_many", "midpoint_tables"]


@jitable
def wall_shear(xi, dp, V_r, mu):
    """Viscous shear stress of the film on the link face, along +i [Pa]: ``mu V_r / xi - xi p' / 2``.

    Parameters
    ----------
    xi : float
        Film thickness [m].
    dp : float
        Pressure gradient along the pad ``p'`` [Pa/m].
    V_r : float
        Velocity of the collar face relative to the link face, along +i [m/s].
    mu : float
        Viscosity [Pa s].
    """
    return mu * V_r / xi - 0.5 * xi * dp


@jitable
def dissipation(xi, dp, V_r, mu):
    """Viscous power dissipated per unit pad area [W/m^2]: ``mu V_r^2 / xi + xi^3 p'^2 / (12 mu)`` (Couette plus
    Poiseuille; arguments as :func:`wall_shear`)."""
    return mu * V_r * V_r / xi + xi * xi * xi * dp * dp / (12.0 * mu)


def midpoint_tables(X, modes, rod_length):
    """``(sin, cos)`` of ``beta_n`` times the midpoints between the pad points ``X`` [m], shape ``(N, X.size - 1)``."""
    mid = 0.5 * (X[1:] + X[:-1])
    bX = np.outer(wavenumbers(modes, rod_length), mid)
    return np.ascontiguousarray(np.sin(bX)), np.ascontiguousarray(np.cos(bX))


@kernel
def film_losses_many(X, p, q, x_star, V_r, side, f, B, L, sin_m, cos_m):
    """Friction force on the link along +i [N], power lost [W] and the moment about the link end O of the film's
    pressure on the link [N m] (about +k) of the film on ``side`` for many states.

    ``X`` (K + 1,): evenly spaced pad points [m] from 0 to ``l``, ``K`` even; ``p`` (T, K + 1): the film's gauge
    pressure there [Pa] (:func:`~lubelink.film.pressure.pad_pressure_many`); ``q`` (T, N) [m]; ``x_star``, ``V_r``
    (T,); ``side`` 1 for the film ``H/2 - u2``, -1 for ``H/2 + u2``; ``f`` the film's kernel view; ``B`` the pad
    width [m]; ``sin_m``, ``cos_m``: :func:`midpoint_tables`. The midpoint rule on the ``K`` pieces (the film the
    Reynolds equation sees, :func:`~lubelink.film.reynolds.effective_film`, at the midpoint, the mean gradient of
    ``p`` over the piece) and on the ``K/2`` pieces of twice the length, extrapolated (Richardson: the rule's
    error goes as the piece length squared). The moment by Simpson's rule on the points: the pressure pushes the
    link with ``-side B p_g`` along +j at ``x0 + X``.
    """
    T, N = q.shape
    K = X.shape[0] - 1
    friction = np.zeros(T)
    loss = np.zeros(T)
    moment = np.zeros(T)
    if f.model == NO_FILM:
        return friction, loss, moment
    s0 = np.empty(N)
    c0 = np.empty(N)
    xi = np.empty(K)
    h = X[1] - X[0]
    for i in range(T):
        x0 = pad_start(x_star[i], f.pad_length, f.pad_reference)
        for n in range(N):
            s0[n] = np.sin(wavenumber(n + 1, L) * x0)
            c0[n] = np.cos(wavenumber(n + 1, L) * x0)
        xi[:] = 0.5 * f.clearance
        add_deflection(q[i], s0, c0, sin_m, cos_m, -side, xi)
        for k in range(K):
            xi[k] = effective_film(xi[k], f.thickness_floor, f.roughness)
        fine_f = 0.0
        fine_d = 0.0
        coarse_f = 0.0
        coarse_d = 0.0
        for k in range(K):
            dp = (p[i, k + 1] - p[i, k]) / h
            fine_f += wall_shear(xi[k], dp, V_r[i], f.viscosity)
            fine_d += dissipation(xi[k], dp, V_r[i], f.viscosity)
        for k in range(0, K - 1, 2):  # the film at the common end of two pieces: the mean of their midpoints' is
            dp = (p[i, k + 2] - p[i, k]) / (2.0 * h)  # second order too, and the extrapolation keeps it (a bias O(h^2))
            film = _film_at(X[k + 1], x0, q[i], side, f, L)
            coarse_f += 2.0 * wall_shear(film, dp, V_r[i], f.viscosity)
            coarse_d += 2.0 * dissipation(film, dp, V_r[i], f.viscosity)
        friction[i] = B * h * (4.0 * fine_f - coarse_f) / 3.0
        loss[i] = B * h * (4.0 * fine_d - coarse_d) / 3.0
        acc = 0.0
        for k in range(K + 1):
            weight = 1.0 if k == 0 or k == K else (4.0 if k % 2 == 1 else 2.0)
            acc += weight * (x0 + X[k]) * p[i, k]
        moment[i] = -side * B * h * acc / 3.0
    return friction, loss, moment


@jitable
def _film_at(X, x0, q, side, f, L):
    """The film the Reynolds equation sees at pad point ``X`` [m] (:func:`~lubelink.film.reynolds.effective_film`)."""
    return effective_film(0.5 * f.clearance - side * deflection_at(q, x0 + X, L), f.thickness_floor, f.roughness)
