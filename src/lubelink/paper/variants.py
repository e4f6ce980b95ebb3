"""The equations of motion as printed in the paper, to show what the errata change.

:func:`simulate_variant` runs a configuration with lubelink's corrected equations or with one of
the printed variants of :data:`VARIANTS`, which are values of the model option
``model.equations``: the right-hand side itself carries them (:func:`lubelink.link.model.rhs_given`),
so they run on both backends.
"""

from __future__ import annotations

from ..errors import suggest

__all__ = ["VARIANTS", "simulate_variant"]

#: Variants of the equations of motion (:func:`simulate_variant`).
VARIANTS = {
    "corrected": "corrected equations (lubelink)",
    "printed-omega2": "Eq. 18 as printed: +omega^2 q_n (stiffening)",
    "double-count": "Eq. 18 as printed: A_O2 + omega v_O1 (omega v_O1 counted twice)",
    "printed": "Eq. 18 as printed: both of the above",
    "printed-film-sign": "Eq. 20 as printed: film force +B p_g (gauge)",
}


def simulate_variant(source="paper", set=None, variant="corrected"):
    """Simulate with the corrected equations or one of the paper's printed variants.

    The variants are the model option ``model.equations`` (see
    :class:`lubelink.params.ModelOptions`); this adds the check that a printed variant runs
    without a contact law and records the variant in the attributes.

    Parameters
    ----------
    source, set
        As for :func:`lubelink.simulate`.
    variant : str
        A key of :data:`VARIANTS`: ``"corrected"`` (lubelink's equations),
        ``"printed-omega2"`` (``+omega^2`` of Eq. 18), ``"double-count"``
        (``A_O2 + omega v_O1`` of Eq. 18 with Section 6's true ``a_O2``),
        ``"printed"`` (both) or ``"printed-film-sign"`` (Eq. 20's ``+B p_g``).

    Returns
    -------
    xarray.Dataset
        As :func:`lubelink.simulate`, with ``attrs["variant"]``.

    Raises
    ------
    ValueError
        For an unknown variant, or a variant other than ``"corrected"`` with
        a contact law (the variants are for impact-free runs).
    """
    from ..config import resolve
    from ..simulate import run, to_dataset

    if variant not in VARIANTS:
        raise ValueError(f"variant = {variant!r}: must be one of {', '.join(VARIANTS)}"
                         + suggest(variant, VARIANTS))
    config = resolve(source, {**dict(set or {}), "model.equations": variant})
    if variant != "corrected" and config.contact.law != "none":
        raise ValueError(f"variant {variant!r} is available for contact.law = 'none' only")
    ds = to_dataset(run(config))
    ds.attrs["variant"] = variant
    return ds
