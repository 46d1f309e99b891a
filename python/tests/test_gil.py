"""The GIL is released during solves and renders: other Python threads keep running."""
import threading
import time

import al_refine as al


def longest_stall(call):
    """Runs call() in a thread while this one counts; returns (call's duration, longest time this
    thread made no progress during it). Holding the GIL in C++, the stall is the whole C++ part."""
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
    inside = [start] + [t for t in ticks if start < t < end] + [end]
    return end - start, max(b - a for a, b in zip(inside, inside[1:]))


def test_refine_releases_the_gil(synth):
    # One cp solve with tight tolerances on a dense graph: long enough to tell a stall from
    # the scheduler's time slices on a loaded machine.
    duration, stall = longest_stall(lambda: al.refine(synth.scene, synth.removed["fgs"], solver="cp", k=30,
                                                      cp_dif_tol=1e-7, cp_it_max=100))
    assert duration > 0.3, "the solve must take long enough for the test to mean something"
    assert stall < 0.5 * duration, (duration, stall)


def test_render_releases_the_gil(synth):
    duration, stall = longest_stall(lambda: al.render(synth.scene, synth.cameras * 16))
    assert duration > 0.3
    assert stall < 0.5 * duration, (duration, stall)
