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
    """``dz/dt`` of ``z = [y, Phi]`` (``Phi`` row-major after ``y``): ``[f(t, y), J(t, y) Phi (+ df/dp)]``.

    ``pa = (rhs, p, steps, given, p_plus, p_minus, dp)``: the right-hand side ``rhs(t, y, out, p)`` of
    size ``n`` and its parameters; ``given``: ``rhs`` writes ``J`` too when handed an ``out`` of
    ``n + n^2`` entries (one evaluation), else ``J`` by central differences with the steps
    ``steps[j]`` of each component (``2 n + 1`` evaluations). With ``dp > 0`` the flow also carries
    a scalar parameter ``P`` of the right-hand side, constant along it (``dP/dt = 0``): ``Phi`` is then
    ``n x (n + 1)``, the Jacobian of ``y(t)`` with respect to ``[y(t0), P]``, its last column
    driven by ``df/dP = (rhs(p_plus) - rhs(p_minus)) / dp``, the right-hand side with the
    parameters at ``P`` plus and minus half of ``dp`` (the row ``[0, ..., 0, 1]`` of ``P`` itself is
    not integrated).
    """
    rhs, p, steps, given, p_plus, p_minus, dp = pa
    r = 1 if dp > 0.0 else 0
    m = z.shape[0]
    n = 0
    while n + n * (n + r) < m:
        n += 1
    c = n + r  # columns of Phi
    y = np.ascontiguousarray(z[:n])
    J = np.empty((n, n))
    f_plus = np.empty(n)
    f_minus = np.empty(n)
    if given:
        rhs(t, y, out[:n + n * n], p)  # f in out[:n], J row by row after it
        for i in range(n):
            for j in range(n):
                J[i, j] = out[n + i * n + j]
    else:
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
    if r:
        rhs(t, y, f_plus, p_plus)
        rhs(t, y, f_minus, p_minus)
    for i in range(n):
        for j in range(c):
            s = 0.0
            for k in range(n):
                s += J[i, k] * z[n + k * c + j]
            if j == n:
                s += (f_plus[i] - f_minus[i]) / dp
            out[n + i * c + j] = s


def flow_parameters(rhs, p, p_type, steps, jacobian, compiled=ENABLED, parameter=None):
    """``(pa, pa_type)``: the parameters of :func:`flow_rhs` for ``rhs`` (a kernel when ``compiled``) and
    its parameters ``p`` of Numba type ``p_type`` (None: not compiled); ``parameter``: ``(p_plus, p_minus,
    dp)`` of a parameter carried by the flow (of ``p``'s type), or None."""
    steps = np.ascontiguousarray(steps, dtype=float)
    p_plus, p_minus, dp = (p, p, 0.0) if parameter is None else parameter
    if not compiled:
        return (getattr(rhs, "py_func", rhs), p, steps, bool(jacobian), p_plus, p_minus, float(dp)), None
    from numba import types

    from ..integrate.driver import first_class, signatures

    f = first_class(rhs, signatures(p_type)[0])
    return ((f, p, steps, bool(jacobian), p_plus, p_minus, float(dp)),
            types.Tuple((f.numba_type, p_type, types.float64[::1], types.boolean, p_type, p_type, types.float64)))


def flow_with_jacobian(rhs, p, t0, y0, t_end, scale, *, rel_step=1e-6, rtol=1e-10, atol=1e-13, jacobian=False,
                       p_type=None, compiled=ENABLED, parameter=None):
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
    parameter : tuple, optional
        ``(p_plus, p_minus, dp, size)``: a scalar parameter ``P`` of ``rhs`` carried by the flow,
        ``p_plus`` and ``p_minus`` the parameters at ``P +- dp / 2`` (``df/dP`` is their central
        difference), ``size`` its typical size (the absolute tolerance of its column). ``Phi`` is
        then ``n x (n + 1)``: its last column ``dy(t_end)/dP``.

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
    columns = scale
    if parameter is not None:
        columns = np.append(scale, float(parameter[3]))
        parameter = parameter[:3]
    c = columns.size
    pa, pa_type = flow_parameters(rhs, p, p_type, rel_step * scale, jacobian, compiled, parameter)
    z0 = np.concatenate([y0, np.eye(n, c).ravel()])
    atol_all = np.concatenate([np.full(n, atol), np.broadcast_to(atol / columns[None, :], (n, c)).ravel()])
    seg = integrate(method("DOP853"), Problem(flow_rhs if compiled else flow_rhs.py_func, None, pa, p_type=pa_type),
                    t0, z0, t_end, [t_end], Options(rtol=rtol, atol=atol_all, compiled=compiled))
    if seg.status != "finished":
        raise RuntimeError(f"the variational equations: {seg.message}")
    z = seg.y_final
    return z[:n].copy(), z[n:].reshape(n, c).copy(), seg
