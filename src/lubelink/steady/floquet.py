"""Floquet multipliers of a periodic orbit and how they cross the unit circle.

The multipliers are the eigenvalues of the monodromy matrix ``M = dP/dy`` (the period map's
Jacobian at its fixed point). The orbit is asymptotically stable when every multiplier lies
inside the unit circle. Along a branch of orbits a multiplier leaves the circle

* through +1: a fold (limit point; the branch turns back) or a branch point;
* through -1: a period doubling (flip);
* as a complex pair: a Neimark-Sacker (torus) bifurcation.

Pure linear algebra on matrices (SciPy); nothing here knows the model.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["multipliers", "max_modulus", "is_stable", "outside", "Crossing", "crossing", "KINDS"]

#: The kinds of crossing :func:`crossing` reports.
KINDS = ("fold", "branch point (+1)", "period doubling (-1)", "Neimark-Sacker (complex pair)")


def multipliers(monodromy):
    """Eigenvalues of ``monodromy``, largest modulus first (ties: by argument) [complex]."""
    import scipy.linalg

    mu = scipy.linalg.eigvals(np.asarray(monodromy, dtype=float))
    order = np.lexsort((np.angle(mu), -np.abs(mu)))
    return mu[order]


def max_modulus(mu) -> float:
    """Largest modulus of the multipliers ``mu`` [-] (0 for none)."""
    return float(np.max(np.abs(mu))) if len(mu) else 0.0


def is_stable(mu, margin=1e-7) -> bool:
    """Whether every multiplier is inside the unit circle by more than ``margin``.

    An orbit with a multiplier on the circle (an undamped linear link: all of them) is not
    asymptotically stable, whichever side rounding puts it.
    """
    return max_modulus(mu) < 1.0 - margin


def outside(mu, margin=1e-7) -> int:
    """How many multipliers lie outside the unit circle by more than ``margin``."""
    return int(np.sum(np.abs(mu) > 1.0 + margin))


class Crossing(NamedTuple):
    """A multiplier crossing the unit circle between two orbits of a branch.

    ``kind`` is one of :data:`KINDS`; ``fraction`` in [0, 1] locates the crossing between the two
    orbits (linear in ``|mu| - 1``); ``multiplier`` is the crossing multiplier on the outer side.
    """

    kind: str
    fraction: float
    multiplier: complex


def crossing(mu_a, mu_b, margin=1e-7, real_tol=1e-6) -> Crossing | None:
    """How the multipliers change from ``mu_a`` to ``mu_b`` (two neighbouring orbits), or None.

    When the number of multipliers outside the circle changes, the crossing multipliers are the
    outer ones nearest the circle on the side with more outside; a complex pair (imaginary part
    above ``real_tol`` of the modulus) is a Neimark-Sacker crossing, a real positive one ``+1``,
    a real negative one ``-1``. Whether a ``+1`` crossing is a fold is for the caller to say (the
    branch's parameter turns back there).
    """
    mu_a, mu_b = np.asarray(mu_a), np.asarray(mu_b)
    n_a, n_b = outside(mu_a, margin), outside(mu_b, margin)
    if n_a == n_b:
        return None
    more, fewer = (mu_b, mu_a) if n_b > n_a else (mu_a, mu_b)
    out = more[np.abs(more) > 1.0 + margin]
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
    return Crossing(kind, frac if n_b > n_a else 1.0 - frac, complex(mu))
