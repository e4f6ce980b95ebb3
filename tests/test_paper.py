"""The paper's figures regenerated at low resolution, each checked against physics, and the CLI.

The figure set is computed once per module (``make_figures(low_res=True)``):
1 s runs instead of 2 s, rtol 1e-6, short modal runs; the checks below are
physical statements that hold at that resolution, each with its tolerance
justified next to it.
"""

import math
import subprocess
import sys

import numpy as np
import pytest

import lubelink
from lubelink import paper

pytest.importorskip("matplotlib")


@pytest.fixture(scope="module")
def figures(tmp_path_factory):
    out = tmp_path_factory.mktemp("figures")
    return out, paper.make_figures(out, low_res=True)


def test_every_figure_is_written_as_png_and_pdf(figures):
    out, result = figures
    assert set(result.paths) == set(paper.FIGURES)
    for name, stem in paper.FIGURES.items():
        for ext in ("png", "pdf"):
            path = out / f"{stem}.{ext}"
            assert path.is_file() and path.stat().st_size > 1000, path
            assert path.stat().st_size < 300_000, f"{path} is larger than 300 kB"
    assert (out / "lubrication-effect.md").read_text().startswith("| film |")
    assert (out / "calibration.json").is_file()
    assert not list(out.glob(".*")), "temporary files left behind"


def test_each_configuration_is_simulated_once(figures):
    _, result = figures
    # paper, dry, squeeze, 4 printed variants (corrected = paper), modes 1/3/5/7 (short runs),
    # the calibrated impact run; the lubrication table reuses paper and squeeze.
    assert result.runs == 3 + 4 + 4 + 1


def test_fig6_forced_response_is_periodic_with_the_crank(tmp_path):
    """With modal damping the free vibration started by zero initial conditions dies out and
    what is left repeats every crank turn (paper: "the overall motion is periodic")."""
    result = paper.make_figures(tmp_path, low_res=True, only=["fig6"], overrides={"beam.damping_ratio": 0.05})
    ds = result.data["fig6"]["paper"]
    T = 2 * np.pi / 31.4159
    dt = float(ds.time[1] - ds.time[0])
    n = int(round(T / dt))
    assert abs(n * dt - T) < 0.01 * dt  # the output step divides the period
    u = ds.u2.values
    last = slice(-n, None)
    drift = np.abs(u[last] - u[-2 * n:-n]).max()
    # decay exp(-zeta omega_1 t) = exp(-0.05 * 148.2 * 0.8) = 2.7e-3 of a ~0.5 mm free vibration
    assert drift < 0.01 * np.abs(u).max()
    # without damping the paper's Fig. 6 is not periodic: the free vibration persists
    undamped = paper.Study(paper.RESOLUTIONS["low"]["overrides"]).dataset("paper-dry").u2.values
    assert np.abs(undamped[last] - undamped[-2 * n:-n]).max() > 0.2 * np.abs(undamped).max()


def test_fig7_films_against_the_dry_joint(figures):
    _, result = figures
    d = result.data["fig7"]
    peak = {k: float(np.abs(ds.u2_mid).max()) for k, ds in d.items()}
    dry, wedge, squeeze = (peak[k] for k in ("dry joint (paper-dry)", "wedge film (paper)", "wedge + squeeze film"))
    # the wedge film adds no damping: the peak stays within a few per cent of the dry joint's
    assert abs(wedge / dry - 1) < 0.05
    # the squeeze film damps the free vibration: a clearly smaller peak
    assert squeeze < 0.95 * dry


def test_fig8_pressure_vanishes_at_the_pad_edges_and_integrates_to_the_film_force(figures):
    _, result = figures
    ds = result.data["fig8"]["paper"]
    p = ds.pressure.values
    assert np.abs(p[:, [0, -1]]).max() <= 1e-9 * np.abs(p).max()  # P = p_am at both edges
    B = lubelink.results.config_of(ds).beam.width
    X = ds.x_pad.values
    force = -B * np.sum(0.5 * (p[:, 1:] + p[:, :-1]) * np.diff(X), axis=1)
    # trapezoid on 11 pad points against the model's Gauss-Legendre force: a few per cent
    assert np.abs(force - ds.film_force.values).max() < 0.05 * np.abs(ds.film_force.values).max()


def test_fig9_first_impact_is_the_calibrated_one(figures):
    _, result = figures
    cal = result.calibration
    ds = result.data["fig9"]["paper-impact"]
    assert lubelink.results.config_of(ds).film.clearance == cal.clearance
    assert ds.impact_time.size >= 1
    # the simulation with impacts finds the same first breakdown as the calibration's runs
    assert float(ds.impact_time[0]) == pytest.approx(cal.first_impact, abs=1e-9)
    if cal.reached:
        assert abs(float(ds.impact_time[0]) - paper.PAPER_IMPACT_TIME) <= cal.tolerance
    else:
        # not reachable: the clearance is the evaluated one closest to the target
        best = min(abs(t - cal.target) for _, t in cal.evaluations)
        assert abs(cal.miss) == pytest.approx(best)
        if cal.bracket[0] != cal.bracket[1]:  # a jump of t1(H) across the target, bracketed tightly
            lo, hi = (min(t, cal.t_stop) for t in cal.bracket_times)
            assert (lo < cal.target) != (hi < cal.target)
            assert cal.bracket[1] - cal.bracket[0] < 1e-6
    # every impact reverses the approach: impacts are separated in time
    assert np.all(np.diff(ds.impact_time.values) > 0)


def test_modal_differences_shrink_with_the_number_of_modes(figures):
    _, result = figures
    d = result.data["modes"]
    ref = d[7].u2_mid.values
    diff = [np.abs(d[n].u2_mid.values - ref).max() for n in (1, 3, 5)]
    assert diff[0] > diff[1] > diff[2] > 0
    assert diff[0] < 0.05 * np.abs(ref).max()  # "no perceptible difference" (paper): a few per cent


def test_errata_variants_differ_from_the_corrected_run_by_their_expected_size(figures):
    _, result = figures
    d = result.data["errata"]
    ref = d["corrected"].u2_mid.values
    scale = np.abs(ref).max()

    def variant(prefix):
        (label,) = [k for k in d if k.startswith(prefix)]
        return d[label]

    def change(prefix):
        u = variant(prefix).u2_mid.values
        return np.abs(u - ref[: u.size]).max() / scale

    # omega^2 / omega_1^2 <= 2.2e-4: the printed sign shifts the frequency by ~1e-4, a tiny drift
    assert 0 < change("+omega^2 q") < 0.01
    # omega v_O1 is ~3.5 % of A_O2 but shifts the free vibration: a visible change, well below the response
    assert 0.005 < change("omega v_O1 twice") < 0.3
    # Eq. 20's sign turns the film into suction: it pulls the link onto the collar and the film breaks down
    printed = variant("+B p_g")
    assert printed.attrs["status"] == "film_breakdown" and printed.sizes["time"] < d["corrected"].sizes["time"]
    assert float(d["corrected"].film_min.min()) > 1e-4  # the corrected film never comes near breakdown


def test_calibration_root_and_jump_logic(monkeypatch):
    """Brent's method on a synthetic t1(H): a continuous branch, then a jump over the target."""
    grid = [5.0e-3, 5.08e-3, 5.2e-3]

    def smooth(config, t_stop=None, motion=None):
        return 1.0 + 1e3 * (config.film.clearance - 5e-3)  # t1 = 1.1 s at H = 5.1 mm

    monkeypatch.setattr(paper, "first_impact_time", smooth)
    cal = paper.calibrate_clearance(1.1, clearances=grid, set={"film.viscosity": 1.01e-3})
    assert cal.reached and cal.clearance == pytest.approx(5.1e-3, abs=1e-9)
    assert abs(cal.miss) <= cal.tolerance

    def jump(config, t_stop=None, motion=None):
        H = config.film.clearance
        return 1.0 + 1e3 * (H - 5e-3) if H < 5.09e-3 else math.inf  # last impact 1.09 s, then none

    monkeypatch.setattr(paper, "first_impact_time", jump)
    cal = paper.calibrate_clearance(1.1, clearances=grid, set={"film.viscosity": 1.02e-3})
    assert not cal.reached and "not reached" in cal.message
    assert cal.bracket[1] - cal.bracket[0] < 1e-9 and cal.bracket[0] == pytest.approx(5.09e-3, abs=1e-9)
    assert cal.first_impact == pytest.approx(1.09, abs=1e-6) and cal.bracket_times[1] == math.inf


def test_calibration_is_cached_on_disk(tmp_path, monkeypatch):
    calls = []

    def fake(config, t_stop=None, motion=None):
        calls.append(config.film.clearance)
        return 1.0 + 1e3 * (config.film.clearance - 5e-3)

    monkeypatch.setattr(paper, "first_impact_time", fake)
    cache = tmp_path / "cal.json"
    first = paper.calibrate_clearance(1.1, clearances=[5.0e-3, 5.2e-3], set={"film.viscosity": 1.03e-3},
                                      cache_file=cache)
    n = len(calls)
    paper._CALIBRATIONS.clear()
    again = paper.calibrate_clearance(1.1, clearances=[5.0e-3, 5.2e-3], set={"film.viscosity": 1.03e-3},
                                      cache_file=cache)
    assert len(calls) == n and again == first


def cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "lubelink", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


def test_cli_figures_low_res(tmp_path):
    r = cli("figures", "--low-res", "--only", "fig6,fig8", "-o", str(tmp_path / "figs"), "-q")
    assert r.returncode == 0, r.stderr
    for stem in ("fig6-deflection-surface", "fig8-pressure"):
        for ext in ("png", "pdf"):
            assert (tmp_path / "figs" / f"{stem}.{ext}").stat().st_size > 1000
    bad = cli("figures", "--only", "fig10", "-o", str(tmp_path))
    assert bad.returncode == 2 and "fig10" in bad.stderr and "Traceback" not in bad.stderr


def test_cli_animate_writes_a_gif(tmp_path):
    from PIL import Image

    out = tmp_path / "crank.gif"
    r = cli("animate", "--scenario", "paper", "-o", str(out), "--duration", "0.2", "--fps", "10",
            "--speed", "0.5", "--set", "output.x_points=11", "-q")
    assert r.returncode == 0, r.stderr
    with Image.open(out) as gif:
        assert gif.format == "GIF" and gif.n_frames == 5  # t = 0, 0.05, ..., 0.2 s
    again = cli("animate", "-o", str(out), "--duration", "0.2", "-q")
    assert again.returncode == 2 and "--overwrite" in again.stderr
    assert not list(tmp_path.glob(".*"))


def test_cli_figures_refuses_a_figure_file_taken_by_a_folder_before_computing(tmp_path):
    """Issue 37 item 4: ``figures -o figs`` where one figure's file name was a folder ended in a traceback after
    the simulations. It is refused at once, naming the file."""
    import time

    (tmp_path / "figs" / "fig6-deflection-surface.png").mkdir(parents=True)
    began = time.perf_counter()
    r = cli("figures", "--low-res", "--only", "fig6", "-o", str(tmp_path / "figs"), "-q")
    assert r.returncode == 2 and "fig6-deflection-surface.png is a folder" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert time.perf_counter() - began < 30 and sorted(p.name for p in (tmp_path / "figs").iterdir()) == [
        "fig6-deflection-surface.png"]


def test_cli_animate_refuses_a_huge_animation_before_simulating(tmp_path):
    """Issue 37 item 5: ``animate --fps 100000`` started 400,001 frames (28 h); it is refused at once, with its cost."""
    import time

    began = time.perf_counter()
    r = cli("animate", "-o", str(tmp_path / "a.gif"), "--fps", "100000", "-q")
    assert r.returncode == 2 and "400,000 frames, more than 2,000" in r.stderr and "h to draw" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and list(tmp_path.iterdir()) == [] and time.perf_counter() - began < 30


@pytest.mark.parametrize("name, needle", [("crank.avi", ".gif or .mp4"), ("crank.mp4", "ffmpeg")])
def test_cli_animate_rejects_what_it_cannot_write(tmp_path, name, needle):
    import shutil

    if name.endswith(".mp4") and shutil.which("ffmpeg"):
        pytest.skip("ffmpeg is installed")
    r = cli("animate", "-o", str(tmp_path / name), "--duration", "0.2", "-q")
    assert r.returncode == 2 and needle in r.stderr and "Traceback" not in r.stderr


def test_errata_figure_shows_the_corrected_curve_and_every_variant():
    """Issue 16 item 11: the corrected curve was hidden under the variants that coincide with it."""
    import xarray as xr

    from lubelink.plots import figure_errata

    t = np.linspace(0.0, 1.0, 201)
    base = 2e-3 * np.sin(2 * np.pi * 5 * t)
    runs = {"corrected": base, "tiny": base + 1e-8 * t, "large": base + 1e-4 * np.sin(40 * t),
            "large too": base + 1.01e-4 * np.sin(40 * t)}
    data = {k: xr.Dataset({"u2_mid": ("time", v)}, coords={"time": t}) for k, v in runs.items()}
    fig = figure_errata(data, "corrected")
    top, bottom = fig.axes[:2]
    lines = {ln.get_label(): ln for ln in top.get_lines()}
    ref = lines["corrected"]
    for label in ("tiny", "large", "large too"):
        # under every variant, and wider than it, so it shows where they coincide
        assert ref.get_zorder() < lines[label].get_zorder() and ref.get_linewidth() > 2 * lines[label].get_linewidth()
    assert len({str(lines[k].get_linestyle()) for k in ("tiny", "large", "large too")}) == 3
    diff = {ln.get_label(): ln for ln in bottom.get_lines() if not ln.get_label().startswith("_")}
    # the smallest difference is drawn last, on top of the larger ones
    assert diff["tiny"].get_zorder() > diff["large too"].get_zorder()
    assert diff["large"].get_zorder() > diff["large too"].get_zorder()
    assert {str(diff[k].get_linestyle()) for k in diff} == {str(lines[k].get_linestyle()) for k in diff}


def test_animation_views_are_to_scale_and_have_legends():
    """Issue 16 item 11: a legend, and no magnified curve on true-coordinate axes."""
    from lubelink.plots import animate_mechanism

    ds = lubelink.simulate("paper", set={"solver.t_end": 0.06, "solver.output_step": 0.02, "output.x_points": 11})
    fig, anim = animate_mechanism(ds)
    anim._init_draw()  # as saving does (and it marks the animation as drawn)
    anim._draw_frame(2)
    plane, link = fig.axes
    assert plane.get_legend() is not None and link.get_legend() is not None
    assert plane.get_xlabel() == "X [m]" and plane.get_ylabel() == "Y [m]"
    assert link.get_ylabel() == "deflection u2 [mm]" and link.get_xlabel().endswith("[m]")
    # the link in the plane: its end is the slider, from the geometry of the mechanism alone
    OA, L, w0 = 0.07, 1.0, 10 * math.pi
    phi = w0 * float(ds.time[2])
    rod = next(ln for ln in plane.get_lines() if ln.get_label() == "link (to scale)")
    end = np.array([rod.get_xdata()[-1], rod.get_ydata()[-1]])
    np.testing.assert_allclose(end, [OA * math.cos(phi) + math.sqrt(L**2 - (OA * math.sin(phi)) ** 2), 0.0],
                               atol=1e-12)
    mid = np.array([rod.get_xdata()[5], rod.get_ydata()[5]])
    pin = OA * np.array([math.cos(phi), math.sin(phi)])
    chord_mid = pin + 0.5 * (end - pin)
    # the true deflection: the midpoint is u2_mid (a few mm) off the chord, not 50 times that
    assert np.linalg.norm(mid - chord_mid) == pytest.approx(abs(float(ds.u2_mid[2])), rel=1e-9)
    deflection = next(ln for ln in link.get_lines() if ln.get_label() == "link deflection u2(x, t)")
    np.testing.assert_allclose(deflection.get_ydata(), ds.u2.values[2] * 1e3)
    face = next(ln for ln in link.get_lines() if ln.get_label().startswith("collar face"))
    assert face.get_ydata()[0] == pytest.approx(0.5 * 6e-3 * 1e3)  # H/2 of the paper scenario [mm]
