"""The flow and its Jacobian: the variational equations integrated with the state.

For ``dy/dt = f(t, y)`` the Jacobian of the flow, ``Phi(t) = dy(t)/dy(t0)``, solves
``dPhi/dt = J(t, y(t)) Phi`` with ``Phi(t0) = I``, ``J = df/dy``; over one period ``Phi(T)`` is
the monodromy matrix. :func:`flow_with_jacobian` integrates the ``n + n^2`` equations together
with one of lubelink's integrators, through the generic driver, with ``J`` from the right-hand side
itself where it gives it (an ``out`` of ``n + n^2`` entries, as the stiff method asks:
:func:`lubelink.link.model.rhs`), else from central differences of the right-hand side (exact, up to
rounding, for a right-hand side linear in ``y``).

Only ``rhs(t, y, out, p)`` is known here, as in :mod:`lubelink.integrate`: no physics.
"""

from __future__ import annotations

import numpy as np

__all__ = ["augmented_rhs", "flow_with_jacobian"]


def augmented_rhs(rhs, n, steps, jacobian=False):
    """The right-hand side of ``[y, Phi]`` (``Phi`` row-major after ``y``) for ``rhs`` of size ``n``.

    Parameters
    ----------
    rhs : callable
        ``rhs(t, y, out, p)`` writing ``dy/dt`` into ``out`` (shape ``(n,)``).
    n : int
        Size of ``y``.
    steps : ndarray, shape ``(n,)``
        Difference steps of each component of ``y`` for ``J = df/dy``.
    jacobian : bool
        ``rhs`` gives ``J`` itself when handed an ``out`` of ``n + n^2`` entries (one evaluation
        instead of ``2 n + 1``; ``steps`` unused).
    """
    steps = np.asarray(steps, dtype=float)
    f_plus = np.empty(n)
    f_minus = np.empty(n)
    y_step = np.empty(n)
    J = np.empty((n, n))
    both = np.empty(n + n * n)

    def aug(t, z, out, p):
        y = np.ascontiguousarray(z[:n])
        if jacobian:
            rhs(t, y, both, p)
            out[:n] = both[:n]
            out[n:] = (both[n:].reshape(n, n) @ z[n:].reshape(n, n)).ravel()
            return
        f = np.empty(n)
        rhs(t, y, f, p)
        out[:n] = f
        for j in range(n):
            h = steps[j]
            y_step[:] = y
            y_step[j] = y[j] + h
            rhs(t, y_step, f_plus, p)
            y_step[j] = y[j] - h
            rhs(t, y_step, f_minus, p)
            J[:, j] = (f_plus - f_minus) / (2.0 * h)
        out[n:] = (J @ z[n:].reshape(n, n)).ravel()

    return aug


def flow_with_jacobian(rhs, p, t0, y0, t_end, scale, *, rel_step=1e-6, method="DOP853", rtol=1e-10, atol=1e-13,
                       jacobian=False):
    """``(y(t_end), Phi(t_end), segment)``: the flow from ``(t0, y0)`` and its Jacobian.

    Integrated by SciPy's ``method`` behind lubelink's driver (a Python loop; the right-hand
    side may be compiled).

    Parameters
    ----------
    rhs : callable
        ``rhs(t, y, out, p)``.
    p : object
        Its parameters.
    t0, t_end : float
        The interval.
    y0 : ndarray, shape ``(n,)``
        Initial state.
    scale : ndarray, shape ``(n,)``
        Size of each component of ``y``: the difference step of ``df/dy`` is ``rel_step * scale``
        and the absolute tolerance of ``Phi[i, j]`` is ``atol / scale[j]`` (``atol`` on ``y``
        for a perturbation of size ``scale[j]``).
    rtol, atol : float
        Tolerances.
    jacobian : bool
        Whether ``rhs`` gives its Jacobian (:func:`augmented_rhs`).

    Raises
    ------
    RuntimeError
        If the integration does not reach ``t_end``.
    """
    from ..integrate import Options, Problem, integrate
    from ..integrate.scipy_methods import scipy_method

    y0 = np.asarray(y0, dtype=float)
    scale = np.asarray(scale, dtype=float)
    n = y0.size
    z0 = np.concatenate([y0, np.eye(n).ravel()])
    atol_all = np.concatenate([np.full(n, atol), np.broadcast_to(atol / scale[None, :], (n, n)).ravel()])
    seg = integrate(scipy_method(method), Problem(augmented_rhs(rhs, n, rel_step * scale, jacobian), None, p), t0, z0,
                    t_end, [t_end], Options(rtol=rtol, atol=atol_all, compiled=False))
    if seg.status != "finished":
        raise RuntimeError(f"the variational equations: {seg.message}")
    z = seg.y_final
    return z[:n].copy(), z[n:].reshape(n, n).copy(), seg
