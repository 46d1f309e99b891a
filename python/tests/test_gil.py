"""The GIL is released during solves and renders: other Python threads keep running."""
import threading
import time

import numpy as np

import al_refine as al


def progress_during(call):
    """Runs call() in a thread; returns (its duration, how much of it the main thread spent running)."""
    span = {}

    def worker():
        span["start"] = time.monotonic()
        call()
        span["end"] = time.monotonic()

    thread = threading.Thread(target=worker)
    ticks = []
    thread.start()
    while thread.is_alive():
        ticks.append(time.monotonic())
    thread.join()
    start, end = span["start"], span["end"]
    inside = [t for t in ticks if start < t < end]
    covered = (max(inside) - min(inside)) if len(inside) > 1 else 0.0
    return end - start, covered, len(inside)


def test_refine_releases_the_gil(synth):
    scene, removed = synth.scene, synth.removed["fgs"]
    # cp with tight tolerances: a solve long enough to measure, on the module's usual input.
    call = lambda: [al.refine(scene, removed, solver="cp", k=14, cp_dif_tol=1e-6, cp_it_max=30) for _ in range(3)]
    duration, covered, ticks = progress_during(call)
    assert duration > 0.2, "the solve must take long enough for the test to mean something"
    # Holding the GIL, the main thread could run only before the call enters C++ (a few ms).
    assert covered > 0.5 * duration and ticks > 100, (duration, covered, ticks)


def test_render_releases_the_gil(synth):
    call = lambda: al.render(synth.scene, synth.cameras * 8)
    duration, covered, ticks = progress_during(call)
    assert duration > 0.1
    assert covered > 0.5 * duration and ticks > 100, (duration, covered, ticks)
