"""The compiled code's rules (:mod:`lubelink._jit`): the integration methods keep no reference counts,
scratch on the stack.

* Numba really compiles the functions of :data:`~lubelink._jit.UNCOUNTED` without them: it refuses
  an allocation there, and compiles the same function elsewhere;
* none of those functions returns one of its arguments (the one array Numba lets a function without
  counts return, which a caller that counts would then release once too often);
* :func:`~lubelink._jit.stack_empty` gives compiled code a working array of a constant size, used by
  many calls in a row and by a callee, and refuses a size that is not a constant.
"""

import ast
import types
from pathlib import Path

import numpy as np
import pytest

import lubelink
from lubelink import _jit

SRC = Path(lubelink.__file__).resolve().parent
numba = pytest.importorskip("numba")
pytestmark = pytest.mark.skipif(not _jit.ENABLED, reason="the compiled path is disabled")


def _allocating(module):
    def total(n):
        return np.empty(n).sum() + n

    f = types.FunctionType(total.__code__, {"np": np}, "total")
    f.__module__ = module
    return _jit.jitable(f)


def test_uncounted_packages_cannot_allocate_and_others_can():
    counted, uncounted = _allocating("lubelink.film._probe"), _allocating("lubelink.integrate._probe")

    @numba.njit
    def call_counted(n):
        return counted(n)

    @numba.njit
    def call_uncounted(n):
        return uncounted(n)

    assert call_counted(3) >= 3.0
    with pytest.raises(numba.core.errors.TypingError, match="returning of array|NRT"):
        call_uncounted(3)


def _compiled_functions(tree):
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            names = {d.id if isinstance(d, ast.Name) else getattr(getattr(d, "func", None), "id", None)
                     for d in node.decorator_list}
            if names & {"jitable", "kernel"}:
                yield node


def _returned_arguments(func):
    """Names of ``func``'s array (or tuple) arguments that one of its ``return`` statements hands back,
    alone or in a tuple; an argument is taken for an array or a tuple where the function indexes it."""
    args = {a.arg for a in func.args.args}
    args &= {n.value.id for n in ast.walk(func) if isinstance(n, ast.Subscript) and isinstance(n.value, ast.Name)}
    found = []
    for node in ast.walk(func):
        if isinstance(node, ast.Return) and node.value is not None:
            values = node.value.elts if isinstance(node.value, ast.Tuple) else [node.value]
            found += [v.id for v in values if isinstance(v, ast.Name) and v.id in args]
    return found


def test_uncounted_functions_never_return_an_argument():
    files = sorted((SRC / "integrate").rglob("*.py"))
    checked = 0
    for path in files:
        for func in _compiled_functions(ast.parse(path.read_text())):
            checked += 1
            assert not _returned_arguments(func), f"{path.name}: {func.name} returns {_returned_arguments(func)}"
    assert checked > 30  # the methods' compiled functions were found


def test_the_check_finds_a_returned_argument():
    tree = ast.parse("@jitable\ndef f(W, h):\n    W[0, 0] = h\n    return W, 1.0\n\n"
                     "@jitable\ndef g(W, h):\n    return h\n")
    funcs = list(_compiled_functions(tree))
    assert [_returned_arguments(f) for f in funcs] == [["W"], []]


SCRATCH = 24


def _scratch_sums(x):
    """For each ``x[i]``, the sum of ``x[i] k`` for ``k < SCRATCH``, through a stack scratch filled by a callee."""
    out = np.empty(x.shape[0])
    ws = _jit.stack_empty(SCRATCH)
    for i in range(x.shape[0]):
        _fill(ws, x[i])
        s = 0.0
        for k in range(SCRATCH):
            s += ws[k]
        out[i] = s
    return out


def _fill(ws, a):
    for k in range(ws.shape[0]):
        ws[k] = a * k


def test_stack_scratch_is_an_array_of_its_size_in_both_backends():
    fill = numba.njit(_fill)
    compiled = numba.njit(types.FunctionType(_scratch_sums.__code__, {**_scratch_sums.__globals__, "_fill": fill}))
    x = np.linspace(-3.0, 5.0, 1001)
    expected = x * SCRATCH * (SCRATCH - 1) / 2
    np.testing.assert_allclose(compiled(x), expected, rtol=1e-15)
    np.testing.assert_allclose(_scratch_sums(x), expected, rtol=1e-15)
    assert _jit.stack_empty(5).shape == (5,) and _jit.stack_empty(5).dtype == np.float64


def test_stack_scratch_needs_a_constant_size():
    @numba.njit
    def sized(n):
        return _jit.stack_empty(n).shape[0]

    with pytest.raises(numba.core.errors.TypingError, match="stack_empty"):
        sized(7)
