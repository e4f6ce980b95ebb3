"""Output files: checked before the work, written atomically, published without clobbering.

Every file or folder lubelink writes goes through :func:`atomic_path`: it is written under a
temporary name in the target folder, given the mode the user's umask asks for (``mkstemp`` would
leave it ``0600``), and renamed to the target only once complete, so an interrupted write leaves
either the old file or the new one, never half of one. Without ``overwrite`` the rename is
exclusive (``renameat2(RENAME_NOREPLACE)``, or a hard link then an unlink): a file that appeared
at the target meanwhile is never replaced, and :class:`FileExistsError` says so. With
``overwrite`` only a regular file is replaced, never a folder, a device or a FIFO.

A temporary is named ``.<name>.<host>-<pid>-<random>.part<suffix>``; a process killed with
SIGKILL cannot remove it, so the next write to the same target removes the temporaries of
processes of this host that are gone (:func:`remove_stale_temporaries`).

:func:`target_problem` tells, before any work is done, why a target could not be written (not a
regular file, folder missing or not writable), so that a long computation is not lost at the end.
:func:`read_netcdf` reads a NetCDF file back, with an error naming the file when it cannot.
"""

from __future__ import annotations

import errno
import os
import re
import secrets
import stat
import time
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_path", "umask_mode", "target_problem", "folder_problem", "remove_stale_temporaries",
           "publish", "fallback_path", "read_netcdf"]

#: Temporaries of the former naming (``mkstemp``: no process id) older than this are removed [s].
LEGACY_STALE_AGE = 3600.0


def umask_mode(mode=0o666):
    """``mode`` with the process umask applied (what ``open()`` would give a new file)."""
    umask = os.umask(0)
    os.umask(umask)
    return mode & ~umask


# ====================================================================== temporaries
def _host_tag() -> str:
    import hashlib
    import socket

    return hashlib.blake2s(socket.gethostname().encode(errors="replace"), digest_size=3).hexdigest()


def _temporary_name(path: Path, suffix: str) -> Path:
    return path.with_name(f".{path.name}.{_host_tag()}-{os.getpid()}-{secrets.token_hex(4)}.part{suffix}")


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # EPERM: a process of another user
        return True
    return True


def _remove(p: Path):
    if p.is_dir() and not p.is_symlink():
        import shutil

        shutil.rmtree(p, ignore_errors=True)
    else:
        try:
            p.unlink()
        except OSError:
            pass


def remove_stale_temporaries(path) -> list:
    """Remove the temporaries of earlier writes to ``path`` whose process is gone; return them.

    Only names of lubelink's own pattern are touched: ``.<name>.<host>-<pid>-<hex>.part...`` of
    this host whose process no longer exists, and temporaries of the former naming
    (``.<stem>.<8 characters>.part<suffix>``) untouched for :data:`LEGACY_STALE_AGE`.
    """
    path = Path(path)
    folder = path.parent
    ours = re.compile(re.escape(f".{path.name}.") + r"([0-9a-f]{6})-(\d+)-[0-9a-f]{8}\.part" + r"(\..*)?\Z")
    legacy = re.compile(re.escape(f".{path.stem}.") + r"[A-Za-z0-9_]{8}\.part" + re.escape(path.suffix) + r"\Z")
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    host = None
    now = time.time()
    for entry in entries:
        name = entry.name
        if not name.startswith(".") or ".part" not in name:
            continue
        m = ours.match(name)
        if m:
            host = host or _host_tag()
            if m.group(1) != host or _alive(int(m.group(2))):
                continue
        elif legacy.match(name):
            try:
                if now - entry.stat(follow_symlinks=False).st_mtime < LEGACY_STALE_AGE:
                    continue
            except OSError:
                continue
        else:
            continue
        _remove(folder / name)
        removed.append(folder / name)
    return removed


# ====================================================================== checks before the work
def _kind(mode) -> str:
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def folder_problem(folder) -> str | None:
    """Why nothing can be written in ``folder`` (missing, not a folder, not writable), or None.

    Writability is probed by creating (and removing) a temporary file there: permission bits say
    nothing for root, nor about read-only mounts and pseudo file systems like ``/proc``.
    """
    folder = Path(folder)
    if not folder.exists():
        return f"folder {folder} does not exist"
    if not folder.is_dir():
        return f"{folder} is not a folder"
    probe = _temporary_name(folder / "lubelink-write-test", "")
    remove_stale_temporaries(probe.with_name("lubelink-write-test"))  # probes of killed processes
    try:
        fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except OSError as exc:
        return f"cannot create files in folder {folder} ({exc.strerror or exc})"
    os.close(fd)
    try:
        os.unlink(probe)
    except OSError:
        pass
    return None


def target_problem(path, directory=False) -> str | None:
    """Why ``path`` could not be (re)placed by a new file (or folder), or None.

    An existing target must be a regular file (a folder when ``directory``): lubelink never
    replaces a device, a FIFO or a folder by a file. The folder must exist and be writable.
    Whether an existing target may be replaced at all (``--overwrite``) is the caller's rule.
    """
    path = Path(path)
    try:
        st = os.stat(path)
    except FileNotFoundError:
        st = None
        if os.path.islink(path):
            return "is a dangling symbolic link"
    except OSError as exc:
        return f"cannot inspect it ({exc.strerror or exc})"
    if st is not None:
        if directory and not stat.S_ISDIR(st.st_mode):
            return f"exists and is {'a file' if stat.S_ISREG(st.st_mode) else _kind(st.st_mode)}, not a folder"
        if not directory and not stat.S_ISREG(st.st_mode):
            return f"is {_kind(st.st_mode)}; only a regular file is ever replaced"
    return folder_problem(path.parent)


# ====================================================================== publishing
_RENAME_NOREPLACE = 1
_AT_FDCWD = -100


def _renameat2_noreplace(src, dst) -> bool:
    """Rename without replacing (Linux ``renameat2``); False when the system cannot do it."""
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    fn.argtypes = (ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint)
    if fn(_AT_FDCWD, os.fsencode(src), _AT_FDCWD, os.fsencode(dst), _RENAME_NOREPLACE) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP, errno.EOPNOTSUPP):
        return False  # an old kernel, or a file system without the flag
    raise OSError(err, os.strerror(err), str(dst))


def publish(tmp, path, overwrite):
    """Move the finished ``tmp`` to ``path``; without ``overwrite``, never replace anything there.

    Raises :class:`FileExistsError` when ``path`` exists and may not be replaced (it appeared
    since the work started), and :class:`IsADirectoryError` or :class:`OSError` when it is not a
    regular file.
    """
    tmp, path = Path(tmp), Path(path)
    if overwrite:
        try:
            st = os.stat(path)
        except FileNotFoundError:
            st = None
        if st is not None and not (stat.S_ISDIR(st.st_mode) if tmp.is_dir() else stat.S_ISREG(st.st_mode)):
            raise IsADirectoryError(errno.EISDIR if stat.S_ISDIR(st.st_mode) else errno.EEXIST,
                                    f"is {_kind(st.st_mode)}; only a regular file is ever replaced", str(path))
        os.replace(tmp, path)
        return
    try:
        if _renameat2_noreplace(tmp, path):
            return
    except FileExistsError:
        raise FileExistsError(errno.EEXIST, "appeared while lubelink was working; not replaced", str(path)) from None
    if tmp.is_dir():  # no atomic no-replace rename of folders here: rename fails onto a non-empty folder
        if os.path.lexists(path):
            raise FileExistsError(errno.EEXIST, "appeared while lubelink was working; not replaced", str(path))
        try:
            os.rename(tmp, path)
        except OSError as exc:
            if exc.errno in (errno.ENOTEMPTY, errno.EEXIST, errno.ENOTDIR):
                raise FileExistsError(errno.EEXIST, "appeared while lubelink was working; not replaced",
                                      str(path)) from None
            raise
        return
    try:
        os.link(tmp, path)  # fails if anything is at path: exclusive
    except FileExistsError:
        raise FileExistsError(errno.EEXIST, "appeared while lubelink was working; not replaced", str(path)) from None
    except OSError as exc:  # a file system without hard links
        if exc.errno not in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EMLINK, errno.EXDEV):
            raise
        if os.path.lexists(path):
            raise FileExistsError(errno.EEXIST, "appeared while lubelink was working; not replaced",
                                  str(path)) from None
        os.rename(tmp, path)
        return
    os.unlink(tmp)


@contextmanager
def atomic_path(path, suffix=None, overwrite=True, directory=False):
    """Yield a temporary path beside ``path``; move it to ``path`` if the block succeeds.

    Parameters
    ----------
    path : str or os.PathLike
        The file (or folder) to write.
    suffix : str, optional
        Suffix of the temporary name; default ``path``'s own suffix, so that writers which pick
        the format from the suffix (Matplotlib, Pillow, Zarr) see the right one.
    overwrite : bool
        Replace an existing regular file at ``path``; when false, a target that exists when the
        block ends is left alone and :class:`FileExistsError` is raised (the temporary is removed).
    directory : bool
        The block creates a folder at the temporary path (nothing is created there beforehand);
        otherwise an empty file reserves the name.

    A failure (or an interruption) inside the block removes the temporary. Stale temporaries of
    earlier writes to ``path`` by processes that are gone are removed first.
    """
    path = Path(path)
    suffix = path.suffix if suffix is None else suffix
    remove_stale_temporaries(path)
    tmp = _temporary_name(path, suffix)
    try:
        if not directory:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
            os.close(fd)
        yield tmp
        if tmp.is_file():
            os.chmod(tmp, umask_mode())
        publish(tmp, path, overwrite)
    except BaseException:
        _remove(tmp)
        raise


def fallback_path(path, folders=()) -> Path | None:
    """A free file name for results that could not be written at ``path``: beside it, else in
    ``folders`` (in order), else None. The name is ``<stem>.unsaved-<time>-<pid><suffix>``."""
    path = Path(path)
    name = f"{path.stem}.unsaved-{time.strftime('%Y%m%d-%H%M%S')}-{os.getpid()}{path.suffix}"
    for folder in (path.parent, *folders):
        folder = Path(folder)
        if folder_problem(folder) is None and not (folder / name).exists():
            return folder / name
    return None


# ====================================================================== reading
def read_netcdf(path, what, error=ValueError, name=None):
    """The NetCDF file ``path`` loaded into memory as an :class:`xarray.Dataset`.

    Raises ``error`` (the caller's error type) with a message naming the file: ``"<path>: no such
    <what>"`` when there is nothing there, ``"<path>: a folder, not a <what>"`` (or another kind of
    file), ``"<path>: not a readable NetCDF file (<why>)"`` when the
    netCDF4 backend cannot read it (it raises many types for a foreign file). ``name`` replaces
    ``<path>`` in the messages (e.g. the spelling the user gave).
    """
    import xarray as xr

    path = Path(path)
    shown = str(path) if name is None else name
    if not path.exists():
        raise error(f"{shown}: no such {what}")
    if not path.is_file():
        raise error(f"{shown}: {_kind(path.stat().st_mode)}, not a {what}")
    try:
        return xr.load_dataset(path, engine="netcdf4")
    except Exception as exc:  # noqa: BLE001 - the backend raises many types for a foreign file
        raise error(f"{shown}: not a readable NetCDF file ({exc})") from None
