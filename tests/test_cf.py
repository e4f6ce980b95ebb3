"""Every file lubelink writes follows the CF conventions it names (CF-1.10, issue 35 item 5).

The writers: ``lubelink run`` (netCDF4), :func:`lubelink.save` (xarray), ``lubelink periodic``,
``lubelink continue``, and a sweep's Zarr store and its NetCDF export. Each file is checked here
against the rules of CF-1.10 that apply to it (the ``Conventions`` attribute, units UDUNITS-2
parses, long names, no two names differing only by case, ``axis`` on the spatial coordinates and
only where CF allows it), and, where the ``cfchecker`` package runs (it needs the UDUNITS-2 C
library), by the CF checker itself.
"""

import re

import numpy as np
import pytest

import lubelink
from lubelink.cli import main

xr = pytest.importorskip("xarray")

#: The sweep of the store checked: numbers only (CF coordinate variables are numeric), a series
#: over each extra dimension (mode, x, x_pad), the summaries of every kind (float, int, string, impacts).
SWEEP = {"base": "paper", "set": {"solver.t_end": 0.05, "output.x_points": 5, "output.pad_points": 5},
         "vary": {"film.viscosity": [0.05, 0.1], "mechanism.crank_speed": [20.0, 30.0]},
         "store": {"quantities": ["peak_u2_mid", "impact_count", "regime", "impact_times"],
                   "time_series": ["pressure", "u2", "q", "u2_mid"]}}
SHORT = ["--set", "solver.t_end=0.3", "--set", "output.x_points=21", "--set", "output.pad_points=11"]


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """``{writer: path}`` of one file of every writer, and the summaries the commands printed."""
    import contextlib
    import io

    folder = tmp_path_factory.mktemp("cf")
    files, printed = {}, {}

    def command(name, args):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            assert main(args + ["-o", str(folder / f"{name}.nc")]) == 0, name
        files[name], printed[name] = folder / f"{name}.nc", out.getvalue()

    command("run", ["run", "--scenario", "paper", *SHORT, "--set", "film.sides=2"])
    command("periodic", ["periodic", "--scenario", "paper-dry", "--set", "beam.damping_ratio=0.05"])
    command("continue", ["continue", "--scenario", "paper-dry", "--set", "beam.damping_ratio=0.05", "--from", "30",
                         "--to", "30.5"])
    files["save"] = lubelink.save(lubelink.simulate("paper-impact", {"solver.t_end": 1.3}), folder / "save.nc")
    distributed = pytest.importorskip("distributed")
    pytest.importorskip("zarr")
    from lubelink.sweep import run_sweep

    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=":0") as client:
        run_sweep(SWEEP, folder / "sweep.zarr", client=client, progress=False)
        run_sweep(SWEEP, folder / "sweep.nc", client=client, progress=False)
    files["sweep.zarr"], files["sweep.nc"] = folder / "sweep.zarr", folder / "sweep.nc"
    return files, printed


def _contents(path):
    """``(global attributes, {name: (dims, dtype kind, attributes)})`` of a NetCDF file (netCDF4: the
    attributes as written) or a Zarr store."""
    if path.suffix == ".zarr":
        import warnings

        with warnings.catch_warnings():  # (the store's journal and lock: not Zarr arrays)
            warnings.simplefilter("ignore", category=UserWarning)
            ds = xr.open_zarr(path, consolidated=False, decode_cf=False)
        return dict(ds.attrs), {n: (v.dims, v.dtype.kind, dict(v.attrs)) for n, v in ds.variables.items()}
    import netCDF4

    with netCDF4.Dataset(path) as nc:
        variables = {n: (v.dimensions, "O" if v.dtype is str else np.dtype(v.dtype).kind,
                         {a: v.getncattr(a) for a in v.ncattrs()}) for n, v in nc.variables.items()}
        return {a: nc.getncattr(a) for a in nc.ncattrs()}, variables


def cf_faults(attrs, variables):
    """What breaks CF-1.10 in a file's global attributes and variables (the rules that apply here)."""
    faults = []
    if attrs.get("Conventions") != "CF-1.10":
        faults.append(f"Conventions = {attrs.get('Conventions')!r}")
    faults += [f"no global {a}" for a in ("title", "source") if not attrs.get(a)]
    names = set(variables) | {d for dims, _, _ in variables.values() for d in dims}
    lower = {}
    for name in names:  # CF 2.3: no two names that differ only by case
        lower.setdefault(name.lower(), []).append(name)
    faults += [f"names differ only by case: {sorted(v)}" for v in lower.values() if len(v) > 1]
    try:
        import cf_units
    except ImportError:  # (its own UDUNITS-2: the units are then only checked by cfchecker, where it runs)
        cf_units = None
    for name, (dims, kind, a) in variables.items():
        if not a.get("long_name"):
            faults.append(f"{name}: no long_name")
        if kind in "biuf":  # strings and the sweep's choices carry no units
            if "units" not in a:
                faults.append(f"{name}: no units")
            elif cf_units is not None and cf_units.Unit(a["units"]).is_unknown():
                faults.append(f"{name}: units {a['units']!r} are not UDUNITS")
        axis = a.get("axis")
        if axis is not None:  # CF 4: X, Y, Z or T on coordinate variables; T is a calendar time
            if axis not in ("X", "Y", "Z", "T") or dims != (name,):
                faults.append(f"{name}: axis {axis!r} on dimensions {dims}")
            if axis == "T" and "since" not in a.get("units", ""):
                faults.append(f"{name}: axis T without a reference time in its units")
        if name in ("x", "x_pad") and axis != "X":
            faults.append(f"{name}: axis {axis!r}, not 'X'")
    for name, (dims, _, _) in variables.items():  # CF 4: one coordinate of each axis per variable
        axes = [variables[d][2].get("axis") for d in dims if d in variables]
        axes = [x for x in axes if x]
        if len(axes) != len(set(axes)):
            faults.append(f"{name}: two coordinates of one axis {axes}")
    return faults


WRITERS = ["run", "save", "periodic", "continue", "sweep.zarr", "sweep.nc"]


@pytest.mark.parametrize("writer", WRITERS)
def test_every_writer_writes_cf_attributes(written, writer):
    files, _ = written
    attrs, variables = _contents(files[writer])
    assert cf_faults(attrs, variables) == []
    expected = {"run": {"x", "x_pad", "time"}, "save": {"x", "x_pad", "time"}, "periodic": {"x", "time"},
                "continue": {"point"}, "sweep.zarr": {"x", "x_pad", "time"}, "sweep.nc": {"x", "x_pad", "time"}}
    assert expected[writer] <= set(variables)  # the coordinates checked above are there
    assert "X" not in variables


def test_the_checks_catch_what_they_check():
    """The faults :func:`cf_faults` is written to find, each in a file of its own."""
    good = {"x": (("x",), "f", {"units": "m", "long_name": "x", "axis": "X"})}
    attrs = {"Conventions": "CF-1.10", "title": "t", "source": "s"}
    assert cf_faults(attrs, good) == []
    assert cf_faults({**attrs, "Conventions": "CF-1.8"}, good)
    assert cf_faults(attrs, {**good, "X": (("X",), "f", {"units": "m", "long_name": "X"})})
    assert cf_faults(attrs, {"x": (("x",), "f", {"units": "m", "long_name": "x"})})  # no axis
    assert cf_faults(attrs, {**good, "t": (("t",), "f", {"units": "s", "long_name": "t", "axis": "T"})})
    assert cf_faults(attrs, {**good, "p": (("x",), "f", {"long_name": "p"})})  # no units
    assert cf_faults(attrs, {**good, "y": (("y",), "f", {"units": "m", "long_name": "y", "axis": "X"}),
                             "p": (("x", "y"), "f", {"units": "Pa", "long_name": "p"})})


def test_the_summaries_quote_the_wall_time_in_the_files(written):
    """``continue`` and ``periodic`` print the wall time their file records (and the command's in all)."""
    import netCDF4

    files, printed = written
    for writer, words in (("continue", "finding the branch"), ("periodic", "finding and sampling the orbit")):
        line = next(row for row in printed[writer].splitlines() if row.startswith("wall time"))
        shown, total = (float(v) for v in re.findall(rf"([0-9.]+) s {words} \(its wall_time\), ([0-9.]+) s in all",
                                                      line)[0])
        with netCDF4.Dataset(files[writer]) as nc:
            assert nc.wall_time_units == "s"
            digits = 2 if writer == "continue" else 3
            assert shown == round(float(nc.wall_time), digits), (line, nc.wall_time)
            assert 0.0 < nc.wall_time <= total + 10.0 ** -digits


#: What cfchecker 4.1.0 (the last on PyPI, for CF up to 1.8) reports that CF-1.10 allows, and why.
KNOWN = {
    # it knows CF-1.0 to CF-1.8 only: "CF-1.10" is checked as CF-1.8 (version= below)
    "(2.6.1): This netCDF file does not appear to contain CF Convention data.",
    # the NetCDF-4 string type: CF 2.2 allows it ("atomic strings") since CF-1.8; the checker predates that
    "(2.2): Invalid variable type: \"<class 'netCDF4.VLType'>\": string type (vlen types not supported)",
}
#: CF 2.3 *recommends* (should) names of letters, digits and underscores: a sweep names its dimensions by
#: their configuration keys (``film.viscosity``), which the sweep's selections and files use throughout.
DOTTED = re.compile(r"\(2\.3\): (Dimension|Variable) names should begin with a letter and be composed of letters, "
                    r"digits and underscores(: [a-z_]+\.[a-z_]+)?")


@pytest.fixture(scope="module")
def cf_checker(tmp_path_factory):
    """A CF checker that reads its tables from files made here (it would download the standard name, area
    type and region tables: no name of those tables is used in lubelink's files)."""
    try:
        from cfchecker.cfchecks import CFChecker, vn1_8
    except Exception as exc:  # noqa: BLE001 - ImportError, or cfunits failing to load the UDUNITS-2 library
        pytest.skip(f"cfchecker does not run here ({type(exc).__name__}: {exc}); pip install cfchecker, with "
                    "the UDUNITS-2 library (Debian: libudunits2-0)")
    folder = tmp_path_factory.mktemp("cf-tables")
    tables = {"cfStandardNamesXML": ("standard_name_table", "last_modified"),
              "cfAreaTypesXML": ("area_type_table", "date"), "cfRegionNamesXML": ("standard_region_list", "date")}
    paths = {}
    for option, (root, date) in tables.items():
        paths[option] = folder / f"{root}.xml"
        paths[option].write_text(f"<?xml version='1.0'?><{root}><version_number>0</version_number>"
                                 f"<{date}>none</{date}></{root}>")

    def check(path):
        checker = CFChecker(**{k: str(v) for k, v in paths.items()}, version=vn1_8, silent=True)
        return checker.checker(str(path))

    return check


@pytest.mark.parametrize("writer", [w for w in WRITERS if w.endswith("nc") or "." not in w])
def test_cfchecker_finds_nothing_but_what_it_predates(written, cf_checker, writer):
    files, _ = written
    result = cf_checker(files[writer])
    found = []
    for where, levels in [("global", result["global"])] + list(result["variables"].items()):
        for level in ("FATAL", "ERROR", "WARN"):
            for message in levels[level]:
                if message in KNOWN or (writer.startswith("sweep") and DOTTED.fullmatch(message)):
                    continue
                found.append(f"{where}: {level} {message}")
    assert found == []
