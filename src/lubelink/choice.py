"""Which integration method a configuration gets: ``solver.method``, or for ``"auto"`` the one measured fastest.

:func:`method_name` is what :func:`lubelink.simulate.run`, the cost estimate and the first-run
policy read; :func:`stiff_reason` decides when the film is stiff (docs/model.md sections 7.1, 7.5).
"""

from __future__ import annotations

from .film.jacobian import squeeze_rate

__all__ = ["method_name", "method_choice", "stiff_reason", "film_squeeze_rate", "STIFF_RATIO", "NONSTIFF_STEP"]


#: ``"auto"`` takes the stiff method where the squeeze film's linearised rate times
#: :data:`NONSTIFF_STEP` exceeds this: measured on ``lubricated`` with 3 and 7 modes, RODAS4 and the
#: exponential method take the same time at 3 mm of clearance (0.19), RODAS4 is 1.5-1.9x faster at
#: 2 mm (0.65) and 2.9-3.3x at 0.5 mm (docs/model.md section 7.5).
STIFF_RATIO = 0.3
#: The step [s] the non-stiff methods take on the paper's mechanism without a film (2 s in about 850 steps).
NONSTIFF_STEP = 2.4e-3


def film_squeeze_rate(config) -> float:
    """:func:`~lubelink.film.jacobian.squeeze_rate` of the link's film [1/s] (0: none); of the spatial link with
    films on both pairs of faces, the larger of the ``u2`` faces' (pad width ``b``) and the ``u3`` faces' (``h``)."""
    if not config.film.enabled:
        return 0.0
    b = config.beam
    mass = 0.5 * b.density * b.width * b.height * config.mechanism.rod_length
    widths = (b.width, b.height) if config.beam.model == "spatial" and config.film.faces == "u2+u3" else (b.width,)
    return max(squeeze_rate(config.film, width, mass) for width in widths)


def stiff_reason(config) -> str:
    """Why ``config`` is stiff for the explicit and exponential methods (``""``: it is not)."""
    rate = film_squeeze_rate(config)
    if rate * NONSTIFF_STEP <= STIFF_RATIO:
        return ""
    return (f"stiff: the squeeze film damps at {rate:.3g} 1/s, {rate * NONSTIFF_STEP:.3g} times the step of "
            f"{NONSTIFF_STEP:g} s the explicit methods take")


def method_choice(config):
    """``(method, why)``: :func:`method_name`, and why ``"auto"`` chose the stiff method (else ``""``)."""
    name = method_name(config)
    return name, (f"auto: {stiff_reason(config)}" if config.solver.method == "auto" and name == "rodas" else "")


def method_name(config):
    """The integration method that ``solver.method`` names.

    ``"auto"``: ``rodas`` for a stiff film (:func:`stiff_reason`, planar or spatial); the exponential Adams method of order six for a planar link without a film or
    without a contact law (two evaluations a step; at the default tolerances 1.5-2.5x faster than
    the exponential Runge-Kutta method and DOP853, within 0.11 um of a tight reference, and at
    equal error on par or faster: benchmarks/README.md); otherwise, a film with impacts or the
    spatial link, DOP853 for one mode and the exponential Runge-Kutta method for more (impacts
    amplify the Adams method's larger error, the spatial link's coupling holds its steps short:
    docs/model.md section 7.1).
    """
    m = config.solver.method
    if m != "auto":
        return m
    if stiff_reason(config):
        return "rodas"
    if config.beam.model == "planar" and (config.film.model == "none" or config.contact.law == "none"):
        return "exponential-adams"
    return "DOP853" if config.beam.modes == 1 else "exponential"
