"""One source for the physics: each function is compiled by Numba or run as plain Python.

Two decorators mark the code that the compiled path executes:

``@jitable``
    A function written in the subset of Python that Numba compiles (scalars, loops, NumPy
    arrays). Called from Python it *is* the plain Python function (so the public vectorised API
    and the ``numpy`` backend run exactly this source); called from compiled code it is compiled
    into the caller (:func:`numba.extending.register_jitable`).
``@kernel``
    An entry point from Python into compiled code (``numba.njit(cache=True)``): the right-hand
    side, the gap, the integrators' steps, the batched results. ``f.py_func`` is the plain Python
    function, which calls the plain ``@jitable`` functions: the ``numpy`` backend.

Numba's on-disk cache keys a compiled function on the source of its own file only, so an edit of
a ``@jitable`` function in another module would leave stale machine code behind. lubelink's
functions are therefore cached under a stamp of every source file of the package that holds
compiled code (:func:`package_stamp`), through a cache locator that serves lubelink's functions
only.

The integration methods (:data:`UNCOUNTED`) are compiled without reference counts: they only
read and write the arrays the driver allocated, so the counts Numba keeps for every array argument
and view guard nothing there, and their calls keep LLVM from holding an array's data pointer and
shape in registers across them.

Setting ``LUBELINK_DISABLE_JIT=1`` (or running without Numba) makes both decorators plain Python.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import warnings
from functools import lru_cache
from pathlib import Path

import numpy as np

__all__ = ["jitable", "kernel", "stack_empty", "ENABLED", "UNCOUNTED", "package_stamp", "NumbaUnavailable",
           "compile_errors"]

_PACKAGE = Path(__file__).resolve().parent
_MARKERS = (b"@jitable", b"@kernel")

try:
    if os.environ.get("LUBELINK_DISABLE_JIT", "") not in ("", "0"):
        raise ImportError("LUBELINK_DISABLE_JIT is set")
    import numba
    from numba.core.errors import NumbaExperimentalFeatureWarning, NumbaIRAssumptionWarning
    from numba.extending import register_jitable
except ImportError as exc:  # pragma: no cover - exercised by the no-Numba CI-less fallback
    numba = None
    _WHY = str(exc)
else:
    _WHY = ""
    # Numba's pedantic SSA check flags variables of inlined functions ("not in scope"): harmless
    warnings.filterwarnings("ignore", category=NumbaIRAssumptionWarning)
    # the integrators take the right-hand side as a first-class function on purpose (integrate/driver.py)
    warnings.filterwarnings("ignore", category=NumbaExperimentalFeatureWarning)

#: Whether kernels are compiled (Numba importable and not disabled).
ENABLED = numba is not None

#: Packages whose compiled functions keep no reference counts (Numba's ``_nrt=False``): the
#: integration methods. Numba then refuses to compile an allocation in them, or the return of an
#: array that is not an argument; ``tests/test_jit.py`` checks that none returns an argument
#: either (a caller that counts would release it once too often). Against the same methods with
#: counts, paired warm runs: ``simulate`` 0.81-0.89x on the built-in scenarios (benchmarks/README.md).
UNCOUNTED = ("lubelink.integrate",)


def _options(func):
    """Numba's options for ``func``: no reference counts in :data:`UNCOUNTED` where Numba offers that."""
    from numba.core.cpu import CPUTargetOptions

    if getattr(func, "__module__", "").startswith(UNCOUNTED) and hasattr(CPUTargetOptions, "_nrt"):
        return {"_nrt": False}
    return {}


def cores() -> int:
    """The processors this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - macOS, Windows
        return os.cpu_count() or 1


class NumbaUnavailable(RuntimeError):
    """The compiled path was asked for where Numba is missing or disabled."""


def compile_errors() -> tuple:
    """The exception types of a failed compilation (empty without Numba): ``except compile_errors():``."""
    try:
        from numba.core.errors import NumbaError
    except ImportError:
        return ()
    return (NumbaError,)


@lru_cache(maxsize=1)
def package_stamp() -> bytes:
    """SHA-256 of every source file of the package that holds ``@jitable`` or ``@kernel`` code."""
    digest = hashlib.sha256()
    for path in sorted(_PACKAGE.rglob("*.py")):
        data = path.read_bytes()
        if any(m in data for m in _MARKERS):
            digest.update(str(path.relative_to(_PACKAGE)).encode())
            digest.update(data)
    return digest.digest()


class _PyKernel:
    """A kernel that is plain Python (Numba missing or disabled): ``f(...)`` and ``f.py_func(...)``."""

    def __init__(self, func):
        self.py_func = func
        self.__name__ = func.__name__
        self.__doc__ = func.__doc__
        self.__wrapped__ = func

    def __call__(self, *args):
        return self.py_func(*args)


def jitable(func=None, *, inline=False):
    """Mark ``func`` as compilable into kernels; from Python it stays the plain function.

    ``inline=True`` inlines it into its callers in Numba's IR, before typing: for the thin functions
    called in the hot loops with the whole parameter structure, where a call costs more than the
    arithmetic (it passes every member, and every array costs reference counts). Such a function
    must not rely on a ``None`` argument to prune its branches (the pruning is by the types of a
    compiled function's own arguments): it calls small non-inlined functions for that
    (``model.phase_side``, ``section.uniform``). Inlining costs compile time, paid on a first run:
    the whole film force inlined into the right-hand side made the cold ``lubelink run`` compile
    2.6x longer for 15-25 % of the ``paper`` run's speed, so only the dispatchers are inlined
    (``model.rhs_given``, ``model.event_with``, ``model.gap_given``, ``faces.thinnest_on``,
    ``film.modal_film_force``, the DOP853 stage), not the film's equations.
    """
    if func is None:
        return lambda f: jitable(f, inline=inline)
    if ENABLED:
        register_jitable(inline="always" if inline else "never", **_options(func))(func)
    return func


def kernel(func):
    """A compiled entry point, cached on disk under :func:`package_stamp`; ``.py_func`` is the source.

    Kernels release the GIL (they touch no Python object), so two of them can run at once in
    threads: the results compute the pad pressure beside the other series (:mod:`lubelink.results`).

    They divide as NumPy does (``error_model="numpy"``: ``x / 0`` is ``inf`` or NaN, which the
    integrators already treat as a failed step, and ``LUBELINK_DISABLE_JIT`` runs stay plain Python).
    Numba's default raises ``ZeroDivisionError`` instead, and every such raising exit keeps its
    reference-count pruning from removing the atomic increments and decrements of the array
    arguments at a function's entry and exits: ``simulate`` 0.95-1.01x, the right-hand side
    0.91-1.01x on the built-in scenarios in paired runs (benchmarks/README.md).
    """
    if not ENABLED:
        return _PyKernel(func)
    _install_locators()
    return numba.njit(cache=True, nogil=True, error_model="numpy", **_options(func))(func)


def stack_empty(size):
    """``np.empty(size)`` of floats; in compiled code an array on the calling function's stack.

    For the scratch of a function called in the hot loop (the film force, at every evaluation of the
    right-hand side): a heap allocation and its release there cost about 70 ns an evaluation
    (``paper``'s integration 0.93-0.96x without them in paired runs, benchmarks/README.md). In compiled code
    ``size`` must be a constant (a module's integer) and the array must not outlive the call that
    made it: neither returned nor stored. From Python it is ``np.empty(size)``.
    """
    return np.empty(size)


def _compile_stack_empty():
    """:func:`stack_empty` for compiled code: an ``alloca`` in the entry block, a C-contiguous array without
    a memory owner (Numba's reference counts skip it), written with Numba's ``intrinsic`` and ``overload``."""
    from numba.core import cgutils, types
    from numba.core.errors import TypingError
    from numba.extending import intrinsic, overload
    from numba.np.arrayobj import populate_array

    array_type = types.Array(types.float64, 1, "C")

    @intrinsic
    def on_stack(typingctx, size):
        if not isinstance(size, types.IntegerLiteral) or size.literal_value < 1:
            raise TypingError(f"stack_empty: the size must be a positive integer constant, not {size}")
        n = size.literal_value

        def codegen(context, builder, signature, args):
            data = cgutils.alloca_once(builder, context.get_value_type(types.float64), size=n)
            array = context.make_array(array_type)(context, builder)
            intp = context.get_value_type(types.intp)
            populate_array(array, data=data, shape=cgutils.pack_array(builder, [intp(n)]),
                           strides=cgutils.pack_array(builder, [intp(8)]), itemsize=intp(8), meminfo=None)
            return array._getvalue()

        return array_type(size), codegen

    @overload(stack_empty, prefer_literal=True)
    def _stack_empty(size):
        if isinstance(size, types.IntegerLiteral):
            return lambda size: on_stack(size)
        raise TypingError(f"stack_empty: the size must be an integer constant in compiled code, not {size}")


if ENABLED:
    _compile_stack_empty()


@lru_cache(maxsize=1)
def _install_locators():
    """Put lubelink's cache locators first in Numba's list (they decline every other function)."""
    try:
        from numba.core import caching
    except ImportError:  # pragma: no cover
        return

    class _Stamped:
        @classmethod
        def from_function(cls, py_func, py_file):
            if not getattr(py_func, "__module__", "").startswith("lubelink"):
                return None
            return super().from_function(py_func, py_file)

        def get_source_stamp(self):
            return package_stamp()

    bases = [getattr(caching, name, None) for name in
             ("UserProvidedCacheLocator", "InTreeCacheLocator", "UserWideCacheLocator")]
    locators = [type(f"_Lubelink{b.__name__}", (_Stamped, b), {}) for b in bases if b is not None]
    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    if impl is not None and len(locators) == 3:
        impl._locator_classes = locators + [c for c in impl._locator_classes if c not in locators]
    _tolerate_foreign_indexes(caching)


def _tolerate_foreign_indexes(caching):
    """Read an on-disk cache index of lubelink's that this version cannot unpickle as stale.

    An index written by another version of lubelink (with the same Numba) can name classes that
    moved or went (the parameter views lived in ``lubelink.params`` in version 0.1); Numba
    unpickles it before it compares the stamp, and would raise. For lubelink's own index files
    (their path names the package) the error means "not this version's": nothing is cached.
    """
    cls = getattr(caching, "IndexDataCacheFile", None)
    original = getattr(cls, "_load_index", None)
    if original is None or getattr(original, "lubelink", False):
        return

    def _load_index(self):
        try:
            return original(self)
        except (AttributeError, ImportError, pickle.UnpicklingError, EOFError, TypeError):
            if "lubelink" not in str(getattr(self, "_index_path", "")):
                raise
            return {}

    _load_index.lubelink = True
    cls._load_index = _load_index
