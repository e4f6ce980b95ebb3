"""The compiled code's views of the parameters (:mod:`lubelink.views`)."""

import pickle

import pytest

from lubelink import views


def test_parameter_views_are_importable_by_name():
    """Numba keys its on-disk cache on the parameter types: each view class must pickle by reference."""
    for cls in (views.MechanismView, views.BeamView, views.FilmView, views.CollarView, views.ContactView,
                views.ModelOptionsView):
        assert pickle.loads(pickle.dumps(cls)) is cls
        assert getattr(views, cls.__name__) is cls


def test_a_cache_index_of_an_earlier_version_is_stale_not_an_error(tmp_path):
    """Version 0.1's indexes name the views in ``lubelink.params``, which no longer has them: Numba
    unpickles an index before it compares the stamp, so ``lubelink._jit`` reads such an index of
    lubelink's as empty (stale) instead of raising; another package's index still raises."""
    numba = pytest.importorskip("numba")
    from numba.core import caching

    from lubelink import _jit

    _jit._install_locators()
    stale = b"(clubelink.params\nFilmView\nNt."  # (stamp, overloads) naming a view by its 0.1 place
    for folder, foreign in (("lubelink_cache", False), ("other_cache", True)):
        path = tmp_path / folder
        path.mkdir()
        index = caching.IndexDataCacheFile(str(path), "model.rhs-1.py311", b"stamp")
        with open(index._index_path, "wb") as f:
            pickle.dump(numba.__version__, f)
            f.write(stale)
        if foreign:
            with pytest.raises(AttributeError):
                index._load_index()
        else:
            assert index._load_index() == {}
