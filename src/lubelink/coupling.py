"""The driven crank and the elastic link coupled both ways: a waveform relaxation (docs/model.md, section 3.8).

With ``drive.coupling = "two-way"`` the torque the link's elastic motion puts on the crank
(:func:`lubelink.link.drive.elastic_torque`) enters the crank's equation. The link's compiled model takes the
rigid motion from a table, so instead of making the crank angle a state of it (every kernel's signature would
change), crank and link are iterated over the whole run (Gauss-Seidel):

0. the crank alone (:func:`~lubelink.link.drive.driven_motion`) -> its sampled motion -> a run of the link;
k. the crank with the elastic torque of run k-1 (a spline of it in time) -> a new sampled motion -> run k,

until the crank speed changes by at most :func:`tolerance` between two iterations, over the time the
link ran (a run that stops early, at film breakdown say, is coupled up to its stop). The method knows the
link only as ``run_link(motion) -> Run`` (:func:`relax`), so the integrators and kernels are those of a
one-way run; its cost is the number of link runs times that of one. A run longer than 1.5
:data:`WINDOW_TURNS` crank turns is relaxed in windows of that many turns (:func:`relax_windows`), each started
from the converged state at the end of the one before: the contraction of a waveform relaxation worsens with the
length of its interval, so the whole run's iterations grow with it, a window's do not.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .derived import modal_accelerations
from .link.drive import driven_motion, elastic_torque, integrate_crank, join_cranks, motion_of, rigid_masses
from .link.reactions import link_inertia
from .link.section import taper

__all__ = ["MAX_ITERATIONS", "TOLERANCE_FACTOR", "CRANK_RTOL_FACTOR", "WINDOW_TURNS", "CouplingError", "Coupling",
           "ElasticTorque", "tolerance", "run_torque", "relax", "relax_windows"]

#: The crank's integration tolerance in the iterations: this times ``solver.rtol`` (at least 1e-13). Its error
#: in the crank speed stays 1e3 below :func:`tolerance`'s; the elastic torque's spline (C2 at the link's
#: samples) and its higher modes make the crank's integrator take 2-3x fewer steps than at the one-way 1e-11.
CRANK_RTOL_FACTOR = 1e-3

#: Link runs after which a relaxation that has not converged is refused (:class:`CouplingError`).
MAX_ITERATIONS = 8

#: The relaxation stops where the crank speed changes by at most this times ``solver.rtol`` times its
#: largest value (:func:`tolerance`).
TOLERANCE_FACTOR = 100.0


class CouplingError(RuntimeError):
    """The two-way relaxation of crank and link did not converge (the message gives its changes)."""


@dataclass
class Coupling:
    """How the relaxation went: the largest change of the crank speed [rad/s] at each iteration (``changes``;
    the first is the one-way model's miss), the link runs (``runs``), the stopping ``tolerance`` [rad/s] and the
    wall time of the crank's integrations (``crank_time``) [s]. Relaxed in windows (:func:`relax_windows`):
    ``windows`` holds ``(start [s], changes)`` of each window, ``changes`` the largest k-th change over them,
    ``tolerance`` the largest of theirs."""

    changes: list = field(default_factory=list)
    runs: int = 0
    tolerance: float = 0.0
    crank_time: float = 0.0
    windows: list = field(default_factory=list)

    @property
    def contraction(self) -> float:
        """The measured contraction factor: the ratio of the last two changes (NaN with fewer than two)."""
        return self.changes[-1] / self.changes[-2] if len(self.changes) > 1 and self.changes[-2] > 0 else np.nan


class ElasticTorque:
    """The link's elastic torque on the crank [N m] as a callable of time [s]: a C2 cubic spline of its samples,
    zero after the last (where the link did not run); ``x``, ``c`` its knots and ``PPoly`` coefficients, which
    the crank's compiled right-hand side evaluates (:class:`~lubelink.link.drive.TabulatedRates`)."""

    def __init__(self, t, torque):
        from scipy.interpolate import CubicSpline

        self.t, self.torque = np.asarray(t, dtype=float), np.asarray(torque, dtype=float)
        self._spline = CubicSpline(self.t, self.torque)
        self.x, self.c = self._spline.x, self._spline.c

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        inside = (t >= self.t[0]) & (t <= self.t[-1])
        return np.where(inside, self._spline(np.clip(t, self.t[0], self.t[-1])), 0.0)


def tolerance(config, speed) -> float:
    """Largest change of the crank speed [rad/s] between two iterations at which the relaxation stops:
    :data:`TOLERANCE_FACTOR` ``solver.rtol max |phi_dot|`` (``speed``: the crank speed's samples [rad/s])."""
    return TOLERANCE_FACTOR * config.solver.rtol * float(np.max(np.abs(speed)))


def run_torque(result):
    """``(t [s], torque [N m])``: the elastic torque on the crank of a link run (a :class:`~lubelink.results.Run`
    of a driven motion) at its samples, from its sine-mode states and their accelerations."""
    model = result.model
    cfg, N = model.config, model.modes
    L = cfg.mechanism.rod_length
    t, y = result.t, result.y
    keep = np.concatenate([[True], np.diff(t) > 0.0])  # (a sample repeated at an event: once)
    t, y = t[keep], y[keep]
    q_ddot = modal_accelerations(result, t, y)
    phi, phi_dot, phi_ddot, _ = model.motion.crank(t)
    inertia = link_inertia(result.section or taper(cfg.beam, L), cfg.beam.density, L, N)
    return t, elastic_torque(phi, phi_dot, phi_ddot, y[:, :N], y[:, N:], q_ddot, cfg.mechanism, inertia)


def relax(config, run_link, section=None, motion=None, max_iterations=MAX_ITERATIONS):
    """Iterate crank and link to their common motion; ``(run, Coupling)``.

    Parameters
    ----------
    config : Config
        A driven crank (``drive.law`` other than ``"speed"``).
    run_link : callable
        ``run_link(motion) -> Run``: one run of the link under a :class:`~lubelink.link.drive.DrivenMotion`.
    section : lubelink.link.section.Section, optional
        The link's section, for the crank's rigid inertia.
    motion : DrivenMotion, optional
        The crank alone's motion, where the caller has it (default: :func:`~lubelink.link.drive.driven_motion`).
    max_iterations : int
        Link runs at most.

    Returns
    -------
    tuple
        The last link run (its crank motion: ``run.model.motion.crank``, integrated with the elastic torque
        of the run before) and the :class:`Coupling` record.

    Raises
    ------
    CouplingError
        Where the crank speed still changes by more than :func:`tolerance` after ``max_iterations`` runs.
    """
    start = time.perf_counter()
    motion = driven_motion(config, section) if motion is None else motion
    record = Coupling(crank_time=time.perf_counter() - start)
    while True:
        result = run_link(motion)
        record.runs += 1
        t, torque = run_torque(result)
        start = time.perf_counter()
        following = driven_motion(config, section, torque=ElasticTorque(t, torque),
                                  rtol=max(CRANK_RTOL_FACTOR * config.solver.rtol, 1e-13))
        record.crank_time += time.perf_counter() - start
        before, after = motion.crank.solution(t)[1], following.crank.solution(t)[1]
        record.tolerance = tolerance(config, before)
        record.changes.append(float(np.max(np.abs(after - before))))
        if record.changes[-1] <= record.tolerance:
            return result, record
        if record.runs >= max_iterations:
            raise CouplingError(
                f"drive.coupling = 'two-way': the crank speed still changes by {record.changes[-1]:.3g} rad/s after "
                f"{record.runs} runs of the link (tolerance {record.tolerance:.3g} rad/s; changes "
                f"{', '.join(f'{c:.3g}' for c in record.changes)}; contraction {record.contraction:.3g}): the "
                "elastic torque is too large against the flywheel for the relaxation; use a larger "
                "drive.flywheel_inertia or drive.coupling = 'one-way'")
        motion = following


#: Crank turns (at ``mechanism.crank_speed``) of a window of :func:`relax_windows`: a run up to 1.5 times longer
#: is relaxed whole.
WINDOW_TURNS = 5.0


def _window_end(t_eval, start, length):
    """The end of the window from ``start`` [s]: the first sample at least ``length`` later, or the run's end
    where that leaves less than half a window."""
    i = int(np.searchsorted(t_eval, start + length * (1.0 - 1e-9)))
    return float(t_eval[-1]) if i >= t_eval.size or t_eval[-1] - t_eval[i] < 0.5 * length else float(t_eval[i])


def relax_windows(config, run_link, build, section=None, max_iterations=MAX_ITERATIONS, turns=WINDOW_TURNS):
    """:func:`relax` in windows of ``turns`` crank turns: each window's crank and link start from the state the
    converged window before ended in, so the iterations a window takes do not grow with the run; ``(run, Coupling)``.

    ``run_link(motion, t_end, y0) -> Run``: a run of the link from the state ``y0`` (None: at rest) under a
    motion whose time starts at the window's start (:func:`~lubelink.link.drive.motion_of`), for ``t_end`` [s];
    ``build(motion)``: the link's model under the whole run's motion, for the joined run. A window ends at a
    sample; where its link is inside a contact phase there, at the last free sample before. A run that stops
    early (a film breakdown) ends the relaxation there. Raises :class:`CouplingError` as :func:`relax`.
    """
    from dataclasses import replace

    from .params import sample_times

    t_eval = sample_times(config.solver)
    length = turns * 2.0 * np.pi / abs(config.mechanism.crank_speed)
    masses = rigid_masses(config, section)
    margin = 2.0 * np.pi / abs(config.mechanism.crank_speed)
    record, pieces = Coupling(), []
    start, state, y0, whole = 0.0, None, None, None
    while True:
        end = _window_end(t_eval, start, length)
        tick = time.perf_counter()
        crank = integrate_crank(config, end + margin, masses, t0=start, y0=state)
        record.crank_time += time.perf_counter() - tick
        changes = []
        while True:
            result = run_link(motion_of(crank, config, masses, start), end - start, y0)
            record.runs += 1
            t, torque = run_torque(result)
            tick = time.perf_counter()
            rtol = max(CRANK_RTOL_FACTOR * config.solver.rtol, 1e-13)
            following = integrate_crank(config, end + margin, masses, rtol, 0.1 * rtol,
                                        torque=ElasticTorque(start + t, torque), t0=start, y0=state)
            record.crank_time += time.perf_counter() - tick
            before, after = crank.solution(start + t)[1], following.solution(start + t)[1]
            bound = tolerance(config, before)
            changes.append(float(np.max(np.abs(after - before))))
            if changes[-1] <= bound:
                break
            if len(changes) >= max_iterations:
                raise CouplingError(
                    f"drive.coupling = 'two-way': in the window from {start:.6g} s the crank speed still changes by "
                    f"{changes[-1]:.3g} rad/s after {len(changes)} runs of the link (tolerance {bound:.3g} rad/s; "
                    f"changes {', '.join(f'{c:.3g}' for c in changes)}): the elastic torque is too large against the "
                    "flywheel for the relaxation; use a larger drive.flywheel_inertia or drive.coupling = 'one-way'")
            crank = following
        record.windows.append((start, changes))
        record.tolerance = max(record.tolerance, bound)
        last = result.t.size - 1
        if result.complete and end < t_eval[-1] and result.phase_side is not None:
            free = np.flatnonzero(result.phase_side == 0)
            last = int(free[-1]) if free.size and free[-1] > 0 else last
        pieces.append((start, result, last))
        whole = crank if whole is None else join_cranks(whole, crank)
        if not result.complete or end >= t_eval[-1]:
            break
        start = start + float(result.t[last])
        state, y0 = crank.solution(start), result.y[last]
    depth = max(len(c) for _, c in record.windows)
    record.changes = [max(c[k] for _, c in record.windows if len(c) > k) for k in range(depth)]
    return _joined(pieces, build(motion_of(whole, config, masses)), replace), record


def _joined(pieces, model, replace):
    """One :class:`~lubelink.results.Run` of the windows' ``(start, run, last sample)``, on ``model``."""
    out = pieces[-1][1]
    ts, ys, sides, vs, points, impacts, contacts = [], [], [], [], [], [], []
    for k, (start, r, last) in enumerate(pieces):
        stop = last + 1
        first = 0 if k == 0 else 1  # (a window's first sample is the last one of the window before)
        ts.append(start + r.t[first:stop])
        ys.append(r.y[first:stop])
        for name, store in (("phase_side", sides), ("phase_v", vs), ("phase_point", points)):
            values = getattr(r, name)
            store.append(None if values is None else values[first:stop])
        t_last = r.t[last]
        impacts += [[start + i[0], *i[1:]] for i in r.impacts if i[0] <= t_last]
        contacts += [[start + c[0], start + c[1], *c[2:]] for c in r.contacts if c[0] <= t_last]

    def glue(parts):
        return None if any(p is None for p in parts) else np.concatenate(parts)

    return replace(out, model=model, t=np.concatenate(ts), y=np.concatenate(ys), impacts=impacts, contacts=contacts,
                   phase_side=glue(sides), phase_v=glue(vs), phase_point=glue(points),
                   nfev=sum(r.nfev for _, r, _ in pieces), nsteps=sum(r.nsteps for _, r, _ in pieces),
                   wall_time=sum(r.wall_time for _, r, _ in pieces),
                   event_time=out.event_time + pieces[-1][0] if np.isfinite(out.event_time) else out.event_time)
