"""Periodic steady state: shooting, Floquet stability, and response curves over a parameter.

With damping the link settles, after a transient, on a response with the period of the crank;
without damping (and with the paper's wedge-only film, which is volume-preserving) it never
does, but the periodic response still exists and organises the motion. This package finds it
directly, by shooting on the period map ``y0 -> y(T)``, says whether it is stable (Floquet
multipliers), and follows it as a parameter varies (pseudo-arclength continuation), detecting
folds and Floquet bifurcations. docs/periodic.md is the guide. The state is the model's whole
integration state, ``[q, q_dot]`` of the planar model or ``[q1, q2, q3, q1_t, q2_t, q3_t]`` of the
spatial one (``beam.model = "spatial"``), whose results add the axial and out-of-plane quantities.

===================  ===========================================================================
module               job
===================  ===========================================================================
``shooting``         damped Newton on ``P(y) = y`` for any map; finite-difference Jacobians
``variational``      the flow's Jacobian from the variational equations (any right-hand side)
``saltation``        the Jacobian's jump at an event (saltation matrix) and the monodromy through events
``floquet``          multipliers, stability, how a multiplier crosses the unit circle
``arclength``        pseudo-arclength continuation of the fixed points of ``P(y, lam)``
``problem``          lubelink's period map: :func:`lubelink.simulate.run` from a state, over one
                     period; the map as a function of a configuration key (:class:`Family`)
``orbit``            :func:`periodic`: one periodic response as a results Dataset
``branch``           :func:`continuation`: the response curve as a Dataset
``plot``             the response-curve figure (Matplotlib, imported lazily)
``cli``              ``lubelink periodic``, ``lubelink continue``, ``lubelink plot-branch``
===================  ===========================================================================

``shooting``, ``variational``, ``saltation``, ``floquet`` and ``arclength`` know nothing of the model: they
see a map ``fmap(y, jacobian) -> MapValue`` (and, for continuation, ``family(lam) -> fmap``).
"""

from __future__ import annotations

from .branch import continuation, find_branch
from .cli import register_cli
from .orbit import PeriodicOrbit, find_periodic, periodic
from .shooting import MapFailure, ShootingError

__all__ = ["periodic", "continuation", "find_periodic", "find_branch", "PeriodicOrbit", "ShootingError",
           "MapFailure", "register_cli", "figure_branch", "plot_branch"]


def __getattr__(name):  # the plotting functions, without importing Matplotlib with the package
    if name in ("figure_branch", "plot_branch"):
        from . import plot

        return getattr(plot, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
