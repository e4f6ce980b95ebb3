"""The compiled code's views of the parameters (:mod:`lubelink.views`)."""

import pickle

from lubelink import views


def test_parameter_views_are_importable_by_name():
    """Numba keys its on-disk cache on the parameter types: each view class must pickle by reference."""
    for cls in (views.MechanismView, views.BeamView, views.FilmView, views.CollarView, views.ContactView,
                views.ModelOptionsView):
        assert pickle.loads(pickle.dumps(cls)) is cls
        assert getattr(views, cls.__name__) is cls
        # a cache index of an earlier version names them in lubelink.params: it must still unpickle
        assert pickle.loads(f"clubelink.params\n{cls.__name__}\n.".encode()) is cls
