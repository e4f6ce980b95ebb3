"""``lubelink animate``: simulate a configuration and write the mechanism as a GIF or MP4.

The frames are drawn by :func:`lubelink.plots.animate_mechanism`; this module
checks the options, runs the simulation at the frame rate and writes the
file atomically. Matplotlib is imported inside :func:`animate` only.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from .._files import atomic_path, target_problem

__all__ = ["animate"]


#: The most frames an animation draws (a GIF of 20 fps: 100 s), and the time a frame takes to draw [s]
#: (measured on the 2-core machine: 0.25 s).
MAX_FRAMES = 2000
SECONDS_PER_FRAME = 0.25


def animate(source="paper", set=None, output="mechanism.gif", fps=20, duration=0.4,
            speed=0.1, overwrite=False, dpi=80, progress=False):
    """Simulate and write an animation of the mechanism (GIF, or MP4 with ffmpeg).

    Parameters
    ----------
    source, set
        As for :func:`lubelink.simulate`; ``solver.t_end`` and
        ``solver.output_step`` are set from ``duration``, ``speed`` and ``fps``.
    output : path
        ``.gif`` (Pillow) or ``.mp4`` (needs ffmpeg); written atomically.
    fps : int
        Frames per second [1/s].
    duration : float
        Simulated time shown [s].
    speed : float
        Playback speed relative to real time [-] (0.1: ten times slower).
    overwrite : bool
        Replace an existing file.
    progress : bool
        Progress bars on stderr of the simulation and the drawing (where stderr is not a
        terminal: a line at the start and the end of each, :class:`lubelink.progress.Bar`).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ValueError
        For an unsupported suffix, missing ffmpeg, an existing file without
        ``overwrite`` or a non-positive option.
    """
    output = Path(output)
    suffix = output.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"-o {output}: the animation must be a .gif or .mp4 file")
    for name, value in (("--fps", fps), ("--duration", duration), ("--speed", speed)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ValueError(f"{name} = {value}: must be a positive number")
    if os.path.lexists(output) and not overwrite:
        raise ValueError(f"-o {output}: the file exists; add --overwrite to replace it")
    problem = target_problem(output)  # a regular file or nothing, in a writable folder
    if problem:
        raise ValueError(f"-o {output}: {problem}")
    import matplotlib.animation as manim

    if suffix == ".mp4" and not manim.FFMpegWriter.isAvailable():
        raise ValueError(f"-o {output}: writing MP4 needs ffmpeg, which was not found; write a .gif instead")
    from ..simulate import simulate

    frame_step = speed / fps
    frames = int(round(duration / frame_step))
    if frames < 2:
        raise ValueError(f"--duration {duration}: shows fewer than 2 frames at --fps {fps} and --speed {speed}")
    if frames > MAX_FRAMES:
        raise ValueError(f"--duration {duration} at --fps {fps} and --speed {speed}: {frames:,} frames, more than "
                         f"{MAX_FRAMES:,} (about {frames * SECONDS_PER_FRAME / 3600:.3g} h to draw); lower --fps or "
                         "--duration, or raise --speed")
    ds = simulate(source, {**(set or {}), "solver.t_end": frames * frame_step, "solver.output_step": frame_step},
                  progress=progress)
    from .. import plots

    fig, anim = plots.animate_mechanism(ds, fps=fps, dpi=dpi)
    writer = manim.PillowWriter(fps=fps) if suffix == ".gif" else manim.FFMpegWriter(fps=fps)
    bar = None
    callback = None
    if progress:
        from ..progress import Bar

        bar = Bar(ds.sizes["time"], "animating", "frame", leave=False)
        bar.stage(f"drawing {ds.sizes['time']} frames into {output.name}")

        def callback(i, n):
            bar.update(1)
    try:
        with atomic_path(output, overwrite=overwrite) as tmp:
            anim.save(str(tmp), writer=writer, dpi=dpi, progress_callback=callback)
    finally:
        if bar is not None:
            bar.close()
    return output
