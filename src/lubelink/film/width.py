"""The film of finite width ``B``: the 2-D Reynolds equation on the pad when the film varies along X only.

The pad is ``X in [0, l]``, ``Z in [-B/2, B/2]``, ambient pressure at all four edges. When the
link bends in its plane only, the film is ``xi(X)`` and the 2-D Reynolds equation

    d/dX(xi^3 dp/dX) + xi^3 d^2p/dZ^2 = R(X),     R = 6 mu V_r xi' + 12 mu xi_t,

is solved across the width by a few terms: each a two-point problem along the pad,

    (xi^3 u_j')' - s_j^2 xi^3 u_j = R,     u_j(0) = u_j(l) = 0,     s_j = 2 sigma_j / B,

solved by the conservative finite-volume scheme of :func:`~lubelink.film.reynolds.reynolds_cavitation`
on the uniform pad grid (one tridiagonal solve), and weighted: the pressure integrated over the
width ``P = B sum_j alpha_j u_j`` [Pa m], the centre line ``p(X, 0) = sum_j beta_j u_j`` [Pa], the
pressure at ``Z = zeta B / 2`` ``sum_j gamma_j(zeta) u_j``.

Why this works for any ``sigma_j``: on the eigenfunctions of ``-(xi^3 phi')' = lambda xi^3 phi``
(``phi(0) = phi(l) = 0``; those of the discrete operator, for the grid's solution) the 1-D film
``p_1D`` (``u`` at ``s = 0``) has components ``a_n``, a term has ``a_n x^2 / (x^2 + sigma_j^2)``
and the exact 2-D film ``a_n B g(x)`` (width integral) and ``a_n h(x)`` (centre line), with
``x = sqrt(lambda_n) B / 2``,

    g(x) = 1 - tanh(x) / x    (:func:`width_mean`),
    h(x) = 1 - 1 / cosh(x)    (:func:`width_profile`: 1 - cosh(zeta x) / cosh(x) at Z = zeta B / 2).

So the terms are a rational approximation of ``g`` and ``h`` in ``x^2``, and a relative error
``e`` of it over all ``x`` is an error of at most ``e`` on every component, whatever the film and
the pad's aspect ratio. Two sets of terms (:func:`width_terms`, ``film.width_series``):

* ``"sine"``: the sine series ``p = sum_k p_k sin(k pi (Z + B/2) / B)``, ``k`` odd, which is the
  partial fractions of ``g`` and ``h`` (``sigma_k = k pi / 2``, ``alpha_k = 8 / (k pi)^2``,
  ``beta_k = +-4 / (k pi)``). It converges like ``1 / K`` (load) on the components with
  ``x >> K``: those of a wide pad (``B >> l``), or of a pressure concentrated on a short part of
  the pad (a steep wedge);
* ``"fitted"`` (default): ``J`` wavenumbers and weights fitted to ``g`` and ``h`` (minimax
  relative error over ``x`` in [1e-3, 1e6], :mod:`.width_table`, ``tools/width_terms.py``): 8
  terms hold ``g`` within 3.2e-5 and ``h`` within 9.7e-5 for every ``x``. Their ``gamma`` (the
  half-Sommerfeld clip across the width) are fitted here, by least squares relative to ``h``.

The short-bearing limit (``B << l``) drops the flow along the pad, ``xi^3 p_ZZ = R``:

    p = A(X) (Z^2 - B^2/4),   A = R / (2 xi^3) = (3 mu / xi^3)(V_r xi' + 2 xi_t),   P = -A B^3 / 6.

Cavitation: half-Sommerfeld clips ``p`` at ``p_cav`` (in closed form across the width for the
short film; for the 2-D one, the clipped part ``int (p_cav - p)^+ dZ`` added to ``P`` on
``width_points`` points across the width, gathered at its edges, :func:`clip_points`); the
Swift-Stieber condition is available with the short film, where it is the obstacle problem across the width at
each X (closed form: ``p = p_cav + A (|Z| - z_c)^2`` outside the cavitated band ``|Z| < z_c``,
``z_c = B/2 - sqrt(-p_cav / A)``). For the 2-D film it needs the general solver
:func:`lubelink.film.pressure_2d`.
"""

from __future__ import annotations

import numpy as np

from .._jit import jitable, kernel
from ..params import CHOICES
from .reynolds import COS, SIN, HALF_SOMMERFELD, NO_FILM, REYNOLDS, WEDGE_SQUEEZE, grid_modal_force, pad_start
from .width_table import TERMS
from ..beam import wavenumber

__all__ = ["ONE_D", "TWO_D", "SHORT", "width_film", "width_pressure", "centre_pressure_many", "width_terms",
           "clip_points", "width_mean", "width_profile"]

ONE_D, TWO_D, SHORT = (CHOICES["film.reynolds"].index(v) for v in ("1d", "2d", "short"))

#: Rows of a :func:`width_terms` table: wavenumbers ``sigma``, weights of the width integral and of the centre line;
#: the weights at the points across the width follow (:data:`GAMMA` on), each with the point's share of the width
#: in the last column.
SIGMA, ALPHA, BETA, GAMMA = 0, 1, 2, 3

#: Where the weights across the width are fitted: ``x = sqrt(lambda) B / 2`` [-].
FIT_X = np.logspace(-3.0, 6.0, 500)


def width_mean(x):
    """``g(x) = 1 - tanh(x) / x`` [-]: a component's width integral over ``B`` times its 1-D film.

    ``x = sqrt(lambda) B / 2`` [-], ``lambda`` [1/m^2] the component's eigenvalue along the pad.
    """
    x = np.asarray(x, dtype=float)
    small = x < 1e-2
    xs = np.where(small, 1.0, x)
    series = x * x * (1.0 / 3.0 - x * x * (2.0 / 15.0 - 17.0 / 315.0 * x * x))
    return np.where(small, series, 1.0 - np.tanh(xs) / xs)


def width_profile(x, zeta):
    """``1 - cosh(zeta x) / cosh(x)`` [-]: a component's pressure at ``Z = zeta B / 2`` over its 1-D film.

    ``x = sqrt(lambda) B / 2`` [-]; ``zeta`` in [-1, 1] [-], 0 the centre line ``h(x)``.
    """
    x = np.asarray(x, dtype=float)
    z = np.abs(np.asarray(zeta, dtype=float))
    small = x < 20.0
    xs = np.where(small, x, 0.0)  # 2 sinh((1 + z) x / 2) sinh((1 - z) x / 2) / cosh(x): no cancellation near 0
    near = 2.0 * np.sinh(0.5 * (1.0 + z) * xs) * np.sinh(0.5 * (1.0 - z) * xs) / np.cosh(xs)
    far = 1.0 - np.exp(x * (z - 1.0)) * (1.0 + np.exp(-2.0 * x * z)) / (1.0 + np.exp(-2.0 * x))
    return np.where(small, near, far)


def clip_points(points):
    """Points ``s`` across the width (``Z = (s - 1/2) B``) [-] and their shares of it [-], for the clip.

    The midpoint rule in ``t``, ``s = t - sin(2 pi t) / (2 pi)``: the points gather at the side
    edges, where the pressure of a wide pad falls to ambient over about ``l``, as a parabola on a
    narrow one; the shares ``ds/dt / points`` sum to 1.
    """
    t = (np.arange(points) + 0.5) / points
    return t - np.sin(2.0 * np.pi * t) / (2.0 * np.pi), (1.0 - np.cos(2.0 * np.pi * t)) / points


def width_terms(modes, series="fitted", points=0):
    """The terms across the width: shape ``(3 + points, modes + 1)``, rows :data:`SIGMA`, :data:`ALPHA`, :data:`BETA`.

    Parameters
    ----------
    modes : int
        Terms ``J`` (the sine series: its odd terms ``k = 1, 3, .., 2 J - 1``).
    series : {"fitted", "sine"}
        The fitted terms of :mod:`.width_table` (``J`` from 1 to 8), or the sine series.
    points : int
        Points across the width (:func:`clip_points`), for the half-Sommerfeld clip: their
        weights ``gamma`` in rows ``3 ..``, their shares of the width in the last column; 0: none.
    """
    modes, points = int(modes), int(points)
    s, share = clip_points(points)
    if series == "sine":
        k = 2.0 * np.arange(modes) + 1.0
        head = [0.5 * np.pi * k, 8.0 / (np.pi * k) ** 2, np.where(np.arange(modes) % 2 == 0, 4.0, -4.0) / (np.pi * k)]
        gamma = 4.0 / (np.pi * k) * np.sin(np.pi * np.outer(s, k))
    elif series == "fitted":
        if modes not in TERMS:
            raise ValueError(f"modes = {modes}: the fitted terms are tabulated for {min(TERMS)} to {max(TERMS)}")
        head = [np.array(row) for row in TERMS[modes]]
        if points:  # least squares relative to the centre line, every point at once
            x = FIT_X[:, None]
            basis = x * x / (x * x + head[SIGMA][None, :] ** 2) / width_profile(x, 0.0)
            target = width_profile(x, 2.0 * s[None, :] - 1.0) / width_profile(x, 0.0)
            gamma = np.linalg.lstsq(basis, target, rcond=None)[0].T
        else:
            gamma = np.empty((0, modes))
    else:
        raise ValueError(f"series = {series!r}: must be 'fitted' or 'sine'")
    table = np.zeros((3 + points, modes + 1))
    table[:GAMMA, :modes] = np.stack(head)
    table[GAMMA:, :modes] = gamma
    table[GAMMA:, modes] = share
    return table


@jitable
def _short_line(A, B, cavitation, p_cav):
    """``(P, p_centre)`` of the short film ``p = A (Z^2 - B^2/4)`` at one X: width integral [Pa m], centre [Pa]."""
    P = -A * B * B * B / 6.0
    pc = -0.25 * A * B * B
    if cavitation == HALF_SOMMERFELD and pc < p_cav:  # clipped on |Z| < z_c where p = p_cav
        z_c = np.sqrt(0.25 * B * B + p_cav / A)
        P = 2.0 * (p_cav * z_c + A * (B * B * B / 24.0 - z_c * z_c * z_c / 3.0 - 0.25 * B * B * (0.5 * B - z_c)))
        pc = p_cav
    elif cavitation == REYNOLDS and pc < p_cav:  # Swift-Stieber across the width: p = p_cav + A (|Z| - z_c)^2
        d = np.sqrt(-p_cav / A)
        P = p_cav * B + 2.0 * A * d * d * d / 3.0
        pc = p_cav
    return P, pc


@jitable
def _terms_film(grid, xi_mid, xi_t, V_r, mu, B, cavitation, p_cav, terms, P, pc):
    """``P`` [Pa m] and ``pc`` [Pa] of the 2-D film from the ``terms`` across the width; None compiles to nothing."""
    if terms is None:
        return
    G = grid.shape[0]
    h = grid[1] - grid[0]
    n = G - 2
    J = terms.shape[1] - 1
    W = terms.shape[0] - GAMMA
    clip = cavitation == HALF_SOMMERFELD and W > 0
    a = np.empty(G - 1)  # xi^3 / h^2 at the midpoints
    for i in range(G - 1):
        a[i] = xi_mid[i] ** 3 / (h * h)
    xi3 = np.empty(n)
    R = np.empty(n)
    for i in range(n):
        xn = 0.5 * (xi_mid[i] + xi_mid[i + 1])
        xi3[i] = xn * xn * xn
        R[i] = 6.0 * mu * V_r * (xi_mid[i + 1] - xi_mid[i]) / h + 12.0 * mu * xi_t[i + 1]
    U = np.zeros((J if clip else 1, G))  # the terms u_j (all of them where the clip needs them)
    c = np.empty(n)
    for i in range(G):
        P[i] = 0.0
        pc[i] = 0.0
    for j in range(J):
        s = 2.0 * terms[SIGMA, j] / B
        s2 = s * s
        u = U[j] if clip else U[0]
        # -a0 u_{i-1} + (a0 + a1 + s^2 xi^3) u_i - a1 u_{i+1} = -R_i (Thomas algorithm)
        d = a[0] + a[1] + s2 * xi3[0]
        c[0] = -a[1] / d
        u[1] = -R[0] / d
        for i in range(1, n):
            d = a[i] + a[i + 1] + s2 * xi3[i] + a[i] * c[i - 1]
            c[i] = -a[i + 1] / d
            u[i + 1] = (-R[i] + a[i] * u[i]) / d
        for i in range(n - 2, -1, -1):
            u[i + 1] -= c[i] * u[i + 2]
        wP = B * terms[ALPHA, j]
        wc = terms[BETA, j]
        for i in range(1, G - 1):
            P[i] += wP * u[i]
            pc[i] += wc * u[i]
    if clip:  # half-Sommerfeld: P gains int (p_cav - p)^+ dZ, on the points across the width
        for i in range(1, G - 1):
            below = 0.0
            for w in range(W):
                p = 0.0
                for j in range(J):
                    p += terms[GAMMA + w, j] * U[j, i]
                if p < p_cav:
                    below += terms[GAMMA + w, J] * (p_cav - p)
            P[i] += B * below
            pc[i] = max(pc[i], p_cav)


@jitable
def width_film(grid, xi_mid, xi_t, V_r, mu, B, reynolds, cavitation, p_cav, terms, P, pc):
    """Width-integrated pressure ``P`` [Pa m] and centre-line pressure ``pc`` [Pa] at the pad grid (gauge).

    Parameters
    ----------
    grid : ndarray, shape ``(G,)``
        Uniform pad grid from 0 to ``l`` [m].
    xi_mid : ndarray, shape ``(G - 1,)``
        Film thickness at the cell midpoints [m].
    xi_t : ndarray, shape ``(G,)``
        ``d xi/dt`` at fixed link points, at the grid points [m/s].
    V_r, mu, B : float
        Collar velocity relative to the link [m/s], viscosity [Pa s], pad width [m].
    reynolds : int
        :data:`TWO_D` (the ``terms`` across the width) or :data:`SHORT`.
    cavitation : int
        Code of ``film.cavitation``; ``"reynolds"`` is honoured by the short film only.
    p_cav : float
        Gauge cavitation pressure [Pa].
    terms : ndarray or None
        :func:`width_terms` (with the points across the width where the 2-D film is clipped by
        half-Sommerfeld); None with the short film.
    P, pc : ndarray, shape ``(G,)``
        Written; zero at the pad ends, except for the short film, whose closed form ignores them.
    """
    G = grid.shape[0]
    h = grid[1] - grid[0]
    if reynolds == SHORT:  # the closed form holds up to the pad ends (it ignores them)
        for i in range(G):
            j = min(max(i, 1), G - 2)  # the ends: the film extrapolated, its slope one-sided
            xi = 0.5 * (xi_mid[j - 1] + xi_mid[j]) + (i - j) * (xi_mid[j] - xi_mid[j - 1])
            R = 6.0 * mu * V_r * (xi_mid[j] - xi_mid[j - 1]) / h + 12.0 * mu * xi_t[i]
            P[i], pc[i] = _short_line(0.5 * R / (xi * xi * xi), B, cavitation, p_cav)
        return
    _terms_film(grid, xi_mid, xi_t, V_r, mu, B, cavitation, p_cav, terms, P, pc)


@jitable
def film_on_grid(side, q, q_dot, s0, c0, f, grid_trig, xi_mid, xi_t):
    """The film ``H/2 - side u2`` at the grid's midpoints and its rate at the grid points, from ``grid_trig``."""
    N = q.shape[0]
    G = grid_trig.shape[2]
    for k in range(G - 1):
        xi_mid[k] = 0.5 * f.clearance
    for k in range(G):
        xi_t[k] = 0.0
    for n in range(N):
        a, b = side * q[n] * s0[n], side * q[n] * c0[n]
        for k in range(G - 1):  # u2(x0 + X) = sum_n q_n [sin(b x0) cos(b X) + cos(b x0) sin(b X)]
            xi_mid[k] -= a * grid_trig[COS + 2, n, k] + b * grid_trig[SIN + 2, n, k]
        if f.model == WEDGE_SQUEEZE:
            a, b = side * q_dot[n] * s0[n], side * q_dot[n] * c0[n]
            for k in range(G):
                xi_t[k] -= a * grid_trig[COS, n, k] + b * grid_trig[SIN, n, k]


@jitable
def width_side(side, q, q_dot, ws, V_r, f, B, grid_trig, terms, F):
    """Modal forces of the finite-width film on ``side`` added to ``F`` [N]; returns its resultant along +j [N].

    ``F_n = -side int_0^l P(X) sin(beta_n (x0 + X)) dX`` by the trapezoidal rule on the pad grid;
    ``ws`` holds ``sin``, ``cos(beta_n x0)`` in its first ``2 N``
    entries. ``grid_trig`` None (the 1-D film) compiles to nothing.
    """
    if grid_trig is None:
        return 0.0
    N = q.shape[0]
    G = grid_trig.shape[2]
    grid = np.linspace(0.0, f.pad_length, G)
    h = grid[1] - grid[0]
    xi_mid = np.empty(G - 1)
    xi_t = np.empty(G)
    film_on_grid(side, q, q_dot, ws[:N], ws[N:2 * N], f, grid_trig, xi_mid, xi_t)
    P = np.empty(G)
    pc = np.empty(G)
    width_film(grid, xi_mid, xi_t, V_r, f.viscosity, B, f.reynolds, f.cavitation,
               f.cavitation_pressure - f.ambient_pressure, terms, P, pc)
    P[0] *= 0.5  # trapezoidal weights
    P[G - 1] *= 0.5
    return grid_modal_force(side, P, h, 1.0, ws, grid_trig, F)  # P is integrated across the width already


@kernel
def centre_pressure_many(X, q, q_dot, x_star, V_r, side, f, B, L, grid_trig, terms):
    """Centre-line (``Z = 0``) gauge pressure [Pa] of the finite-width film at pad points ``X``, many states.

    ``q``, ``q_dot`` shape ``(T, N)``; ``x_star``, ``V_r`` shape ``(T,)``; ``grid_trig`` the
    :class:`~lubelink.film.force.PadTables` table of ``N`` modes. Returns shape ``(T, X.size)``.
    """
    T, N = q.shape
    out = np.zeros((T, X.shape[0]))
    if f.model == NO_FILM:
        return out
    G = grid_trig.shape[2]
    grid = np.linspace(0.0, f.pad_length, G)
    s0 = np.empty(N)
    c0 = np.empty(N)
    xi_mid = np.empty(G - 1)
    xi_t = np.empty(G)
    P = np.empty(G)
    pc = np.empty(G)
    for i in range(T):
        x0 = pad_start(x_star[i], f.pad_length, f.pad_reference)
        for m in range(N):
            s0[m] = np.sin(wavenumber(m + 1, L) * x0)
            c0[m] = np.cos(wavenumber(m + 1, L) * x0)
        film_on_grid(side, q[i], q_dot[i], s0, c0, f, grid_trig, xi_mid, xi_t)
        width_film(grid, xi_mid, xi_t, V_r[i], f.viscosity, B, f.reynolds, f.cavitation,
                   f.cavitation_pressure - f.ambient_pressure, terms, P, pc)
        out[i] = np.interp(X, grid, pc)
    return out


@kernel
def _width_kernel(grid, xi_mid, xi_t, V_r, mu, B, reynolds, cavitation, p_cav, terms):
    P = np.empty(grid.shape[0])
    pc = np.empty(grid.shape[0])
    width_film(grid, xi_mid, xi_t, V_r, mu, B, reynolds, cavitation, p_cav, terms, P, pc)
    return P, pc


def width_pressure(xi, V_r, mu, width, pad_length, *, xi_t=None, reynolds="2d", modes=8, series="fitted",
                   cavitation="none", p_cav=-101325.0, grid_points=201, width_points=32):
    """The finite-width film of a film ``xi(X)`` uniform across the width, on a uniform pad grid.

    What the right-hand side executes (:func:`width_film`), from Python.

    Parameters
    ----------
    xi : callable
        Film thickness [m], a vectorised function of ``X`` [m].
    V_r, mu : float
        Collar velocity relative to the link [m/s], viscosity [Pa s].
    width, pad_length : float
        ``B``, ``l`` [m].
    xi_t : callable, optional
        ``d xi / dt`` [m/s] (squeeze term).
    reynolds : {"2d", "short"}
        ``modes`` terms across the width, or the short-bearing closed form.
    series : {"fitted", "sine"}
        The terms of ``"2d"`` (:func:`width_terms`): fitted (``modes`` from 1 to 8), or the odd
        terms of the sine series.
    cavitation : {"none", "half-sommerfeld", "reynolds"}
        ``"reynolds"`` with ``reynolds = "short"`` only.
    p_cav : float
        Gauge cavitation pressure [Pa].
    grid_points, width_points : int
        Pad grid; points across the width where the 2-D film is clipped (half-Sommerfeld).

    Returns
    -------
    X : ndarray, shape ``(grid_points,)``
        The grid [m].
    P : ndarray
        Pressure integrated over the width [Pa m].
    p_centre : ndarray
        Pressure on the centre line ``Z = 0`` [Pa].
    """
    if reynolds not in ("2d", "short"):
        raise ValueError(f"reynolds = {reynolds!r}: must be '2d' or 'short'")
    if cavitation not in CHOICES["film.cavitation"]:
        raise ValueError(f"cavitation = {cavitation!r}: must be 'none', 'half-sommerfeld' or 'reynolds'")
    if cavitation == "reynolds" and reynolds == "2d":
        raise ValueError("cavitation = 'reynolds' with reynolds = '2d': use lubelink.film.pressure_2d")
    grid = np.linspace(0.0, pad_length, int(grid_points))
    mid = 0.5 * (grid[1:] + grid[:-1])
    xi_mid = np.ascontiguousarray(np.broadcast_to(np.asarray(xi(mid), dtype=float), mid.shape))
    if not (np.all(np.isfinite(xi_mid)) and np.all(xi_mid > 0)):
        raise ValueError("the film thickness xi must be finite and positive on the whole pad")
    xt = np.zeros_like(grid) if xi_t is None else np.broadcast_to(np.asarray(xi_t(grid), dtype=float), grid.shape)
    cav = CHOICES["film.cavitation"].index(cavitation)
    terms = None
    if reynolds == "2d":
        terms = width_terms(modes, series, width_points if cavitation == "half-sommerfeld" else 0)
    P, pc = _width_kernel(grid, xi_mid, np.ascontiguousarray(xt), float(V_r), float(mu), float(width),
                          CHOICES["film.reynolds"].index(reynolds), cav, float(p_cav), terms)
    return grid, P, pc
