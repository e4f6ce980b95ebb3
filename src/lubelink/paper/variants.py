"""The equations of motion as printed in the paper, to show what the errata change.

:func:`simulate_variant` runs a configuration with lubelink's corrected
equations or with one of the printed variants of :data:`VARIANTS`: a motion
provider with the printed acceleration (``"double-count"``) and/or a
:class:`PrintedModel` with the printed signs (``"printed-omega2"``,
``"printed-film-sign"``), integrated by :func:`_run_model` on the reference
(NumPy) integrator, whose right-hand side is ``model.rhs``.

Everything about the variants lives here (nothing else in the package knows
how they are built), and this module and :mod:`lubelink.paper.calibration`
are the only ones that call the simulation core (``build_model``, ``run``,
``to_dataset``, ``reference_segment_integrator``) directly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import suggest
from ..model import Model
from .calibration import _event_resolution

__all__ = ["VARIANTS", "PrintedModel", "simulate_variant"]

#: Variants of the equations of motion (:func:`simulate_variant`).
VARIANTS = {
    "corrected": "corrected equations (lubelink)",
    "printed-omega2": "Eq. 18 as printed: +omega^2 q_n (stiffening)",
    "double-count": "Eq. 18 as printed: A_O2 + omega v_O1 (omega v_O1 counted twice)",
    "printed": "Eq. 18 as printed: both of the above",
    "printed-film-sign": "Eq. 20 as printed: film force +B p_g (gauge)",
}


def _variant_model(config, variant):
    """The model of ``config`` with the equations of ``variant`` (see :data:`VARIANTS`)."""
    from dataclasses import fields

    from ..kinematics import PrescribedMotion, SliderCrank, slider_crank
    from ..model import build_model

    if variant not in VARIANTS:
        raise ValueError(f"variant = {variant!r}: must be one of {', '.join(VARIANTS)}"
                         + suggest(variant, VARIANTS))
    motion = None
    if variant in ("double-count", "printed"):
        m = config.mechanism
        crank = SliderCrank(m)

        def kin(name):
            return lambda t: slider_crank(t, m.crank_length, m.rod_length, m.crank_speed,
                                          m.guide_distance)[name]

        def a_printed(t):
            k = slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
            return k["A_O2"] + k["omega"] * k["v_O1"]

        motion = PrescribedMotion(A_O2=a_printed, omega=kin("omega"), alpha=kin("alpha"),
                                  x_star=kin("x_star"), V_r=kin("V_r"),
                                  reaction=lambda t: crank.joint_reaction(t, config.collar.mass),
                                  angle=crank.link_angle)
    base = build_model(config, motion)
    if variant in ("corrected", "double-count"):
        return base
    stiffening = variant in ("printed-omega2", "printed")
    film_sign = -1.0 if variant == "printed-film-sign" else 1.0
    return PrintedModel(**{f.name: getattr(base, f.name) for f in fields(Model)},
                        stiffening=stiffening, film_sign=film_sign)


@dataclass(frozen=True)
class PrintedModel(Model):
    """:class:`lubelink.model.Model` with some of the paper's printed signs.

    ``stiffening``: ``+omega^2 q_n`` in the modal equation (Eq. 18 as
    printed) instead of the corrected ``-omega^2 q_n``, i.e. an extra
    ``-2 omega^2 q_n`` in ``q_ddot``. ``film_sign = -1``: the film force of
    Eq. 20 as printed, ``+B p_g`` on the link (gauge pressure kept).
    """

    stiffening: bool = False
    film_sign: float = 1.0

    def film_loads(self, t, y, kin=None):
        F, total = Model.film_loads(self, t, y, kin)
        return self.film_sign * F, self.film_sign * total

    def rhs(self, t, y, phase=None):
        dy = Model.rhs(self, t, y, phase)
        if self.stiffening:
            N = self.modes
            dy[N:] -= 2.0 * float(self.motion(t).omega) ** 2 * y[:N]
        return dy


def simulate_variant(source="paper", set=None, variant="corrected"):
    """Simulate with the corrected equations or one of the paper's printed variants.

    Parameters
    ----------
    source, set
        As for :func:`lubelink.simulate`.
    variant : str
        A key of :data:`VARIANTS`: ``"corrected"`` (lubelink's equations),
        ``"printed-omega2"`` (``+omega^2`` of Eq. 18), ``"double-count"``
        (``A_O2 + omega v_O1`` of Eq. 18 with Section 6's true ``a_O2``),
        ``"printed"`` (both) or ``"printed-film-sign"`` (Eq. 20's ``+B p_g``).

    Returns
    -------
    xarray.Dataset
        As :func:`lubelink.simulate`, with ``attrs["variant"]``.

    Raises
    ------
    ValueError
        For an unknown variant, or a variant other than ``"corrected"`` with
        a contact law (the variants are for impact-free runs).
    """
    from ..config import resolve
    from ..simulate import Run, run, to_dataset

    config = resolve(source, set)
    if variant == "corrected":
        ds = to_dataset(run(config))
    else:
        if config.contact.law != "none":
            raise ValueError(f"variant {variant!r} is available for contact.law = 'none' only")
        ds = to_dataset(_run_model(config, _variant_model(config, variant), Run))
    ds.attrs["variant"] = variant
    return ds


def _run_model(config, model, run_class):
    """Impact-free run of ``model`` from zero initial conditions, as :func:`lubelink.simulate.run`.

    Always on the reference (NumPy) segment integrator, which calls
    ``model.rhs``: the variants live in that method.
    """
    import time

    from ..simulate import reference_segment_integrator

    start = time.perf_counter()
    s = config.solver
    n_out = int(np.floor(s.t_end / s.output_step * (1 + 1e-12))) + 1
    t_eval = np.arange(n_out) * s.output_step
    y0 = model.initial_state()
    monitored = config.film.enabled or config.contact.law != "none"
    segment = reference_segment_integrator(model)
    seg = segment(0.0, y0, s.t_end, t_eval[1:], phase=None, event_sign=-1 if monitored else None,
                  event_resolution=_event_resolution(model), deadline=None, progress=None)
    out = run_class(model=model, t=np.concatenate([t_eval[:1], seg.t]),
                    y=np.concatenate([y0[None, :], seg.y]), nfev=seg.nfev, nsteps=seg.nsteps)
    if seg.status == "event":
        out.status, out.message = "film_breakdown", f"the film broke down at t = {seg.t_final:.9g} s"
    elif seg.status != "finished":
        out.status, out.message = "solver_failure", seg.message
    out.wall_time = time.perf_counter() - start
    return out
