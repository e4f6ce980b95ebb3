"""The sweep store: the Zarr writer, its journal, and reading the results back.

A Zarr directory holds one array per quantity (:mod:`.layout`); the client is its only writer
(:class:`_Store`, a lock file inside the store). A finished point is committed by one line
appended to ``journal.jsonl``, folded into the arrays every :data:`COMPACT_INTERVAL` seconds and
at the end. A NetCDF result (``.nc``) is exported atomically from a Zarr side store
``<name>.nc.partial.zarr``, removed once every point is stored. :func:`load_sweep` reads either,
a store being written included (arrays and journal); :func:`point_config` gives the
configuration of one stored point. Zarr and xarray are imported inside the functions.
"""

from __future__ import annotations

import errno
import json
import math
import os
import shutil
import time
import tomllib
from pathlib import Path

import numpy as np

from .._files import atomic_path, read_netcdf
from ..netcdf import renamed
from .layout import write_empty
from .schema import ALWAYS, QUANTITIES, SWEEP_FORMAT, SweepError
from .spec import Sweep

__all__ = ["load_sweep", "point_config", "outcome", "JOURNAL", "COMPACT_INTERVAL"]

JOURNAL = "journal.jsonl"
LOCK = "lock"
#: Seconds between folds of the journal into the Zarr arrays.
COMPACT_INTERVAL = 10.0


def _open_own(path, flags):
    """``os.open(path, flags)`` of a file of a store, never through a symbolic link (``O_NOFOLLOW``; a link
    makes a :class:`SweepError` naming it): a store's files are its own, and a link inside it must not
    make a sweep write, truncate or lock a file elsewhere."""
    if os.path.islink(path):
        raise SweepError(f"{path} is a symbolic link: a sweep store never writes through one; remove it")
    try:
        return os.open(path, flags | getattr(os, "O_NOFOLLOW", 0), 0o666)
    except OSError as exc:
        if exc.errno == errno.ELOOP:  # made a link between the check and the open
            raise SweepError(f"{path} is a symbolic link: a sweep store never writes through one; remove it") from None
        raise


def _read_journal(path):
    """Records of a journal file; a torn last line (a kill mid-write) is ignored."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        return []
    records = []
    for line in text.splitlines():
        try:
            rec = json.loads(line)
        except json.JSONDecodeError:
            continue
        if isinstance(rec, dict) and isinstance(rec.get("i"), int):
            records.append(rec)
    return records


def _scatter(records, shape, quantities, max_impacts):
    """``{variable: (index, values)}`` of journal records; ``done`` comes last.

    A point recorded twice (a retried failure) keeps its latest record.
    """
    latest = {}
    for rec in records:
        if 0 <= rec["i"] < int(np.prod(shape)):
            latest[rec["i"]] = rec
    if not latest:
        return {}
    recs = list(latest.values())
    idx = np.unravel_index(np.array([r["i"] for r in recs]), shape)
    out = {}
    for name in list(ALWAYS) + list(quantities):
        vals = [r.get(name) for r in recs]
        kind = "s" if name in ("status", "message") else QUANTITIES.get(name, ("", "", "f"))[2]
        if kind == "impacts":
            k = max_impacts
            ix = tuple(np.repeat(i, k) for i in idx) + (np.tile(np.arange(k), len(recs)),)
            out[name] = (ix, np.array(vals, dtype=float).reshape(-1))
        elif kind == "s":
            out[name] = (idx, np.array([str(v) for v in vals], dtype=object))
        elif kind == "i":
            out[name] = (idx, np.array(vals, dtype=np.int64))
        else:
            out[name] = (idx, np.array([math.nan if v is None else v for v in vals], dtype=float))
    out["done"] = (idx, np.ones(len(recs), dtype=bool))
    return out


def _store_attrs(path):
    """Group attributes of a Zarr store, or None when ``path`` is not a Zarr group."""
    import zarr

    try:
        return dict(zarr.open_group(str(path), mode="r").attrs)
    except Exception:  # noqa: BLE001 - anything unreadable is "not a sweep store"
        return None


def _check_attrs(path, attrs, sp, overwrite):
    """Refuse a store of another sweep (or not a sweep store); True when it must be replaced."""
    if attrs is None or "lubelink_sweep_format" not in attrs:
        raise SweepError(f"{path} exists and is not a lubelink sweep store; choose another output")
    version = str(attrs["lubelink_sweep_format"])
    if version.split(".")[0] != SWEEP_FORMAT.split(".")[0]:
        if overwrite:
            return True
        raise SweepError(f"{path}: sweep store format {version}, this lubelink writes {SWEEP_FORMAT}; "
                         "add --overwrite to start it again")
    if attrs.get("sweep_hash") != sp.hash:
        if overwrite:
            return True
        raise SweepError(
            f"{path} holds a different sweep (hash {str(attrs.get('sweep_hash'))[:12]}, this sweep file gives "
            f"{sp.hash[:12]}): the base configuration, the grid or the stored quantities differ; "
            "use another output, or add --overwrite to discard it")
    return False


class _Store:
    """Writer of a Zarr sweep store; one process at a time (a lock file inside the store).

    Points are committed by one line appended to the journal; :meth:`compact`
    folds the journal into the arrays (values first, ``done`` last, then the
    journal is emptied), so a kill at any instant leaves every committed point
    either in the arrays or in the journal, never half-written (Zarr replaces
    chunk files atomically).
    """

    def __init__(self, path: Path, sp: Sweep):
        self.path, self.sweep = Path(path), sp
        self.group = None
        self.created = False  # by this writer (removed again if nothing gets stored: run_sweep)
        self._arrays = {}
        self._lock_fd = self._journal_fd = None
        self._last_compact = time.monotonic()

    @classmethod
    def open(cls, path, sp: Sweep, overwrite=False) -> "_Store":
        """Open the store at ``path`` for writing, creating it if there is none.

        A new store is built under a temporary name with its lock already held, then renamed into
        place without replacing anything: of two sweeps that create the same store at once, one
        creates it and the other finds it locked ("being written by another sweep").
        """
        st = cls(path, sp)
        try:
            if not os.path.lexists(st.path):
                try:
                    st._create()
                except FileExistsError:
                    pass  # another sweep created it meanwhile: open it as an existing store
            if not st.created:
                attrs = _store_attrs(st.path)
                if attrs is None or "lubelink_sweep_format" not in attrs:  # never touch a foreign folder
                    raise SweepError(f"{st.path} exists and is not a lubelink sweep store; choose another output")
                st._lock(st.path)
                if _check_attrs(st.path, _store_attrs(st.path), sp, overwrite):
                    st._unlock()
                    shutil.rmtree(st.path)
                    try:
                        st._create()
                    except FileExistsError:
                        raise SweepError(f"{st.path} was created by another sweep while this one replaced "
                                         "it; run again") from None
            import zarr

            st.group = zarr.open_group(str(st.path), mode="r+")
            for tmp in st.path.rglob("*.partial"):  # temporaries of a chunk write cut by a kill
                tmp.unlink(missing_ok=True)
            st._journal_fd = _open_own(st.path / JOURNAL, os.O_WRONLY | os.O_APPEND | os.O_CREAT)
            st.compact()  # fold what a killed run left in the journal
        except OSError as exc:
            st.close_files()
            raise SweepError(f"{st.path}: cannot write the store ({exc.strerror or exc})") from None
        except BaseException:
            st.close_files()
            raise
        return st

    def _create(self):
        """Build the empty store under a temporary name, lock it, and rename it into place without
        replacing anything (:func:`lubelink._files.atomic_path`); :class:`FileExistsError` if a
        store appeared there meanwhile."""
        from .._files import folder_problem

        problem = folder_problem(self.path.parent)
        if problem:
            raise SweepError(f"{self.path}: {problem}")
        try:
            self._build_and_publish()
        except BaseException:
            self._unlock()
            raise
        self.created = True

    def _build_and_publish(self):
        with atomic_path(self.path, overwrite=False, directory=True) as tmp:
            write_empty(self.sweep, tmp)
            (tmp / JOURNAL).touch()
            self._lock(tmp)  # held from the store's first appearance under its name

    def _lock(self, folder):
        try:
            import fcntl
        except ImportError:  # Windows: no advisory locks; one writer is the user's responsibility
            return
        fd = _open_own(Path(folder) / LOCK, os.O_RDWR | os.O_CREAT)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            other = os.read(fd, 64).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise SweepError(f"{self.path} is being written by another sweep (process {other}); "
                             "wait for it to finish or stop it") from None
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        self._lock_fd = fd

    def _unlock(self):
        if self._lock_fd is not None:
            os.close(self._lock_fd)
            self._lock_fd = None

    def array(self, name):
        if name not in self._arrays:
            self._arrays[name] = self.group[name]
        return self._arrays[name]

    def state(self):
        """``(done, status)`` as flat arrays over the points (journal folded in first)."""
        self.compact()
        done = np.asarray(self.array("done")[...]).reshape(-1)
        status = np.asarray(self.array("status")[...], dtype=object).reshape(-1)
        return done, status

    def write(self, results):
        """Store points ``[(flat, record, series), ...]``: their time series (if any), then one
        journal line each, in one append (the commit)."""
        lines = []
        for flat, record, series in results:
            if self.sweep.time_series:
                index = tuple(int(i) for i in np.unravel_index(flat, self.sweep.shape))
                for name in self.sweep.time_series:
                    if name in series:
                        self.array(name)[index] = series[name]
                    else:  # a point without results: clear what a previous attempt may have left
                        self.array(name)[index] = np.nan
            lines.append(json.dumps({"i": int(flat), **record}, default=_plain) + "\n")
        os.write(self._journal_fd, "".join(lines).encode())
        if time.monotonic() - self._last_compact > COMPACT_INTERVAL:
            self.compact()

    def compact(self):
        records = _read_journal(self.path / JOURNAL)
        sp = self.sweep
        for name, (index, values) in _scatter(records, sp.shape, sp.quantities, sp.max_impacts).items():
            self.array(name).vindex[index] = values
        if records:
            os.ftruncate(self._journal_fd, 0)
        self._last_compact = time.monotonic()

    def import_dataset(self, ds):
        """Fill the store from a loaded results Dataset (a NetCDF export being resumed)."""
        for name in list(ALWAYS) + list(self.sweep.quantities) + list(self.sweep.time_series):
            values = ds[name].values
            self.array(name)[...] = values.astype(object) if values.dtype.kind in "OUST" else values
        self.array("done")[...] = ds["done"].values.astype(bool)

    def close(self, session=None):
        try:
            self.compact()
            if session is not None:
                runs = json.loads(self.group.attrs.get("runs", "[]"))
                runs.append(session)
                self.group.attrs.update({"runs": json.dumps(runs)})
        finally:
            self.close_files()

    def close_files(self):
        if self._journal_fd is not None:
            os.close(self._journal_fd)
            self._journal_fd = None
        self._unlock()


def _plain(value):
    """JSON form of NumPy scalars and arrays in a record."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"cannot store {type(value).__name__} in a sweep record")


def _side_store(path: Path) -> Path:
    return path.with_name(path.name + ".partial.zarr")


def _is_netcdf(path) -> bool:
    return Path(path).suffix.lower() in (".nc", ".nc4", ".netcdf")


def _export_netcdf(side: Path, path: Path):
    """Write the side store's results to ``path`` atomically (:func:`lubelink._files.atomic_path`)."""
    ds = load_sweep(side)
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4")
    return ds


# ====================================================================== reading
def _normalise(ds):
    """Strings as Python objects, whichever backend (Zarr StringDType, NetCDF fixed width)."""
    for name in list(ds.variables):
        if ds[name].dtype.kind in "TUS":
            if name in ds.coords:
                ds = ds.assign_coords({name: ds[name].astype(object)})
            else:
                ds[name] = ds[name].astype(object)
    ds = renamed(ds)  # a store of format 1.0: the pad's coordinate was X
    first = ["done", "status", "message"] + ds.attrs.get("quantities", "").split() + ["wall_time"]
    order = [v for v in first if v in ds.data_vars] + [v for v in ds.data_vars if v not in first]
    return ds[order]


def load_sweep(path):
    """The results of a sweep as an in-memory :class:`xarray.Dataset`.

    Works on a store being written (it reads the arrays and the journal, both
    written atomically) and on a NetCDF export (preferring its side store when
    a run was interrupted). Points with ``done == False`` hold the no-data
    values: NaN, -1 and empty strings.
    """
    import warnings

    import xarray as xr

    path = Path(path)
    if _is_netcdf(path) and not _side_store(path).exists():
        ds = read_netcdf(path, "sweep results file", SweepError)
        _check_format(path, ds.attrs)
        return _normalise(ds)
    if _is_netcdf(path):
        path = _side_store(path)
    if not path.exists():
        raise SweepError(f"{path}: no such sweep store")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", category=UserWarning)
        try:
            ds = xr.open_zarr(str(path), consolidated=False, chunks=None).load()
        except Exception as exc:  # noqa: BLE001 - many backend error types
            raise SweepError(f"{path}: not a readable Zarr store ({exc})") from None
    _check_format(path, ds.attrs)
    ds = _normalise(ds)
    records = _read_journal(path / JOURNAL)
    if records:
        shape = tuple(ds.sizes[d] for d in ds.attrs["swept_dims"].split())
        quantities = ds.attrs.get("quantities", "").split()
        for name, (index, values) in _scatter(records, shape, quantities, ds.sizes.get("impact", 0)).items():
            ds[name].data[index] = values
    return ds


def outcome(path):
    """``(done, status, message, attrs)`` of a sweep's results: flat arrays over the points and the
    store's attributes. Read with Zarr alone from a Zarr store (its journal included); a NetCDF
    export through :func:`load_sweep`."""
    path = Path(path)
    if _is_netcdf(path) and not _side_store(path).exists():
        ds = load_sweep(path)
        return (ds.done.values.reshape(-1), ds.status.values.reshape(-1), ds.message.values.reshape(-1),
                dict(ds.attrs))
    import zarr

    folder = _side_store(path) if _is_netcdf(path) else path
    g = zarr.open_group(str(folder), mode="r")
    attrs = dict(g.attrs)
    _check_format(path, attrs)
    arrays = {name: np.asarray(g[name][...]) for name in ("done", "status", "message")}
    arrays["status"], arrays["message"] = arrays["status"].astype(object), arrays["message"].astype(object)
    for name, (index, values) in _scatter(_read_journal(folder / JOURNAL), arrays["done"].shape, (), 0).items():
        if name in arrays:
            arrays[name][index] = values
    return arrays["done"].reshape(-1), arrays["status"].reshape(-1), arrays["message"].reshape(-1), attrs


def point_config(results, point):
    """The validated :class:`~lubelink.params.Config` of one point of a sweep's results.

    Parameters
    ----------
    results : xarray.Dataset or path
        Results of :func:`run_sweep` (or a store path).
    point : dict
        ``{dimension: value}`` for every swept dimension (``point`` takes the
        point number), e.g. ``{"film.viscosity": 0.1, "mechanism.crank_speed": 30.0}``.

    Example: ``lubelink.simulate(point_config(ds, {...}))`` runs that point again
    with its full results.
    """
    from ..config import from_stored, resolve

    ds = results if hasattr(results, "data_vars") else load_sweep(results)
    dims = ds.attrs["swept_dims"].split()
    missing = [d for d in dims if d not in point]
    if missing or set(point) - set(dims):
        raise SweepError(f"point {point}: give exactly one value for each of " + ", ".join(dims))
    try:
        one = ds.sel(point)
    except KeyError as exc:
        raise SweepError(f"point {point}: no such value {exc}") from None
    overrides = {str(c.attrs["parameter"]): c.values.item() for c in one.coords.values() if "parameter" in c.attrs}
    return resolve(from_stored(tomllib.loads(ds.attrs["base_config"]), "the sweep's base_config attribute"), overrides)


def _check_format(path, attrs):
    version = str(attrs.get("lubelink_sweep_format", ""))
    if not version:
        raise SweepError(f"{path}: not a lubelink sweep store (no lubelink_sweep_format attribute)")
    if version.split(".")[0] != SWEEP_FORMAT.split(".")[0]:
        raise SweepError(f"{path}: sweep store format {version}, this lubelink reads {SWEEP_FORMAT}")
