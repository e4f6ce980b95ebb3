"""Atomic file output: every file lubelink writes goes through :func:`atomic_path`.

A file is written to a temporary name in the target folder, given the mode the user's umask asks
for (``mkstemp`` would leave it ``0600``), and renamed over the target only once complete, so an
interrupted write leaves either the old file or the new one, never half of one.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_path", "umask_mode"]


def umask_mode(mode=0o666):
    """``mode`` with the process umask applied (what ``open()`` would give a new file)."""
    umask = os.umask(0)
    os.umask(umask)
    return mode & ~umask


@contextmanager
def atomic_path(path, suffix=None):
    """Yield a temporary path beside ``path``; rename it over ``path`` if the block succeeds.

    Parameters
    ----------
    path : str or os.PathLike
        The file to (re)place.
    suffix : str, optional
        Suffix of the temporary name; default ``path``'s own suffix, so that writers which pick
        the format from the suffix (Matplotlib, Pillow, Zarr) see the right one.

    A failure (or an interruption) inside the block removes the temporary file.
    """
    path = Path(path)
    suffix = path.suffix if suffix is None else suffix
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f".part{suffix}", dir=path.parent)
    os.close(fd)
    tmp = Path(tmp)
    try:
        yield tmp
        if tmp.is_file():
            os.chmod(tmp, umask_mode())
        os.replace(tmp, path)
    except BaseException:
        if tmp.is_dir():
            import shutil

            shutil.rmtree(tmp, ignore_errors=True)
        else:
            tmp.unlink(missing_ok=True)
        raise
