"""Print the accuracy tables of docs/film2d.md: the 2-D film's terms across the width over ``B / l``.

    PYTHONPATH=src python tools/figures/film2d_accuracy.py          # about half a minute

For ``B / l`` from 0.1 to 100 on the 50 mm pad of 201 points, the errors of
:func:`lubelink.film.width_pressure` (the right-hand side's film) with the default terms
(8 fitted), 6 fitted terms and 8 sine terms, against

* the parallel squeeze film in closed form (:func:`squeeze_plates`): load, centre line;
* linear wedges (film ratio 2 and 10, ``V = 1.5 m/s``) with a squeeze ``-2 sin(pi X / l)`` mm/s,
  against :func:`lubelink.film.pressure_2d` on the same pad grid, with nodes across the width
  graded towards its side edges (:func:`graded_width`);

then the largest relative errors of the fitted terms on the width functions (the table of
``lubelink.film.width_table``). The tests (tests/test_film_width.py) use the two references.
"""

from __future__ import annotations

import numpy as np

from lubelink.film import pressure_2d, width_pressure

L_PAD, MU, H0, V = 0.05, 0.1, 1e-4, 1.5
RATIOS = (0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0)


def graded_width(B, l):
    """Nodes across the width for ``pressure_2d`` [m]: ``min(l / 40, B / 120)`` apart within ``1.5 l`` of the
    side edges (the pressure falls to ambient over about ``l``), 15 % further apart a node beyond, up to ``l``
    (there the pressure is the 1-D film's); a node on the centre line, the middle one."""
    b, d = B / 2, [0.0]
    step = min(l / 40, b / 60)
    while d[-1] + step < b - 0.5 * step:
        d.append(d[-1] + step)
        if d[-1] > 1.5 * l:
            step = min(1.15 * step, l)
    half = np.append(d, b)
    return np.concatenate([-b + half, b - half[::-1][1:]])


def squeeze_plates(X, B, l, S):
    """The parallel squeeze film ``lap p = S`` [Pa/m^2] on the ``l x B`` pad, ambient on its edges, in closed form.

    The rectangle's Poisson problem (as for the torsion of a rectangular bar; Timoshenko & Goodier,
    Theory of Elasticity): ``p = -S sum_(m odd) 4 l^2 / (m pi)^3 sin(m pi X / l) (1 - cosh(m pi Z / l) /
    cosh(m pi B / (2 l)))``. Returns the load [N] and the centre line at ``X`` [m] [Pa].
    """
    m = np.arange(1, 4001, 2)[:, None]
    a = m * np.pi * B / (2 * l)
    load = -S * np.sum(8 * l ** 3 / (m * np.pi) ** 4 * (B - 2 * l / (m * np.pi) * np.tanh(a)))
    centre = -S * np.sum(4 * l ** 2 / (m * np.pi) ** 3 * np.sin(m * np.pi * X[None, :] / l)
                         * (1 - 1 / np.cosh(np.minimum(a, 700))), axis=0)
    return load, centre


def squeeze(X):
    return -2e-3 * np.sin(np.pi * X / L_PAD)


def errors(ratio, **terms):
    """Relative errors of load and centre line (to its peak): squeeze plates, wedge 2 and wedge 10 (six numbers)."""
    B = ratio * L_PAD
    xt = -1e-3
    g, P, pc = width_pressure(lambda X: H0 + 0 * X, 0.0, MU, B, L_PAD, xi_t=lambda X: xt + 0 * X, **terms)
    load, centre = squeeze_plates(g, B, L_PAD, 12 * MU * xt / H0 ** 3)
    out = [np.trapezoid(P, g) / load - 1, np.abs(pc - centre).max() / np.abs(centre).max()]
    Z = graded_width(B, L_PAD)
    for steep in (2.0, 10.0):
        def xi(X):
            return H0 * (steep - (steep - 1) * X / L_PAD)

        g, P, pc = width_pressure(xi, V, MU, B, L_PAD, xi_t=squeeze, **terms)
        p = pressure_2d(g, Z, xi(g)[:, None], V, MU, xi_t=squeeze(g)[:, None])
        line = p[:, Z.size // 2]
        out += [np.trapezoid(P, g) / np.trapezoid(np.trapezoid(p, Z, axis=1), g) - 1,
                np.abs(pc - line).max() / np.abs(line).max()]
    return out


def main():
    from lubelink.film.width_table import ERRORS

    print("| B / l | terms | squeeze: load | centre | wedge 2: load | centre | wedge 10: load | centre |")
    print("|---|---|---|---|---|---|---|---|")
    for ratio in RATIOS:
        for name, terms in (("8 fitted", {}), ("6 fitted", {"modes": 6}), ("8 sine", {"series": "sine"})):
            e = errors(ratio, **terms)
            cells = " | ".join(f"{v * 100:+.3f} %" if i % 2 == 0 else f"{v * 100:.3f} %" for i, v in enumerate(e))
            print(f"| {ratio:g} | {name} | {cells} |", flush=True)
    print()
    print("| terms | width integral g | centre line h |")
    print("|---|---|---|")
    for J, (eg, eh) in ERRORS.items():
        print(f"| {J} | {eg:.1e} | {eh:.1e} |")


if __name__ == "__main__":
    main()
