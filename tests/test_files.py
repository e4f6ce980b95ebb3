"""Output files: exclusive atomic publishing, only regular files replaced, stale temporaries removed,
the umask honoured (issue 15, items 3, 5, 10 and 11)."""

import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from lubelink import _files
from lubelink._files import atomic_path, fallback_path, folder_problem, remove_stale_temporaries, target_problem


def entries(folder):
    return sorted(p.name for p in Path(folder).iterdir())


# ====================================================================== item 3: exclusive publish
@pytest.mark.parametrize("renameat2", [True, False], ids=["renameat2", "link-unlink"])
def test_a_file_that_appears_during_the_write_is_never_replaced(tmp_path, monkeypatch, renameat2):
    if not renameat2:  # the fallback of systems without RENAME_NOREPLACE: link, then unlink
        monkeypatch.setattr(_files, "_renameat2_noreplace", lambda src, dst: False)
    target = tmp_path / "r.nc"
    with pytest.raises(FileExistsError, match="appeared"):
        with atomic_path(target, overwrite=False) as tmp:
            tmp.write_text("mine")
            target.write_text("theirs")  # another run published meanwhile
    assert target.read_text() == "theirs"
    assert entries(tmp_path) == ["r.nc"]  # no temporary left


def test_without_a_competitor_the_exclusive_publish_writes(tmp_path):
    target = tmp_path / "r.nc"
    with atomic_path(target, overwrite=False) as tmp:
        tmp.write_text("mine")
    assert target.read_text() == "mine" and entries(tmp_path) == ["r.nc"]


def test_a_folder_is_published_exclusively(tmp_path):
    target = tmp_path / "s.zarr"
    with pytest.raises(FileExistsError):
        with atomic_path(target, overwrite=False, directory=True) as tmp:
            tmp.mkdir()
            (tmp / "a").write_text("mine")
            target.mkdir()
            (target / "b").write_text("theirs")
    assert entries(target) == ["b"] and entries(tmp_path) == ["s.zarr"]


# ====================================================================== item 5: only regular files
def special_files(folder):
    folder = Path(folder)
    (folder / "dir.nc").mkdir()
    os.mkfifo(folder / "fifo.nc")
    out = {"dir.nc": "a folder", "fifo.nc": "a FIFO"}
    if os.geteuid() == 0:
        os.mknod(folder / "null.nc", 0o666 | stat.S_IFCHR, os.makedev(1, 3))
        out["null.nc"] = "a device"
    return out


def test_overwrite_replaces_only_regular_files(tmp_path):
    for name, kind in special_files(tmp_path).items():
        assert kind in target_problem(tmp_path / name)
        with pytest.raises(OSError, match="only a regular file"):
            with atomic_path(tmp_path / name, overwrite=True) as tmp:
                tmp.write_text("x")
    assert stat.S_ISFIFO(os.stat(tmp_path / "fifo.nc").st_mode) and (tmp_path / "dir.nc").is_dir()
    assert not [n for n in entries(tmp_path) if ".part" in n]
    (tmp_path / "plain.nc").write_text("old")
    assert target_problem(tmp_path / "plain.nc") is None
    with atomic_path(tmp_path / "plain.nc", overwrite=True) as tmp:
        tmp.write_text("new")
    assert (tmp_path / "plain.nc").read_text() == "new"


def test_unwritable_folders_are_found_before_the_work():
    assert "cannot create files in folder /proc" in target_problem("/proc/x.nc")
    assert "does not exist" in target_problem("/nonexistent-dir/x.nc")
    assert folder_problem("/proc") is not None


@pytest.mark.skipif(os.geteuid() == 0, reason="permission bits do not bind root")
def test_a_read_only_folder_is_found_before_the_work(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        assert "cannot create files" in target_problem(ro / "x.nc")
    finally:
        ro.chmod(0o755)


# ====================================================================== item 10: stale temporaries
def dead_pid():
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_stale_temporaries_of_dead_processes_are_removed_on_the_next_write(tmp_path):
    target = tmp_path / "r.nc"
    host = _files._host_tag()
    dead = tmp_path / f".r.nc.{host}-{dead_pid()}-0123abcd.part.nc"
    dead.write_bytes(b"x" * 1000)
    dead_dir = tmp_path / f".r.nc.{host}-{dead_pid()}-0123abce.part.nc"
    dead_dir.mkdir()
    live = tmp_path / f".r.nc.{host}-{os.getpid()}-0123abcd.part.nc"  # a write in progress
    live.write_text("x")
    other_host = tmp_path / f".r.nc.ffffff-{dead_pid()}-0123abcd.part.nc"  # shared file system
    other_host.write_text("x")
    other_target = tmp_path / f".q.nc.{host}-{dead_pid()}-0123abcd.part.nc"
    other_target.write_text("x")
    legacy_old = tmp_path / ".r.abc_1234.part.nc"  # mkstemp naming of earlier versions
    legacy_old.write_text("x")
    os.utime(legacy_old, (1e9, 1e9))
    legacy_new = tmp_path / ".r.abc_1235.part.nc"
    legacy_new.write_text("x")
    with atomic_path(target) as tmp:
        tmp.write_text("results")
    assert not dead.exists() and not dead_dir.exists() and not legacy_old.exists()
    assert live.exists() and other_host.exists() and other_target.exists() and legacy_new.exists()
    assert target.read_text() == "results"
    assert remove_stale_temporaries(target) == []


def test_a_sigkilled_write_leaves_a_temporary_that_the_next_write_removes(tmp_path):
    code = ("import os, signal, sys\n"
            "from lubelink._files import atomic_path\n"
            "with atomic_path(sys.argv[1]) as tmp:\n"
            "    tmp.write_bytes(b'x' * 100000)\n"
            "    os.kill(os.getpid(), signal.SIGKILL)\n")
    r = subprocess.run([sys.executable, "-c", code, str(tmp_path / "r.nc")])
    assert r.returncode == -9
    assert [n for n in entries(tmp_path) if ".part" in n], "the killed write left no temporary"
    with atomic_path(tmp_path / "r.nc") as tmp:
        tmp.write_text("ok")
    assert entries(tmp_path) == ["r.nc"]


# ====================================================================== item 11: the umask
@pytest.mark.parametrize("umask", [0o022, 0o002, 0o077])
def test_files_and_folders_honour_the_umask(tmp_path, umask):
    old = os.umask(umask)
    try:
        with atomic_path(tmp_path / "f.txt") as tmp:
            tmp.write_text("x")
        with atomic_path(tmp_path / "d.zarr", directory=True) as tmp:
            tmp.mkdir()
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(tmp_path / "f.txt").st_mode) == 0o666 & ~umask
    assert stat.S_IMODE(os.stat(tmp_path / "d.zarr").st_mode) == 0o777 & ~umask


def test_fallback_names_are_free_and_beside_the_target(tmp_path):
    target = tmp_path / "r.nc"
    other = fallback_path(target)
    assert other.parent == tmp_path and other.name.startswith("r.unsaved-") and other.suffix == ".nc"
    assert fallback_path("/proc/r.nc", folders=[tmp_path]).parent == tmp_path
    assert fallback_path("/proc/r.nc") is None


# ====================================================================== issue 16 item 4: one helper for every output
#: Calls that write a file: the method names, and for which the written path is the receiver
#: (``tmp.write_text(...)``) rather than the first argument (``fig.savefig(tmp)``).
WRITERS = {"savefig": "arg", "to_netcdf": "arg", "to_zarr": "arg", "savez": "arg", "savez_compressed": "arg",
           "save": "arg", "write_text": "receiver", "write_bytes": "receiver", "touch": "receiver"}
#: Writes that are not outputs published under their name, each with its reason.
NOT_PUBLISHED = {
    ("src/lubelink/sweep/store.py", "touch"): "the journal, created inside the store folder before it is published",
    ("benchmarks/exudyn_rod.py", "savez"): "a worker's answer in a private temporary folder (its interpreter has "
                                          "no lubelink)",
    ("benchmarks/exudyn_frequency.py", "savez"): "the same, for the frequency set-ups",
    ("benchmarks/exudyn_coupled.py", "savez"): "the same, for the coupled crank and link",
    ("src/lubelink/sweep/_warm.py", "open"): "an empty file that says the pool's server is ready (its existence "
                                             "is the message)",
    ("benchmarks/bench.py", "write_text"): "the smallest cached kernel's module, in the start section's private "
                                           "temporary folder",
}


def _writes(tree):
    """``(call, method name, written expression)`` of every file-writing call of a module."""
    import ast

    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        f = node.func
        name = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else None
        if name == "Dataset" and len(node.args) >= 2 and isinstance(node.args[1], ast.Constant) \
                and node.args[1].value in ("w", "a", "r+"):
            yield node, "netCDF4.Dataset", node.args[0]
        elif name == "open" and any(isinstance(a, ast.Constant) and isinstance(a.value, str) and
                                    set(a.value) & set("wax+") for a in node.args[1:2]):
            yield node, "open", node.args[0]
        elif name in WRITERS and isinstance(f, ast.Attribute):
            if name == "save" and isinstance(f.value, ast.Name) and f.value.id in ("lubelink", "results"):
                continue  # lubelink.save is itself the atomic writer
            target = f.value if WRITERS[name] == "receiver" else (node.args[0] if node.args else None)
            if target is not None:
                yield node, name, target


def test_every_output_is_written_through_the_atomic_helper():
    """Every call that writes a file in the package, the docs scripts, the benchmarks and the
    examples writes to the temporary of an enclosing ``with atomic_path(...) as tmp`` (or of
    results' ``_publishing``, which wraps it): the one helper that publishes atomically with the
    umask's mode."""
    import ast

    root = Path(__file__).resolve().parent.parent
    files = [*sorted((root / "src" / "lubelink").rglob("*.py")), *sorted((root / "docs").glob("*.py")),
             *sorted((root / "benchmarks").glob("*.py")), *sorted((root / "examples").glob("*.py"))]
    problems, checked = [], 0
    for path in files:
        rel = path.relative_to(root).as_posix()
        tree = ast.parse(path.read_text(encoding="utf-8"))
        temporaries = set()
        for node in ast.walk(tree):
            if isinstance(node, (ast.With, ast.AsyncWith)):
                for item in node.items:
                    call = item.context_expr
                    fn = call.func if isinstance(call, ast.Call) else None
                    fname = getattr(fn, "attr", None) or getattr(fn, "id", None)
                    if fname in ("atomic_path", "_publishing") and isinstance(item.optional_vars, ast.Name):
                        temporaries.add(item.optional_vars.id)
        for call, name, target in _writes(tree):
            if (rel, name) in NOT_PUBLISHED:
                continue
            checked += 1
            used = {n.id for n in ast.walk(target) if isinstance(n, ast.Name)}
            if not used & temporaries:
                problems.append(f"{rel}:{call.lineno}: {name} writes {ast.unparse(target)}, not an atomic_path temporary")
    assert checked >= 10
    assert not problems, "\n".join(problems)


class _Refused(Exception):
    pass


def test_read_netcdf_reads_a_file_and_names_the_path_when_it_cannot(tmp_path):
    import numpy as np
    import xarray as xr

    good = tmp_path / "good.nc"
    xr.Dataset({"a": ("t", np.arange(3.0))}, attrs={"kind": "test"}).to_netcdf(good, engine="netcdf4")
    ds = _files.read_netcdf(good, "test file")
    assert ds.attrs["kind"] == "test" and list(ds.a.values) == [0.0, 1.0, 2.0]
    good.unlink()  # loaded into memory: the file is not held open
    with pytest.raises(_Refused, match=r"missing\.nc: no such test file$"):
        _files.read_netcdf(tmp_path / "missing.nc", "test file", _Refused)
    with pytest.raises(_Refused, match=r"folder\.nc: a folder, not a test file$"):
        (tmp_path / "folder.nc").mkdir()
        _files.read_netcdf(tmp_path / "folder.nc", "test file", _Refused)
    foreign = tmp_path / "foreign.nc"
    foreign.write_text("not netcdf")
    with pytest.raises(_Refused, match=r"^as typed: not a readable NetCDF file \(") as info:
        _files.read_netcdf(foreign, "test file", _Refused, name="as typed")
    assert info.value.__cause__ is None and info.value.__suppress_context__
    with pytest.raises(ValueError, match="foreign.nc: not a readable NetCDF file"):
        _files.read_netcdf(foreign, "test file")
