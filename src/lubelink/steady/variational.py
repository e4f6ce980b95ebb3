"""The flow and its Jacobian: the variational equations integrated with the state, compiled.

For ``dy/dt = f(t, y)`` the Jacobian of the flow, ``Phi(t) = dy(t)/dy(t0)``, solves
``dPhi/dt = J(t, y(t)) Phi`` with ``Phi(t0) = I``, ``J = df/dy``; over one period ``Phi(T)`` is
the monodromy matrix. :func:`flow_with_jacobian` integrates the ``n + n^2`` equations together
(:func:`flow_rhs`) with lubelink's DOP853 through the generic driver, compiled like any run: the
model's right-hand side reaches the kernel as a first-class function inside its parameters, so
one compiled kernel serves every model. ``J`` comes from the right-hand side itself where it gives
it (an ``out`` of ``n + n^2`` entries, as the stiff method asks: :func:`lubelink.link.model.rhs`),
else from central differences of the right-hand side (exact, up to rounding, for a right-hand
side linear in ``y``).

Only ``rhs(t, y, out, p)`` is known here, as in :mod:`lubelink.integrate`: no physics.
"""

from __future__ import annotations

import numpy as np

from .._jit import ENABLED, kernel

__all__ = ["flow_rhs", "flow_with_jacobian", "flow_parameters"]


@kernel
def flow_rhs(t, z, out, pa):
    """``dz/dt`` of ``z = [y, Phi]`` (``Phi`` row-major after ``y``): ``[f(t, y), J(t, y) Phi]``.

    ``pa = (rhs, p, steps, given)``: the right-hand side ``rhs(t, y, out, p)`` of size ``n`` and
    its parameters; ``given``: ``rhs`` writes ``J`` too when handed an ``out`` of ``n + n^2``
    entries (one evaluation), else ``J`` by central differences with the steps ``steps[j]`` of
    each component (``2 n + 1`` evaluations).
    """
    rhs, p, steps, given = pa
    m = z.shape[0]
    n = 0
    while n + n * n < m:
        n += 1
    y = np.ascontiguousarray(z[:n])
    J = np.empty((n, n))
    if given:
        rhs(t, y, out, p)  # f in out[:n], J row by row after it
        for i in range(n):
            for j in range(n):
                J[i, j] = out[n + i * n + j]
    else:
        f_plus = np.empty(n)
        f_minus = np.empty(n)
        y_step = y.copy()
        rhs(t, y, f_plus, p)
        out[:n] = f_plus
        for j in range(n):
            h = steps[j]
            y_step[j] = y[j] + h
            rhs(t, y_step, f_plus, p)
            y_step[j] = y[j] - h
            rhs(t, y_step, f_minus, p)
            y_step[j] = y[j]
            for i in range(n):
                J[i, j] = (f_plus[i] - f_minus[i]) / (2.0 * h)
    for i in range(n):
        for j in range(n):
            s = 0.0
            for k in range(n):
                s += J[i, k] * z[n + k * n + j]
            out[n + i * n + j] = s


def flow_parameters(rhs, p, p_type, steps, jacobian, compiled=ENABLED):
    """``(pa, pa_type)``: the parameters of :func:`flow_rhs` for ``rhs`` (a kernel when ``compiled``) and
    its parameters ``p`` of Numba type ``p_type`` (None: not compiled)."""
    steps = np.ascontiguousarray(steps, dtype=float)
    if not compiled:
        return (getattr(rhs, "py_func", rhs), p, steps, bool(jacobian)), None
    from numba import types

    from ..integrate.driver import first_class, signatures

    f = first_class(rhs, signatures(p_type)[0])
    return (f, p, steps, bool(jacobian)), types.Tuple((f.numba_type, p_type, types.float64[::1], types.boolean))


def flow_with_jacobian(rhs, p, t0, y0, t_end, scale, *, rel_step=1e-6, rtol=1e-10, atol=1e-13, jacobian=False,
                       p_type=None, compiled=ENABLED):
    """``(y(t_end), Phi(t_end), segment)``: the flow from ``(t0, y0)`` and its Jacobian.

    Integrated by lubelink's DOP853 (:mod:`lubelink.integrate.dop853`), compiled when ``compiled``
    (``rhs`` a kernel, ``p_type`` the Numba type of ``p``, computed if None), else as Python.

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
        Whether ``rhs`` gives its Jacobian (:func:`flow_rhs`).

    Raises
    ------
    RuntimeError
        If the integration does not reach ``t_end``.
    """
    from ..integrate import Options, Problem, integrate, method

    y0 = np.asarray(y0, dtype=float)
    scale = np.asarray(scale, dtype=float)
    n = y0.size
    if compiled and p_type is None:
        import numba

        p_type = numba.typeof(p)
    pa, pa_type = flow_parameters(rhs, p, p_type, rel_step * scale, jacobian, compiled)
    z0 = np.concatenate([y0, np.eye(n).ravel()])
    atol_all = np.concatenate([np.full(n, atol), np.broadcast_to(atol / scale[None, :], (n, n)).ravel()])
    seg = integrate(method("DOP853"), Problem(flow_rhs if compiled else flow_rhs.py_func, None, pa, p_type=pa_type),
                    t0, z0, t_end, [t_end], Options(rtol=rtol, atol=atol_all, compiled=compiled))
    if seg.status != "finished":
        raise RuntimeError(f"the variational equations: {seg.message}")
    z = seg.y_final
    return z[:n].copy(), z[n:].reshape(n, n).copy(), seg
