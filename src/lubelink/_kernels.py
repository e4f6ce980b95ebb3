"""Compiled (Numba) kernels of the model physics, for the fast path (:mod:`lubelink.integrate.fast`).

Each kernel reproduces a NumPy reference function to rounding (``tests/test_fast.py`` checks them
on random states, with tolerances of a few eps times the size of the terms each sum adds up):

==========================  ===============================================
kernel                      reference
==========================  ===============================================
:func:`slider_crank`        :func:`lubelink.kinematics.slider_crank` (scalar)
:func:`film_loads`          :meth:`lubelink.model.Model.film_loads`
                            (:func:`lubelink.film.modal_force`, cavitation
                            ``"none"`` and ``"half-sommerfeld"``)
:func:`thinnest_film`       :meth:`lubelink.model.Model.thinnest_film`
                            (:func:`lubelink.contact.thinnest_film`)
:func:`contact_force`       :meth:`lubelink.model.Model.contact_force`
:func:`rhs`                 :meth:`lubelink.model.Model.rhs`
:func:`gap`, :func:`event`  :meth:`lubelink.model.Model.gap` (``event`` is
                            the gap times the event sign of the segment)
:func:`film_force_many`     ``Model.film_loads(t, y)[1]`` for many samples
                            (the ``film_force`` of the results)
:func:`pad_pressure_many`   :func:`lubelink.film.pad_pressure` for many
                            samples (the ``pressure`` of the results)
==========================  ===============================================

Data layout
-----------
The model reaches every kernel as one read-only float64 array ``p`` built by :func:`pack`: a
header of scalars at the ``I_*`` indices below, then arrays at the offsets the header holds --
the natural frequencies, the Gauss-Legendre nodes and weights of the pad, and tables that depend
on the pad geometry only: ``sin``, ``cos`` and ``1 - cos`` of ``beta_n X`` at the nodes and at
the uniform samples of the thinnest-film search (and the spectral integration matrix for
half-Sommerfeld). So :func:`rhs` and :func:`event` have the fixed signatures
(:data:`lubelink.integrate.fast.RHS_SIG`, :data:`~lubelink.integrate.fast.EVENT_SIG`) that the
compiled integrators take as first-class functions. The compliant-contact phase and the event
sign of a segment are header entries (:func:`set_segment` makes a segment's copy).

Speed
-----
* One ``sin``/``cos`` pair per call for the pad: ``sin(beta_n (x0 + X))`` is
  ``sin(beta_n x0) cos(beta_n X) + cos(beta_n x0) sin(beta_n X)`` with the tables, and
  ``sin(n beta_1 x0)`` comes from the angle-addition recurrence (re-seeded every 32 modes;
  rounding grows like ``n eps``). ``1 - cos`` is tabulated as ``2 sin^2(beta X / 2)``, so the
  by-parts weight ``W_n`` has no cancellation (the reference's ``cos0 - cos`` has).
* Scratch is one array per call (``p[I_WORK]`` long); arrays are addressed by offsets rather
  than sliced (a Numba view costs two atomic reference-count updates), and the loops are
  laid out element-wise over contiguous table rows, with a (never taken) early return on
  negative offsets that lets LLVM drop Numba's negative-index wraparound and vectorise.

Only the slider-crank motion and cavitation ``"none"``/``"half-sommerfeld"`` are compiled:
:func:`supported` says why not otherwise, and
:func:`lubelink.integrate.fast.make_segment_integrator` then returns None (reference path).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = [
    "pack",
    "supported",
    "slider_crank",
    "film_loads",
    "thinnest_film",
    "contact_force",
    "rhs",
    "gap",
    "event",
    "film_force_many",
    "pad_pressure_many",
    "set_segment",
]

# --- layout of the parameter array p (header indices) ----------------------------------------
I_N = 0  # modes N
I_L = 1  # rod length L [m] (beam)
I_OA = 2  # crank length [m] (motion)
I_W0 = 3  # crank speed omega0 [rad/s]
I_A = 4  # guide distance a [m]
I_L_KIN = 5  # rod length of the motion's mechanism [m]
I_GX = 6  # gravity [m/s^2]
I_GY = 7
I_FILM = 8  # 1: film on
I_SIDES = 9  # 1 or 2
I_SQUEEZE = 10  # 1: wedge+squeeze
I_CAV = 11  # 0: none, 1: half-sommerfeld
I_MU = 12  # viscosity [Pa s]
I_H = 13  # clearance [m]
I_PAD = 14  # pad length [m]
I_CENTRE = 15  # 1: x_star is the pad centre
I_B = 16  # width [m]
I_NODES = 17  # Gauss-Legendre nodes
I_PCAV = 18  # gauge cavitation pressure [Pa]
I_MC = 19  # collar mass [kg]
I_MASS = 20  # modal mass [kg]
I_ZETA = 21  # damping ratio
I_PHASE_SIDE = 22  # compliant contact in progress: side (+-1), 0 for none
I_PHASE_V = 23  # its approach velocity v_minus [m/s]
I_K = 24  # contact stiffness
I_EXP = 25  # contact exponent
I_E = 26  # restitution
I_MIN_FILM = 27  # xi_min [m]
I_EVENT = 28  # event(t, y) = p[I_EVENT] * gap(t, y)
I_SAMPLES = 29  # pad samples of the thinnest-film search, 16 + 4 N
# offsets of the arrays that follow the header
I_OFF_OMEGA = 30  # omega_n (N)
I_OFF_X = 31  # X_j = l s_j (nodes)
I_OFF_WX = 32  # l w_j (nodes)
I_OFF_SXT = 33  # sin(beta_n X_j), (N, nodes)
I_OFF_CXT = 34  # cos(beta_n X_j), (N, nodes)
I_OFF_VXT = 35  # 1 - cos(beta_n X_j) = 2 sin^2(beta_n X_j / 2), (N, nodes)
I_OFF_SMT = 36  # l times the transposed spectral integration matrix (nodes, nodes), half-Sommerfeld only
I_OFF_SKT = 37  # sin(beta_n X_k), X_k = k l / (samples - 1): thinnest-film samples, (N, samples)
I_OFF_CKT = 38  # cos(beta_n X_k), (N, samples)
I_WORK = 39  # size of the scratch array of a kernel call: 8 N + 8 nodes + samples
I_OFF_VS = 40  # [1 - cos | sin](beta_n X_j), (nodes, 2 N): projections by rows when N >= _ROWS_FROM
I_OFF_CS = 41  # [cos | sin](beta_n X_j), (nodes, 2 N)
HEADER = 42

_ROWS_FROM = 4  # modes from which the film projections run over table rows (vectorised over modes)

_RESEED = 32  # the sine recurrence is re-seeded from sin/cos every this many modes

CAVITATION_CODES = {"none": 0, "half-sommerfeld": 1}


def supported(model):
    """Why ``model`` cannot be compiled (a string), or None if it can."""
    from .kinematics import SliderCrank

    if type(model.motion) is not SliderCrank:
        return f"motion {type(model.motion).__name__} (only the slider-crank is compiled)"
    if model.config.film.cavitation not in CAVITATION_CODES:
        return f"film.cavitation = {model.config.film.cavitation!r}"
    return None


def pack(model, phase=None, event_sign=None):
    """The parameter array ``p`` of ``model`` for the kernels.

    Besides the scalars, ``p`` holds tables that depend on the pad geometry
    only: ``sin``, ``cos`` and ``1 - cos`` of ``beta_n X`` at the
    Gauss-Legendre nodes ``X_j`` of the pad and at the uniform samples of the
    thinnest-film search, so that a kernel call needs one ``sin``/``cos``
    pair, ``beta_1 x0`` (by the angle-addition formulas
    ``sin(beta (x0 + X)) = sin(beta x0) cos(beta X) + cos(beta x0) sin(beta X)``).

    Parameters
    ----------
    model : lubelink.model.Model
        A model with a :class:`~lubelink.kinematics.SliderCrank` motion and a
        cavitation the kernels support (:func:`supported`).
    phase : lubelink.model.ContactPhase, optional
        Compliant contact in progress.
    event_sign : {-1, 1, None}
        ``-1`` (or None): the event is the gap; ``+1``: minus the gap.

    Returns
    -------
    ndarray of float64
        Read-only for the kernels (each call allocates its own scratch).
    """
    from .film import _integration_matrix, gauss_legendre

    why = supported(model)
    if why is not None:
        raise ValueError(f"the compiled kernels do not support {why}")
    cfg = model.config
    fm, ct, m = cfg.film, cfg.contact, model.motion.mechanism
    nodes = fm.quadrature_nodes
    N = model.modes
    L, pad = cfg.mechanism.rod_length, fm.pad_length
    beta = np.arange(1, N + 1) * np.pi / L
    s, w = gauss_legendre(nodes)
    X = pad * s
    samples = 16 + 4 * N
    Xk = np.arange(samples) * (pad / (samples - 1))
    smat = pad * _integration_matrix(nodes) if fm.cavitation == "half-sommerfeld" else np.zeros((0, 0))
    bX = np.outer(X, beta)
    bXk = np.outer(Xk, beta)
    SX, CX, VX = np.sin(bX), np.cos(bX), 2.0 * np.sin(0.5 * bX) ** 2
    arrays = [model.omega_n, X, pad * w, SX.T, CX.T, VX.T, smat.T, np.sin(bXk).T, np.cos(bXk).T,
              np.hstack([VX, SX]), np.hstack([CX, SX])]
    head = np.zeros(HEADER)
    head[I_N] = N
    head[I_L] = L
    head[I_OA], head[I_W0], head[I_A], head[I_L_KIN] = m.crank_length, m.crank_speed, m.guide_distance, m.rod_length
    head[I_GX], head[I_GY] = cfg.mechanism.gravity
    head[I_FILM] = float(fm.enabled)
    head[I_SIDES] = fm.sides
    head[I_SQUEEZE] = float(fm.model == "wedge+squeeze")
    head[I_CAV] = CAVITATION_CODES[fm.cavitation]
    head[I_MU], head[I_H], head[I_PAD] = fm.viscosity, fm.clearance, pad
    head[I_CENTRE] = float(fm.pad_reference == "centre")
    head[I_B] = cfg.beam.width
    head[I_NODES] = nodes
    head[I_PCAV] = fm.cavitation_pressure - fm.ambient_pressure
    head[I_MC] = cfg.collar.mass
    head[I_MASS] = model.modal_mass
    head[I_ZETA] = cfg.beam.damping_ratio
    head[I_PHASE_SIDE] = 0.0 if phase is None else phase.side
    head[I_PHASE_V] = 0.0 if phase is None else phase.v_minus
    head[I_K], head[I_EXP], head[I_E], head[I_MIN_FILM] = ct.stiffness, ct.exponent, ct.restitution, ct.min_film
    head[I_EVENT] = 1.0 if event_sign in (None, -1) else -1.0
    head[I_SAMPLES] = samples
    head[I_WORK] = 8 * N + 8 * nodes + samples
    off = HEADER
    for i, a in zip([I_OFF_OMEGA, I_OFF_X, I_OFF_WX, I_OFF_SXT, I_OFF_CXT, I_OFF_VXT, I_OFF_SMT, I_OFF_SKT,
                     I_OFF_CKT, I_OFF_VS, I_OFF_CS], arrays):
        head[i] = off
        off += a.size
    return np.concatenate([head] + [np.ravel(a) for a in arrays]).astype(np.float64)


def set_segment(p, phase=None, event_sign=None):
    """A copy of ``p`` for one segment: compliant ``phase`` (or None) and ``event_sign``."""
    p = p.copy()
    p[I_PHASE_SIDE] = 0.0 if phase is None else phase.side
    p[I_PHASE_V] = 0.0 if phase is None else phase.v_minus
    p[I_EVENT] = 1.0 if event_sign in (None, -1) else -1.0
    return p


# --- kinematics -------------------------------------------------------------------------------
@numba.njit(cache=True)
def slider_crank(t, crank_length, rod_length, crank_speed, guide_distance):
    """Scalar :func:`lubelink.kinematics.slider_crank`.

    Returns
    -------
    tuple of float
        ``(A_O2, omega, alpha, x_star, V_r, Y_ddot, cos_theta, sin_theta)``
        in the units of the reference.
    """
    OA, L, w0, a = crank_length, rod_length, crank_speed, guide_distance
    lam = OA / L
    phi = w0 * t
    sphi, cphi = math.sin(phi), math.cos(phi)
    s_th = lam * sphi
    c_th = math.sqrt(1.0 - s_th**2)
    s_sum = sphi * c_th + cphi * s_th
    A_O2 = -OA * w0**2 * s_sum
    omega = -lam * w0 * cphi / c_th
    alpha = lam * w0**2 * sphi / c_th - lam**3 * w0**2 * cphi**2 * sphi / c_th**3
    theta_dot = -omega
    theta_ddot = -alpha
    x_star = (a - OA * cphi) / c_th
    V_r = (OA * w0 * sphi * c_th + (a - OA * cphi) * s_th * theta_dot) / c_th**2
    A_r = (OA * w0**2 * cphi + 2.0 * V_r * s_th * theta_dot + x_star * (c_th * theta_dot**2 + s_th * theta_ddot)) / c_th
    lever = OA - lam * x_star
    Y_ddot = -(w0**2) * sphi * lever - 2.0 * lam * w0 * cphi * V_r - lam * sphi * A_r
    return A_O2, omega, alpha, x_star, V_r, Y_ddot, c_th, s_th


@numba.njit(cache=True)
def _kin(t, p):
    return slider_crank(t, p[I_OA], p[I_L_KIN], p[I_W0], p[I_A])


# --- helpers -------------------------------------------------------------------------------------
# Hot kernels address their arrays by offsets (q at y[oq], q_dot at y[oq + N], tables at offsets of
# p, scratch at offsets of one array ws per call) instead of slicing: a Numba array view costs two
# atomic reference-count updates.
@numba.njit(cache=True)
def _modal_sincos(x, beta1, N, a, off):
    """``a[off + n] = sin((n + 1) beta1 x)``, ``a[off + N + n] = cos((n + 1) beta1 x)`` for ``n < N``."""
    s1 = math.sin(beta1 * x)
    c1 = math.cos(beta1 * x)
    a[off] = s1
    a[off + N] = c1
    for n in range(1, N):
        if n % _RESEED == 0:
            th = (n + 1) * beta1 * x
            a[off + n] = math.sin(th)
            a[off + N + n] = math.cos(th)
        else:
            sp = a[off + n - 1]
            cp = a[off + N + n - 1]
            a[off + n] = sp * c1 + cp * s1
            a[off + N + n] = cp * c1 - sp * s1


@numba.njit(cache=True)
def _dot2(a, oa, ob, b, o, n):
    """``(sum_i a[oa + i] b[o + i], sum_i a[ob + i] b[o + i])``, each with two partial sums (ILP)."""
    if oa < 0 or ob < 0 or o < 0:  # lets LLVM drop Numba's negative-index wraparound
        return 0.0, 0.0
    a0 = 0.0
    a1 = 0.0
    b0 = 0.0
    b1 = 0.0
    m = n - n % 2
    for i in range(0, m, 2):
        x0 = b[o + i]
        x1 = b[o + i + 1]
        a0 += a[oa + i] * x0
        a1 += a[oa + i + 1] * x1
        b0 += a[ob + i] * x0
        b1 += a[ob + i + 1] * x1
    if m < n:
        a0 += a[oa + m] * b[o + m]
        b0 += a[ob + m] * b[o + m]
    return a0 + a1, b0 + b1


@numba.njit(cache=True)
def _project(p, offA, offB, offR, N, nodes, ws, od, oacc):
    """``ws[oacc + n] = sum_j A_nj d_j`` and ``ws[oacc + N + n] = sum_j B_nj d_j``, ``d = ws[od:od + nodes]``.

    ``A`` and ``B`` are ``(N, nodes)`` tables at ``offA``, ``offB`` (dot
    products, for few modes) and also the ``(nodes, 2N)`` rows ``[A | B]``
    at ``offR`` (summed row by row, vectorised over the modes, for
    ``N >= _ROWS_FROM``).
    """
    if offA < 0 or offB < 0 or offR < 0 or N < 0 or nodes < 0 or od < 0 or oacc < 0:
        return
    if N < _ROWS_FROM:
        for n in range(N):
            a, b = _dot2(p, offA + n * nodes, offB + n * nodes, ws, od, nodes)
            ws[oacc + n] = a
            ws[oacc + N + n] = b
        return
    for m in range(2 * N):
        ws[oacc + m] = 0.0
    for j in range(nodes):
        dj = ws[od + j]
        row = offR + j * 2 * N
        for m in range(2 * N):
            ws[oacc + m] += dj * p[row + m]


@numba.njit(cache=True)
def _pad_start(x_star, p):
    return x_star - 0.5 * p[I_PAD] if p[I_CENTRE] != 0.0 else x_star


@numba.njit(cache=True)
def _pad_deflection(y, oq, N, p, ws, osc, offsT, offcT, rows, ou):
    """``ws[ou + k] = u2(x0 + X_k) = sum_n q_n [sin(beta_n x0) C_nk + cos(beta_n x0) S_nk]``.

    ``q = y[oq:oq + N]``; ``sin``, ``cos(beta_n x0)`` at ``ws[osc]``,
    ``ws[osc + N]``; ``S``, ``C`` the ``(N, rows)`` tables of ``sin``,
    ``cos(beta_n X_k)`` at ``p[offsT]``, ``p[offcT]``. The inner loop runs
    over the points (element-wise, vectorisable), the modes are summed in
    increasing order.
    """
    if oq < 0 or osc < 0 or offsT < 0 or offcT < 0 or ou < 0 or N < 0 or rows < 0:
        return  # (never) lets LLVM drop Numba's negative-index wraparound and vectorise
    for k in range(rows):
        ws[ou + k] = 0.0
    for n in range(N):
        a = ws[osc + n] * y[oq + n]
        b = ws[osc + N + n] * y[oq + n]
        bs = offsT + n * rows
        bc = offcT + n * rows
        for k in range(rows):
            ws[ou + k] += p[bc + k] * a + p[bs + k] * b


# --- film -----------------------------------------------------------------------------------------
@numba.njit(cache=True)
def _film_side(side, N, V_r, p, ws, F, oF):
    """Add ``side * F_n`` of one side's film to ``F[oF:oF + N]``; return ``side * total``.

    The scratch ``ws`` holds ``sin``, ``cos(beta_n x0)`` (``2 N``), then
    ``u2`` and the squeeze integral ``-int_0^X u2_dot`` at the pad's
    Gauss-Legendre nodes, then room for six more node arrays and ``2 N``
    projections. The reference
    is :func:`lubelink.film.modal_force` on ``side * q``, ``side * q_dot``:
    cavitation ``"none"`` integrates by parts, ``F_n = B int p_g' W_n`` with
    ``W_n(X) = int_0^X sin(beta_n (x0 + s)) ds
    = [cos(beta_n x0) (1 - cos(beta_n X)) + sin(beta_n x0) sin(beta_n X)] / beta_n``;
    ``"half-sommerfeld"`` integrates the clipped pressure at the nodes.
    """
    nodes = int(p[I_NODES])
    mu, B = p[I_MU], p[I_B]
    half = 0.5 * p[I_H]
    offx, offw = int(p[I_OFF_X]), int(p[I_OFF_WX])
    offs, offc, offv = int(p[I_OFF_SXT]), int(p[I_OFF_CXT]), int(p[I_OFF_VXT])
    if N < 0 or nodes < 0 or offx < 0 or offw < 0 or offs < 0 or offc < 0 or offv < 0 or oF < 0:
        return 0.0  # (never) lets LLVM drop Numba's negative-index wraparound
    osc = 0
    ou = 2 * N
    oQ = ou + nodes
    o2 = oQ + nodes  # xi^-2
    o3 = o2 + nodes  # xi^-3
    oq3 = o3 + nodes  # Q xi^-3
    od = oq3 + nodes  # quadrature weights times p_g' (or p_g)
    oa1 = od + nodes
    oa2 = oa1 + nodes
    oacc = oa2 + nodes  # 2 N projections
    I1 = 0.0
    I2 = 0.0
    I3 = 0.0
    for j in range(nodes):
        r = 1.0 / (half - side * ws[ou + j])
        r2 = r * r
        r3 = r2 * r
        q3 = (side * ws[oQ + j]) * r3
        ws[o2 + j] = r2
        ws[o3 + j] = r3
        ws[oq3 + j] = q3
        wj = p[offw + j]
        I1 += wj * r2
        I2 += wj * r3
        I3 += wj * q3
    C = -(6.0 * mu * V_r * I1 + 12.0 * mu * I3) / I2
    beta1 = math.pi / p[I_L]
    if p[I_CAV] == 0.0:  # by parts: p_g' = (6 mu V_r xi + 12 mu Q + C) / xi^3
        total = 0.0
        for j in range(nodes):
            dj = p[offw + j] * (6.0 * mu * V_r * ws[o2 + j] + 12.0 * mu * ws[oq3 + j] + C * ws[o3 + j])
            ws[od + j] = dj
            total += dj * p[offx + j]
        _project(p, offv, offs, int(p[I_OFF_VS]), N, nodes, ws, od, oacc)
        for n in range(N):
            W_n = ws[osc + N + n] * ws[oacc + n] + ws[osc + n] * ws[oacc + N + n]  # beta_n int p_g' W_n
            F[oF + n] += side * B * W_n / ((n + 1) * beta1)
        return side * B * total
    # half-Sommerfeld: the pressure at the nodes by the spectral integration matrix, clipped
    off = int(p[I_OFF_SMT])  # transposed: column j of the matrix is contiguous
    if off < 0:
        return 0.0
    for i in range(nodes):
        ws[od + i] = 0.0
        ws[oa1 + i] = 0.0
        ws[oa2 + i] = 0.0
    for j in range(nodes):
        x2 = ws[o2 + j]
        x3 = ws[o3 + j]
        x4 = ws[oq3 + j]
        col = off + j * nodes
        for i in range(nodes):
            sij = p[col + i]
            ws[od + i] += sij * x2
            ws[oa1 + i] += sij * x3
            ws[oa2 + i] += sij * x4
    total = 0.0
    for i in range(nodes):
        pg = max(6.0 * mu * V_r * ws[od + i] + C * ws[oa1 + i] + 12.0 * mu * ws[oa2 + i], p[I_PCAV])
        ws[od + i] = p[offw + i] * pg
        total += ws[od + i]
    _project(p, offc, offs, int(p[I_OFF_CS]), N, nodes, ws, od, oacc)
    for n in range(N):  # sin(beta (x0 + X)) = sin(beta x0) cos(beta X) + cos(beta x0) sin(beta X)
        F[oF + n] -= side * B * (ws[osc + n] * ws[oacc + n] + ws[osc + N + n] * ws[oacc + N + n])
    return -side * B * total


@numba.njit(cache=True)
def _film_loads(y, oq, N, x_star, V_r, p, ws, F, oF):
    """Add the modal film forces of ``q = y[oq:oq + N]``, ``q_dot = y[oq + N:oq + 2N]`` to ``F[oF:oF + N]``.

    Returns the resultant film force along +j [N].
    """
    nodes = int(p[I_NODES])
    beta1 = math.pi / p[I_L]
    x0 = _pad_start(x_star, p)
    w = np.int64(0)  # film scratch: 4 N + 8 nodes (np.int64: no literal specialisation)
    ou = w + 2 * N
    oQ = ou + nodes
    _modal_sincos(x0, beta1, N, ws, w)
    _pad_deflection(y, oq, N, p, ws, w, int(p[I_OFF_SXT]), int(p[I_OFF_CXT]), nodes, ou)
    for j in range(nodes):
        ws[oQ + j] = 0.0
    if p[I_SQUEEZE] != 0.0:  # Q = -int_0^X u2_dot = -sum_n q_dot_n W_n(X)
        offs, offv = int(p[I_OFF_SXT]), int(p[I_OFF_VXT])
        if offs < 0 or offv < 0 or oQ < 0 or N < 0:
            return 0.0
        for n in range(N):
            b = (n + 1) * beta1
            cq = ws[w + N + n] * y[oq + N + n] / b
            sq = ws[w + n] * y[oq + N + n] / b
            bv = offv + n * nodes
            bs = offs + n * nodes
            for j in range(nodes):
                ws[oQ + j] -= p[bv + j] * cq + p[bs + j] * sq
    total = _film_side(1.0, N, V_r, p, ws, F, oF)
    if p[I_SIDES] == 2.0:
        total += _film_side(-1.0, N, V_r, p, ws, F, oF)
    return total


@numba.njit(cache=True)
def film_loads(t, y, p):
    """Modal film forces [N] and the resultant film force along +j [N] at ``(t, y)``."""
    N = int(p[I_N])
    F = np.zeros(N)
    if p[I_FILM] == 0.0:
        return F, 0.0
    kin = _kin(t, p)
    total = _film_loads(y, np.int64(0), N, kin[3], kin[4], p, np.empty(int(p[I_WORK])), F, np.int64(0))
    return F, total


@numba.njit(cache=True)
def film_force_many(t, y, p):
    """Resultant film force along +j [N] at every sample ``(t[i], y[i])`` (``y`` of shape ``(T, 2N)``).

    The batched form of ``Model.film_loads(t, y)[1]`` for the results
    (``film_force``).
    """
    T = t.shape[0]
    out = np.zeros(T)
    if p[I_FILM] == 0.0:
        return out
    N = int(p[I_N])
    F = np.zeros(N)
    yi = np.empty(2 * N)
    ws = np.empty(int(p[I_WORK]))
    for i in range(T):
        for m in range(2 * N):
            yi[m] = y[i, m]
        kin = _kin(t[i], p)
        out[i] = _film_loads(yi, np.int64(0), N, kin[3], kin[4], p, ws, F, np.int64(0))
    return out


# --- thinnest film, gap, contact --------------------------------------------------------------
@numba.njit(cache=True)
def _u2_derivatives(y, oq, N, x, beta1, ws, osc):
    """``u2``, ``u2'``, ``u2''`` at ``x`` (``ws[osc:osc + 2N]`` is scratch)."""
    _modal_sincos(x, beta1, N, ws, osc)
    u = 0.0
    d1 = 0.0
    d2 = 0.0
    for n in range(N):
        b = (n + 1) * beta1
        q = y[oq + n]
        u += ws[osc + n] * q
        d1 += ws[osc + N + n] * b * q
        d2 += ws[osc + n] * b * b * q
    return u, d1, -d2


@numba.njit(cache=True)
def _thinnest_side(side, y, oq, N, x0, p, ws, ous, n_s, osc):
    """:func:`lubelink.contact.thinnest_film` on ``side * q``; ``ws[ous:ous + n_s]`` holds ``u2`` at the samples.

    Returns ``(xi_min, x_c, at_edge)``.
    """
    pad = p[I_PAD]
    beta1 = math.pi / p[I_L]
    stop = x0 + pad
    step = (stop - x0) / (n_s - 1)
    i = 0
    best = -np.inf
    for k in range(n_s):
        if side * ws[ous + k] > best:
            best = side * ws[ous + k]
            i = k
    xi_i = stop if i == n_s - 1 else i * step + x0
    if i == 0 or i == n_s - 1:
        d1 = side * _u2_derivatives(y, oq, N, xi_i, beta1, ws, osc)[1]
        inward = d1 < 0.0 if i == 0 else d1 > 0.0
        if inward:
            return 0.5 * p[I_H] - best, xi_i, True
    x = xi_i
    k_lo = max(i - 1, 0)
    k_hi = min(i + 1, n_s - 1)
    lo = stop if k_lo == n_s - 1 else k_lo * step + x0
    hi = stop if k_hi == n_s - 1 else k_hi * step + x0
    for _ in range(8):
        _, d1, d2 = _u2_derivatives(y, oq, N, x, beta1, ws, osc)
        d1 *= side
        d2 *= side
        if d2 >= 0.0:
            break
        x_new = min(max(x - d1 / d2, lo), hi)
        if abs(x_new - x) < 1e-15 * max(1.0, abs(x)):
            x = x_new
            break
        x = x_new
    u_x = side * _u2_derivatives(y, oq, N, x, beta1, ws, osc)[0]
    if u_x < best:
        x, u_x = xi_i, best
    edge = x <= x0 or x >= x0 + pad
    return 0.5 * p[I_H] - u_x, x, edge


@numba.njit(cache=True)
def _thinnest(y, oq, N, x_star, p, ws, only_side):
    """Thinnest film over the sides (or on ``only_side`` if non-zero): ``(xi, x_c, at_edge, side)``."""
    x0 = _pad_start(x_star, p)
    n_s = int(p[I_SAMPLES])
    beta1 = math.pi / p[I_L]
    w = 4 * N + 8 * int(p[I_NODES])  # scratch: 2 N + samples (after the film's)
    ous = w + 2 * N
    _modal_sincos(x0, beta1, N, ws, w)
    _pad_deflection(y, oq, N, p, ws, w, int(p[I_OFF_SKT]), int(p[I_OFF_CKT]), n_s, ous)
    if only_side != 0.0:
        xi, xc, edge = _thinnest_side(only_side, y, oq, N, x0, p, ws, ous, n_s, w)
        return xi, xc, edge, only_side
    xi, xc, edge = _thinnest_side(1.0, y, oq, N, x0, p, ws, ous, n_s, w)
    side = 1.0
    if p[I_SIDES] == 2.0:
        xi2, xc2, edge2 = _thinnest_side(-1.0, y, oq, N, x0, p, ws, ous, n_s, w)
        if xi2 < xi:
            xi, xc, edge, side = xi2, xc2, edge2, -1.0
    return xi, xc, edge, side


@numba.njit(cache=True)
def thinnest_film(t, y, p):
    """:meth:`lubelink.model.Model.thinnest_film`: ``(xi_min, x_c, at_edge, side)``."""
    N = int(p[I_N])
    kin = _kin(t, p)
    return _thinnest(y, np.int64(0), N, kin[3], p, np.empty(int(p[I_WORK])), 0.0)


@numba.njit(cache=True)
def gap(t, y, p):
    """:meth:`lubelink.model.Model.gap`: thinnest film minus ``min_film`` [m]."""
    return thinnest_film(t, y, p)[0] - p[I_MIN_FILM]


@numba.njit(cache=True)
def event(t, y, p):
    """The segment's event function: ``gap`` (event sign -1) or ``-gap`` (+1), per ``p``."""
    return p[I_EVENT] * gap(t, y, p)


@numba.njit(cache=True)
def _contact_force(y, oq, N, x_star, V_r, p, ws, F, oF):
    """Add the compliant contact's modal force to ``F[oF:oF + N]``; return its magnitude [N]."""
    side = p[I_PHASE_SIDE]
    xi, x_c, at_edge, _ = _thinnest(y, oq, N, x_star, p, ws, side)
    delta = p[I_MIN_FILM] - xi
    if delta <= 0.0:
        return 0.0
    V_c = V_r if at_edge else 0.0
    beta1 = math.pi / p[I_L]
    w = 6 * N + 8 * int(p[I_NODES]) + int(p[I_SAMPLES])  # scratch: 2 N (after the thinnest film's)
    _modal_sincos(x_c, beta1, N, ws, w)
    a = 0.0
    b = 0.0
    for n in range(N):
        a += ws[w + n] * (side * y[oq + N + n])
        b += ((n + 1) * beta1 * ws[w + N + n]) * (side * y[oq + n])
    delta_dot = a + b * V_c
    v_minus = p[I_PHASE_V]
    e = p[I_E]
    damping = 0.75 * (1.0 - e**2) * delta_dot / v_minus if v_minus > 0.0 else 0.0
    force = max(p[I_K] * delta ** p[I_EXP] * (1.0 + damping), 0.0)
    for n in range(N):
        F[oF + n] += -side * (force * ws[w + n])
    return force


@numba.njit(cache=True)
def contact_force(t, y, p):
    """:meth:`lubelink.model.Model.contact_force` of the phase in ``p``: ``(F, magnitude)``."""
    N = int(p[I_N])
    F = np.zeros(N)
    if p[I_PHASE_SIDE] == 0.0:
        return F, 0.0
    kin = _kin(t, p)
    force = _contact_force(y, np.int64(0), N, kin[3], kin[4], p, np.empty(int(p[I_WORK])), F, np.int64(0))
    return F, force


# --- right-hand side ------------------------------------------------------------------------------
@numba.njit(cache=True)
def rhs(t, y, out, p):
    """:meth:`lubelink.model.Model.rhs` (with the phase in ``p``), written into ``out``.

    The modal forces are accumulated in ``out[N:]`` before the accelerations
    replace them.
    """
    N = int(p[I_N])
    L = p[I_L]
    offo = int(p[I_OFF_OMEGA])
    if N < 0 or offo < 0:
        return  # (never) lets LLVM drop Numba's negative-index wraparound
    A_O2, omega, alpha, x_star, V_r, Y_ddot, c_th, s_th = _kin(t, p)
    for n in range(N):
        out[N + n] = 0.0
    ws = np.empty(int(p[I_WORK]))
    if p[I_FILM] != 0.0:
        _film_loads(y, np.int64(0), N, x_star, V_r, p, ws, out, N)
    beta1 = math.pi / L
    if p[I_MC] > 0.0:
        R = -p[I_MC] * Y_ddot / c_th
        for n in range(N):
            out[N + n] += R * math.sin((n + 1) * beta1 * x_star)
    if p[I_PHASE_SIDE] != 0.0:
        _contact_force(y, np.int64(0), N, x_star, V_r, p, ws, out, N)
    gX, gY = p[I_GX], p[I_GY]
    A_eff = A_O2
    if gX != 0.0 or gY != 0.0:
        psi = -math.asin(p[I_OA] / p[I_L_KIN] * math.sin(p[I_W0] * t))
        A_eff = A_O2 - (-gX * math.sin(psi) + gY * math.cos(psi))
    mass = p[I_MASS]
    zeta = p[I_ZETA]
    for n in range(N):
        beta = (n + 1) * beta1
        sign = 1.0 if n % 2 == 0 else -1.0
        rigid = -2.0 / (L * beta) * (A_eff * (1.0 + sign) + alpha * L * sign)
        wn = p[offo + n]
        forcing = rigid + out[N + n] / mass
        out[N + n] = -(wn**2 - omega**2) * y[n] - 2.0 * zeta * wn * y[N + n] + forcing
    for n in range(N):
        out[n] = y[N + n]


# --- results: the pad pressure of many samples -------------------------------------------------------
@numba.njit(cache=True)
def _pad_pressure_kernel(t, y, p, side, h, w, smat, SP, CP, out):
    """``out[i]``: gauge pressure at the pad breaks for sample ``i`` (see :func:`pad_pressure_many`)."""
    T = t.shape[0]
    N = int(p[I_N])
    M = h.shape[0]
    n = w.shape[0]
    P = M * n
    beta1 = math.pi / p[I_L]
    mu = p[I_MU]
    half = 0.5 * p[I_H]
    squeeze = p[I_SQUEEZE] != 0.0
    clip = p[I_CAV] == 1.0
    sc = np.empty(2 * N)
    u = np.empty(P)
    ud = np.empty(P)
    for i in range(T):
        kin = _kin(t[i], p)
        x0 = _pad_start(kin[3], p)
        V_r = kin[4]
        _modal_sincos(x0, beta1, N, sc, np.int64(0))
        for k in range(P):
            u[k] = 0.0
            ud[k] = 0.0
        for m in range(N):  # u2 and u2_dot at the points: sin(b (x0 + X)) = s0 cos(b X) + c0 sin(b X)
            a = sc[m] * y[i, m]
            b = sc[N + m] * y[i, m]
            ad = sc[m] * y[i, N + m]
            bd = sc[N + m] * y[i, N + m]
            for k in range(P):
                u[k] += CP[m, k] * a + SP[m, k] * b
                ud[k] += CP[m, k] * ad + SP[m, k] * bd
        I1 = 0.0
        I2 = 0.0
        I3 = 0.0
        Q0 = 0.0  # int_0 xi_t up to the start of the piece
        out[i, 0] = 0.0
        for piece in range(M):
            a1 = 0.0
            a2 = 0.0
            a3 = 0.0
            aq = 0.0
            for j in range(n):
                k = piece * n + j
                xi = half - side * u[k]
                wt = h[piece] * w[j]
                inv3 = xi**-3
                a1 += wt * xi**-2
                a2 += wt * inv3
                if squeeze:
                    Qj = 0.0  # int of xi_t = -side u2_dot from the piece start to node j
                    for l in range(n):
                        Qj += smat[j, l] * (-side * ud[piece * n + l])
                    a3 += wt * (Q0 + h[piece] * Qj) * inv3
                    aq += wt * (-side * ud[k])
            I1 += a1
            I2 += a2
            I3 += a3
            Q0 += aq
            out[i, piece + 1] = I1  # cumulative integrals for now; the pressure below
            out[i, M + 1 + piece + 1] = I2
            out[i, 2 * (M + 1) + piece + 1] = I3
        C = -(6.0 * mu * V_r * I1 + 12.0 * mu * I3) / I2
        for b in range(M + 1):
            c1 = out[i, b] if b > 0 else 0.0
            c2 = out[i, M + 1 + b] if b > 0 else 0.0
            c3 = out[i, 2 * (M + 1) + b] if b > 0 else 0.0
            pg = 6.0 * mu * V_r * c1 + C * c2 + 12.0 * mu * c3
            out[i, b] = max(pg, p[I_PCAV]) if clip else pg


def pad_pressure_many(model, t, y, X, side=1, nodes=8):
    """Gauge pressure [Pa] on the pad at ``X`` for many samples: the batched form of the results' pressure.

    Computes what :func:`lubelink.film.pad_pressure` (``nodes`` Gauss-Legendre
    nodes between consecutive points of ``X``) gives for the film of side
    ``side`` at every sample, clipped at the cavitation pressure for
    ``"half-sommerfeld"`` -- the ``pressure`` of the results
    (:func:`lubelink.simulate.to_dataset`).

    Parameters
    ----------
    model : lubelink.model.Model
        A model the kernels support (:func:`supported`).
    t : ndarray, shape ``(T,)``
        Sample times [s].
    y : ndarray, shape ``(T, 2N)``
        States at ``t``.
    X : ndarray, shape ``(M + 1,)``
        Increasing pad positions from 0 to ``l`` [m].
    side : {1, -1}
        Film at ``H/2 - u2`` (1) or ``H/2 + u2`` (-1).

    Returns
    -------
    ndarray, shape ``(T, M + 1)``
    """
    from .film import _integration_matrix, gauss_legendre

    X = np.asarray(X, dtype=float)
    s, w = gauss_legendre(nodes)
    h = np.diff(X)
    pts = (X[:-1, None] + h[:, None] * s).ravel()
    beta = np.arange(1, model.modes + 1) * np.pi / model.config.mechanism.rod_length
    bp = np.outer(beta, pts)
    t = np.ascontiguousarray(t, dtype=float)
    y = np.ascontiguousarray(y, dtype=float)
    out = np.empty((t.size, 3 * X.size))  # room for the cumulative integrals
    _pad_pressure_kernel(t, y, pack(model), float(side), h, np.ascontiguousarray(w),
                         np.ascontiguousarray(_integration_matrix(nodes)), np.sin(bp), np.cos(bp), out)
    return out[:, :X.size].copy()
