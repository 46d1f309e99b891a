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


def long_enough(make_call, limit=6):
    """Grows the work (make_call(1), make_call(2), make_call(4), ...) until one call lasts over
    0.3 s: long enough to tell a stall from the scheduler's time slices on a loaded machine, on
    machines of any speed. Returns (duration, stall) of that call."""
    for doubling in range(limit):
        duration, stall = longest_stall(make_call(2 ** doubling))
        if duration > 0.3:
            return duration, stall
    raise AssertionError(f"the work never took 0.3 s (last call {duration:.3f} s)")


def test_refine_releases_the_gil(synth):
    # cp with tight tolerances on a dense graph; bigger scenes of the same room when that is quick.
    def make_call(factor):
        scene = synth if factor == 1 else al.synth("room", 20000 * factor, seed=3, views=1, width=16, height=12)
        return lambda: al.refine(scene.scene, scene.removed["fgs"], solver="cp", k=30, cp_dif_tol=1e-7,
                                 cp_it_max=100)
    duration, stall = long_enough(make_call)
    assert stall < 0.5 * duration, (duration, stall)


def test_render_releases_the_gil(synth):
    duration, stall = long_enough(lambda factor: lambda: al.render(synth.scene, synth.cameras * 16 * factor))
    assert stall < 0.5 * duration, (duration, stall)
