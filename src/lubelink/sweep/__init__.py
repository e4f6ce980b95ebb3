"""Parameter studies: sweeps that resume and never lose a point.

A sweep file (TOML) names a base configuration and the parameters to vary
(lists, linear or log ranges, explicit points); every point of the full
factorial grid is one simulation, run in the calling process, on a pool of
worker processes or in Dask tasks (one point each, or a few when points are
short), whichever finishes first (:func:`~.execute.choose_executor`). The summary quantities of each point are written to
one labelled store over the swept dimensions as soon as its task finishes, so
a crash loses nothing already stored and running the same sweep again resumes
it. docs/sweeps.md is the reference.

==========================  =================================================
module                      job
==========================  =================================================
``schema``                  store format version, quantities, time series,
                            parameter units, :class:`SweepError`
``spec``                    :class:`Sweep` and :class:`Axis`: grid, points,
                            hash, validation of every point
``parse``                   sweep file -> :class:`Sweep` (:func:`read_sweep`)
``compute``                 one point on a worker: simulate, summarise
                            (:func:`summarise`, or :func:`reduce_run` from the
                            run's arrays), sample time series
``layout``                  the variables of a new store, written with Zarr
                            (:func:`~.layout.write_empty`) or as a Dataset
``store``                   Zarr writer and journal, NetCDF export,
                            :func:`load_sweep`, :func:`point_config`
``local``                   this process or a process pool; the free cores,
                            the commit of finished points (``Tally``), task sizes
``_warm``                   the pool server's warm-up on the first point
``on_dask``                 the Dask client or LocalCluster, the task window
``execute``                 :func:`run_sweep`: the store, where the points run
``plot``                    :func:`plot_sweep`: response map
``cli``                     ``sweep`` and ``plot-sweep`` subcommands
                            (:func:`register_cli`)
==========================  =================================================

==========================  =================================================
piece                       job
==========================  =================================================
:func:`read_sweep`          sweep file -> :class:`Sweep` (validated, hashed)
:meth:`Sweep.point_configs` every point -> validated ``Config`` (or problems)
:func:`summarise`           one results Dataset -> summary quantities
:func:`run_sweep`           run the missing points, store, return all
:func:`load_sweep`          the stored results as an ``xarray.Dataset``
:func:`point_config`        the ``Config`` of one stored point (to run it again)
:func:`plot_sweep`          response map (heat map, curves, facets)
==========================  =================================================

Store layout (Zarr directory, the default): one array per quantity over the
swept dimensions, a boolean ``done`` mask, the swept parameters as
coordinates, and the sweep definition and its hash in the attributes. The
client appends every finished point to ``journal.jsonl`` inside the store
(one line, a few microseconds) and folds the journal into the arrays every few
seconds and at the end; a point is stored once its journal line is written.
A NetCDF result (``.nc``) is exported atomically at the end of each run from a
Zarr side store ``<name>.nc.partial.zarr``, which is removed once every point
is stored.

Heavy libraries (Dask, Zarr, xarray, Matplotlib) are imported inside the
functions that need them.
"""

from __future__ import annotations

# The constants of the former single module ``lubelink.sweep`` stay importable from here, and so
# do the private pieces that tests/test_sweep.py and benchmarks/sweep_throughput.py use.
from .cli import register_cli
from .compute import _compute_point, _empty_record, _TaskOptions, summarise  # noqa: F401
from .execute import LOCAL_CLUSTER_CONFIG, run_sweep, sweep
from .parse import MAX_POINTS, read_sweep  # noqa: F401
from .plot import plot_sweep
from .schema import ALWAYS, DEFAULT_QUANTITIES, QUANTITIES, SERIES, SWEEP_FORMAT, SweepError  # noqa: F401
from .spec import Axis, Sweep
from .store import COMPACT_INTERVAL, JOURNAL, LOCK, _Store, load_sweep, point_config  # noqa: F401

__all__ = [
    "Axis",
    "Sweep",
    "SweepError",
    "QUANTITIES",
    "SERIES",
    "LOCAL_CLUSTER_CONFIG",
    "read_sweep",
    "summarise",
    "run_sweep",
    "sweep",
    "load_sweep",
    "point_config",
    "plot_sweep",
    "register_cli",
]
