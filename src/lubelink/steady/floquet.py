"""Floquet multipliers of a periodic orbit and how they cross the unit circle.

The multipliers are the eigenvalues of the monodromy matrix ``M = dP/dy`` (the period map's
Jacobian at its fixed point). The orbit is asymptotically stable when every multiplier lies
inside the unit circle. Along a branch of orbits a multiplier leaves the circle

* through +1: a fold (limit point; the branch turns back) or a branch point;
* through -1: a period doubling (flip);
* as a complex pair: a Neimark-Sacker (torus) bifurcation.

A branch of neutral orbits (every multiplier on the circle: an undamped linear link) has instead a
*resonance* where a multiplier passes +1 along the circle: a pole of the forced response.

Every multiplier carries an accuracy estimate (:func:`multiplier_errors`: its distance from the
same multiplier of a second, less accurate monodromy matrix), and the tests use it as their
margin: a multiplier whose distance from the unit circle is within its error is *undecided*, so
an orbit with one is not called stable, and a crossing is reported only when the number of
multipliers outside the circle changes by more than the undecided ones allow.

Pure linear algebra on matrices (SciPy); nothing here knows the model.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["multipliers", "multiplier_errors", "max_modulus", "is_stable", "outside", "undecided", "outside_range",
           "Crossing", "crossing", "KINDS", "ROUNDING"]

#: The kinds of crossing :func:`crossing` reports.
KINDS = ("fold", "branch point (+1)", "period doubling (-1)", "Neimark-Sacker (complex pair)",
         "resonance (+1 on the circle)")


def multipliers(monodromy):
    """Eigenvalues of ``monodromy``, largest modulus first (ties: by argument) [complex]."""
    import scipy.linalg

    mu = scipy.linalg.eigvals(np.asarray(monodromy, dtype=float))
    order = np.lexsort((np.angle(mu), -np.abs(mu)))
    return mu[order]


#: The smallest accuracy estimate of a multiplier, relative to the largest modulus [-]: rounding in the
#: eigenvalues of a matrix known to the last bits.
ROUNDING = 1e-12


def multiplier_errors(mu, check, scale=1.0):
    """Accuracy estimate of each multiplier ``mu`` [-]: its distance from the eigenvalue of ``check`` paired with it.

    ``check`` is a second, less accurate monodromy matrix (a looser tolerance of the variational
    equations, a larger difference step), so the distance estimates the error of the less accurate
    one and bounds that of ``mu``. The pairing minimises the sum of distances (one eigenvalue each;
    near a double multiplier the estimate is then the splitting, as large as the error there is).
    No ``check`` (an exact Jacobian): rounding only, :data:`ROUNDING` times ``max(1, |mu|)``.
    ``scale`` multiplies the estimate (a safety factor).
    """
    mu = np.asarray(mu, dtype=complex)
    floor = ROUNDING * max(1.0, max_modulus(mu))
    if check is None:
        return np.full(mu.size, floor)
    from scipy.optimize import linear_sum_assignment

    other = multipliers(check)
    cost = np.abs(mu[:, None] - other[None, :])
    rows, cols = linear_sum_assignment(cost)
    err = np.empty(mu.size)
    err[rows] = cost[rows, cols]
    return np.maximum(scale * err, floor)


def max_modulus(mu) -> float:
    """Largest modulus of the multipliers ``mu`` [-] (0 for none)."""
    return float(np.max(np.abs(mu))) if len(mu) else 0.0


def is_stable(mu, margin=1e-7) -> bool:
    """Whether every multiplier is inside the unit circle by more than ``margin`` (its accuracy: a scalar or one each).

    An orbit with a multiplier on the circle (an undamped linear link: all of them) is not
    asymptotically stable, whichever side rounding puts it.
    """
    mu = np.asarray(mu)
    return bool(mu.size == 0 or np.all(np.abs(mu) < 1.0 - np.asarray(margin)))


def outside(mu, margin=1e-7) -> int:
    """How many multipliers lie outside the unit circle by more than ``margin`` (a scalar or one each)."""
    return int(np.sum(np.abs(np.asarray(mu)) > 1.0 + np.asarray(margin)))


def undecided(mu, margin=1e-7) -> int:
    """How many multipliers lie within ``margin`` of the unit circle: neither inside nor outside."""
    return int(np.sum(np.abs(np.abs(np.asarray(mu)) - 1.0) <= np.asarray(margin)))


def outside_range(mu, margin=1e-7) -> tuple:
    """``(fewest, most)`` multipliers that may lie outside the circle: the undecided ones either way."""
    lo = outside(mu, margin)
    return lo, lo + undecided(mu, margin)


class Crossing(NamedTuple):
    """A multiplier crossing the unit circle between two orbits of a branch.

    ``kind`` is one of :data:`KINDS`; ``fraction`` in [0, 1] locates the crossing between the two
    orbits (linear in ``|mu| - 1``); ``multiplier`` is the crossing multiplier on the outer side.
    """

    kind: str
    fraction: float
    multiplier: complex


def crossing(mu_a, mu_b, margin=1e-7, real_tol=1e-6, margin_b=None, known=None) -> Crossing | None:
    """How the multipliers change from ``mu_a`` to ``mu_b`` (two neighbouring orbits), or None.

    A crossing is reported when the number of multipliers outside the circle certainly changes:
    the ranges :func:`outside_range` of the two orbits (with their margins ``margin`` and
    ``margin_b``, default ``margin``; ``known`` replaces the range of ``mu_a``, e.g. what the
    orbits since the last crossing allow) do not overlap. The crossing multipliers are then the
    outer ones nearest the circle on the side with more outside; a complex pair (imaginary part
    above ``real_tol`` of the modulus) is a Neimark-Sacker crossing, a real positive one ``+1``,
    a real negative one ``-1``. Whether a ``+1`` crossing is a fold is for the caller to say (the
    branch's parameter turns back there).
    """
    mu_a, mu_b = np.asarray(mu_a), np.asarray(mu_b)
    margin_b = margin if margin_b is None else margin_b
    lo_a, hi_a = outside_range(mu_a, margin) if known is None else known
    lo_b, hi_b = outside_range(mu_b, margin_b)
    if lo_b <= hi_a and lo_a <= hi_b:
        return None
    up = lo_b > hi_a
    more, fewer, m_more = (mu_b, mu_a, margin_b) if up else (mu_a, mu_b, margin)
    out = more[np.abs(more) > 1.0 + np.asarray(m_more)]
    if out.size == 0:  # the outer side was known from earlier orbits only: the nearest to the circle there
        out = more[np.abs(more) > 1.0] if np.any(np.abs(more) > 1.0) else more
    mu = out[np.argmin(np.abs(out))]
    if abs(mu.imag) > real_tol * abs(mu):
        kind = KINDS[3]
    elif mu.real > 0:
        kind = KINDS[1]
    else:
        kind = KINDS[2]
    partner = fewer[np.argmin(np.abs(fewer - mu))]  # the same multiplier at the other orbit
    m_out, m_in = abs(mu) - 1.0, abs(partner) - 1.0
    frac = m_in / (m_in - m_out) if m_in != m_out else 0.5
    frac = float(np.clip(frac, 0.0, 1.0))
    return Crossing(kind, frac if up else 1.0 - frac, complex(mu))
