"""The arrays own the C++ buffers (no copy into Python memory), the GIL is released while
rendering, and two Python threads can render at once."""
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np

import mvr


def test_arrays_own_cpp_buffers():
    r = mvr.render(views=3, size=(40, 30))
    for a in (r.color, r.depth):
        assert type(a.base).__name__ == "PyCapsule"  # the C++ owner
        assert not a.flags.owndata and a.flags.c_contiguous
    one = mvr.render(views=1, size=(40, 30))
    assert type(one.color.base).__name__ == "PyCapsule"
    assert type(mvr.compose("sbs", r.color[:2]).base).__name__ == "PyCapsule"
    # The views outlive the result object and each other.
    color = r.color
    del r
    assert color.sum() > 0


def test_views_are_rendered_in_place():
    # Every method of every backend here renders the N views straight into the block the
    # arrays own: nothing is copied in (copied_views counts images that had to be).
    backends = [b for b in mvr.info()["backends"] if b["available"]]
    assert backends
    for b in backends:
        for m in b["methods"]:
            if not m["supported"]:
                continue
            try:
                views = 5
                r = mvr.render(views=views, size=(48, 36), backend=b["name"], method=m["name"])
            except (ValueError, RuntimeError):  # stereo-only methods (gs-mrt, gs-depthmap)
                views = 2
                r = mvr.render(views=views, size=(48, 36), backend=b["name"], method=m["name"])
            assert r.copied_views == 0, (b["name"], m["name"], r.copied_views)
            assert r.color.shape == (views, 36, 48, 4)
            # Each view is its own picture (not one view repeated, not a stale block).
            assert not np.array_equal(r.color[0], r.color[-1]), (b["name"], m["name"])


def test_peak_memory_not_doubled():
    # In a fresh interpreter: the rise of the peak RSS over a render of 8 views of 1024x768 stays
    # well under twice what the arrays hold, and numpy allocates none of it (tracemalloc).
    code = textwrap.dedent("""
        import resource, tracemalloc
        import mvr
        mvr.render(views=2, size=(64, 48))
        base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
        tracemalloc.start()
        r = mvr.render(views=8, size=(1024, 768), backend="soft")
        _, traced = tracemalloc.get_traced_memory()
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
        print(peak - base, r.color.nbytes + r.depth.nbytes, traced)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**__import__("os").environ})
    rise, held, traced = map(int, out.stdout.split())
    assert held == 8 * 1024 * 768 * (4 + 4)
    # The backend renders into the arrays' memory: the peak rises by what they hold, plus\n    # the renderer's own working memory (bins, per-vertex arrays), not by a second copy.\n    assert rise < 1.3 * held, (rise, held)
    assert traced < held / 100, traced


def test_gil_released_while_rendering():
    done = threading.Event()
    ticks = 0

    def work():
        mvr.render(views=8, size=(1024, 768))
        done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.0005)
    t.join()
    assert ticks > 20, ticks


def test_two_threads_render_at_once():
    kwargs = [dict(views=4, size=(160, 120)), dict(view_grid=(2, 2), size=(120, 90), shading="pixel")]
    expected = [mvr.render(**k).color for k in kwargs]
    backends = ["soft"]
    if any(b["name"] == "gl" and b["available"] for b in mvr.info()["backends"]):
        backends.append("gl")
    for backend in backends:
        results = [[None] * 3 for _ in kwargs]
        errors = []
        barrier = threading.Barrier(len(kwargs))

        def work(i):
            try:
                barrier.wait()
                for round_ in range(3):
                    results[i][round_] = mvr.render(backend=backend, method="multipass",
                                                    **kwargs[i]).color
            except Exception as e:  # pragma: no cover - reported below
                errors.append(e)

        threads = [threading.Thread(target=work, args=(i,)) for i in range(len(kwargs))]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert not errors, errors
        for i, k in enumerate(kwargs):
            for got in results[i]:
                if backend == "soft":
                    np.testing.assert_array_equal(got, expected[i])
                else:
                    assert got.shape == expected[i].shape
                    np.testing.assert_array_equal(got, results[i][0])
