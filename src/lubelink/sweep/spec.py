"""The sweep definition: :class:`Sweep` (the grid, what is stored, its hash) and :class:`Axis`.

A :class:`Sweep` is made by :func:`lubelink.sweep.read_sweep` (:mod:`.parse`), which validates
the sweep file; here are its shape, the overrides and label of each point, its identity (the
definition as TOML, the SHA-256 hash a store is checked against) and the validation of every
point's configuration.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from ..config import ConfigError
from .schema import SWEEP_FORMAT, _fmt

__all__ = ["Axis", "Sweep", "SweepEstimate"]

#: Seconds per point besides the simulation: the Dask task, the summary, the store.
POINT_OVERHEAD = 0.02
#: Seconds per value of a point's results Dataset (deflection and pressure samples).
ASSEMBLY_PER_VALUE = 2e-8
#: Bytes of a status or message string held as a Python object.
STRING_BYTES = 80
#: Bytes of the client process besides the results (Python, NumPy, xarray, Dask).
MEMORY_BASE = 300e6


def config_with(base, overrides):
    """``base`` (a :class:`~lubelink.params.Config`) with ``{"section.key": value}`` ``overrides``, not
    validated: a point of a sweep, built where it is computed from its overrides and the base."""
    by_section = {}
    for name, value in overrides.items():
        section, key = name.split(".", 1)
        by_section.setdefault(section, {})[key] = value
    return replace(base, **{s: replace(getattr(base, s), **kv) for s, kv in by_section.items()})


@dataclass(frozen=True)
class SweepEstimate:
    """Up-front estimate of a sweep: points, client memory [B], store size [B], time [s]."""

    points: int
    memory_bytes: float
    store_bytes: float
    cpu_seconds: float
    wall_seconds: float
    workers: int | None

    def __str__(self):
        from ..estimate import duration

        time = (f"about {duration(self.wall_seconds)} on {self.workers} worker(s) ({duration(self.cpu_seconds)} "
                "of CPU)" if self.workers else f"about {duration(self.cpu_seconds)} of CPU (over the workers)")
        return (f"{time}, client memory about {_bytes(self.memory_bytes)}, "
                f"store about {_bytes(self.store_bytes)} before compression")


def _bytes(n):
    for unit, size in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n:.0f} B"


@dataclass(frozen=True)
class Axis:
    """One swept parameter: a dimension of the results.

    Attributes
    ----------
    name : str
        ``"section.key"``; also the name of the dimension and its coordinate.
    values : tuple
        The values in order, in the parameter's type.
    scale : str
        ``"list"``, ``"linear"`` or ``"log"`` (how the values were given).
    """

    name: str
    values: tuple
    scale: str = "list"


@dataclass(frozen=True)
class Sweep:
    """A parsed, validated sweep definition (see :func:`read_sweep`).

    The results have one dimension per :class:`Axis` (in file order) and, when
    explicit points are given, a last dimension ``point``. ``hash`` identifies
    everything that decides the stored values and their layout.
    """

    base: str
    base_config: object
    fixed: dict
    axes: tuple
    point_names: tuple
    point_rows: tuple
    quantities: tuple
    time_series: tuple
    max_impacts: int
    invalid_points: str
    origin: str

    # ------------------------------------------------------------ shape
    @property
    def dims(self) -> tuple:
        return tuple(a.name for a in self.axes) + (("point",) if self.point_rows else ())

    @property
    def shape(self) -> tuple:
        return tuple(len(a.values) for a in self.axes) + ((len(self.point_rows),) if self.point_rows else ())

    @property
    def size(self) -> int:
        return math.prod(self.shape)  # exact, however large (np.prod would overflow int64)

    def overrides(self, flat: int) -> dict:
        """``{"section.key": value}`` of point ``flat`` (C order over :attr:`shape`)."""
        index = np.unravel_index(flat, self.shape)
        out = {a.name: a.values[i] for a, i in zip(self.axes, index)}
        if self.point_rows:
            out.update(zip(self.point_names, self.point_rows[index[-1]]))
        return out

    def label(self, flat: int) -> str:
        return ", ".join(f"{k}={_fmt(v)}" for k, v in self.overrides(flat).items())

    # ------------------------------------------------------------ identity
    def definition(self) -> dict:
        """The sweep as a TOML-ready dict, with the base configuration resolved in full."""
        from ..config import to_dict

        store = {"quantities": list(self.quantities), "time_series": list(self.time_series)}
        if "impact_times" in self.quantities:
            store["max_impacts"] = self.max_impacts
        data = {"base": self.base, "vary": {a.name: list(a.values) for a in self.axes}, "store": store}
        if self.fixed:
            data["set"] = {k: list(v) if isinstance(v, tuple) else v for k, v in self.fixed.items()}
        if self.point_rows:
            data["points"] = [dict(zip(self.point_names, row)) for row in self.point_rows]
        data["base_config"] = to_dict(self.base_config)
        return data

    @cached_property
    def hash(self) -> str:
        """SHA-256 of the resolved base configuration, the grid and the stored quantities."""
        data = self.definition()
        data.pop("base")  # the resolved configuration counts, not how it was named
        data.pop("set", None)  # already folded into base_config
        data["format"] = SWEEP_FORMAT.split(".")[0]
        text = json.dumps(data, sort_keys=True, default=list)
        return hashlib.sha256(text.encode()).hexdigest()

    def to_toml(self) -> str:
        import tomli_w

        data = self.definition()
        data.pop("base_config")
        return tomli_w.dumps(data)

    # ------------------------------------------------------------ points
    def point_config(self, flat: int):
        """The :class:`~lubelink.params.Config` of point ``flat`` (not validated: see
        :meth:`invalid_points_of`), built when needed, so that a large sweep holds no configurations."""
        return config_with(self.base_config, self.overrides(flat))

    def invalid_points_of(self, progress=None, flats=None) -> dict:
        """Validate the points (all, or ``flats``) one by one: ``{flat: problems}`` of the invalid ones.

        Nothing else is kept, so memory stays bounded by the invalid points; ``progress`` is called
        with the count of points checked (about every thousand points and at the end).
        """
        from ..config import validate

        invalid = {}
        flats = range(self.size) if flats is None else flats
        n = 0
        for n, flat in enumerate(flats, 1):
            try:
                validate(self.point_config(flat))
            except ConfigError as exc:
                invalid[int(flat)] = exc.problems
            if progress is not None and n % 1024 == 0:
                progress(n)
        if progress is not None:
            progress(n)
        return invalid

    def point_configs(self, progress=None):
        """Validate every point: ``(configs, invalid)`` keyed by flat index (small sweeps: every
        configuration is kept; :func:`run_sweep` uses :meth:`invalid_points_of` instead).

        ``configs[flat]`` is the validated :class:`~lubelink.params.Config`;
        ``invalid[flat]`` the list of problems of a point that fails
        :func:`lubelink.config.validate`. ``progress`` is called with the count
        of points checked.
        """
        from ..config import validate

        configs, invalid = {}, {}
        for flat in range(self.size):
            try:
                configs[flat] = validate(self.point_config(flat))
            except ConfigError as exc:
                invalid[flat] = exc.problems
            if progress is not None:
                progress(flat + 1)
        return configs, invalid

    # ------------------------------------------------------------ cost
    def estimate(self, workers=None, sample=64):
        """:class:`SweepEstimate`: memory, store size and time of the whole sweep, up front.

        Time: the up-front cost of a run (:func:`lubelink.estimate.run_cost`) plus the results
        assembly and the per-point overhead, averaged over up to ``sample`` valid points spread
        over the grid, times the number of points, over ``workers`` processes (None: unknown, a
        remote cluster; the time is then CPU time). Memory: the
        results as the client holds them when the sweep ends (:func:`load_sweep`), with the
        strings as Python objects; the store: the same values on disk before compression.
        """
        from ..config import validate
        from ..estimate import run_cost
        from ..params import sample_times
        from .schema import QUANTITIES, SERIES

        size = self.size
        picks = sorted({int(i) for i in np.linspace(0, size - 1, min(size, sample))}) if 0 < size < 2**62 else []
        seconds = []
        for flat in picks:
            try:
                cfg = validate(self.point_config(flat))
            except ConfigError:
                continue
            n_out = cfg.solver.t_end / cfg.solver.output_step + 1
            assembly = n_out * (cfg.output.x_points * cfg.beam.modes
                                + cfg.output.pad_points * cfg.film.sides * cfg.film.enabled) * ASSEMBLY_PER_VALUE
            seconds.append(run_cost(cfg).seconds + assembly + POINT_OVERHEAD)
        if not seconds and self.base_config is not None:  # no valid point in the sample: the base
            seconds.append(run_cost(self.base_config).seconds + POINT_OVERHEAD)
        per_point = float(np.mean(seconds)) if seconds else POINT_OVERHEAD
        values = 0
        for name in self.quantities:
            values += self.max_impacts if QUANTITIES[name][2] == "impacts" else 1
        per_point_bytes = 1 + 8 + 8 * values + 2 * (8 + STRING_BYTES)  # done, wall_time, quantities, status/message
        store_per_point = 1 + 8 + 8 * values + 2 * 16
        if self.time_series:
            cfg = self.base_config
            n_time = len(sample_times(cfg.solver))
            extent = {"mode": cfg.beam.modes, "x": cfg.output.x_points, "x_pad": cfg.output.pad_points, None: 1}
            series = sum(8 * n_time * extent[SERIES[name][0]] for name in self.time_series)
            per_point_bytes += series
            store_per_point += series
        return SweepEstimate(points=size, memory_bytes=size * per_point_bytes + MEMORY_BASE,
                             store_bytes=size * store_per_point, cpu_seconds=size * per_point,
                             wall_seconds=size * per_point / (workers or 1), workers=workers or None)

    def invalid_report(self, invalid: dict) -> list:
        """One line per distinct problem, naming the first point it occurs at and how many more."""
        groups = {}
        for flat, problems in invalid.items():
            for p in problems:
                groups.setdefault(p, []).append(flat)
        lines = []
        for problem, flats in list(groups.items())[:20]:
            more = f" and {len(flats) - 1} more point(s)" if len(flats) > 1 else ""
            lines.append(f"{self.origin}: invalid point ({self.label(flats[0])}{more}): {problem}")
        if len(groups) > 20:
            lines.append(f"{self.origin}: ... and {len(groups) - 20} more distinct problems")
        lines.append(f"{self.origin}: {len(invalid)} of {self.size} points are invalid; fix the "
                     "ranges, or set invalid_points = \"record\" to store them as failed points")
        return lines
