"""backend="auto": the backend that picks the fastest BACKEND:METHOD (mvr/backends.h
kAutoBackend) — its pick is one of the candidates, its images are that backend:method's, the
note names the pick and the measured times, and a method other than "auto" is a ValueError."""
import numpy as np
import pytest

import mvr


def test_auto_renders_the_picked_backend_methods_images():
    r = mvr.render(backend="auto", size=(64, 48))
    assert r.backend == "auto"
    backend, _, method = r.method.partition(":")
    assert backend in {b["name"] for b in mvr.info()["backends"]} and method and method != "auto"
    assert r.note.startswith(f"auto picked {r.method}: "), r.note
    assert "soft:unified " in r.note and " ms" in r.note, r.note
    assert r.copied_views == 0  # rendered into the arrays it returns, as every backend does
    ref = mvr.render(backend=backend, method=method, size=(64, 48))
    np.testing.assert_array_equal(r.color, ref.color)
    np.testing.assert_array_equal(r.depth, ref.depth)


def test_auto_has_one_method():
    with pytest.raises(ValueError, match="backend auto has one method, auto"):
        mvr.render(backend="auto", method="multipass", size=(16, 12))
    assert mvr.render(backend="auto", method="auto", size=(16, 12)).note.startswith("auto picked")


def test_info_lists_auto_among_the_backend_choices():
    info = mvr.info()
    names = [b["name"] for b in info["backends"]]
    assert info["backend_choices"] == names + ["auto"]
