"""Cancellation: a raising progress callback and Ctrl-C stop the engine
within a second and leave the interpreter usable."""
import _thread
import threading
import time

import numpy as np
import pytest

import skelseg

# Generous bound: measured from the request to the exception in the caller,
# on a machine that may be busy; the engine polls every few milliseconds.
STOP_SECONDS = 2.0


@pytest.fixture(scope="module")
def slow_case(shapes):
    """A figure that takes seconds to segment, and how long a whole run takes."""
    mask = skelseg.read_volume(shapes.nrrd("figure", 224, 1))
    start = time.perf_counter()
    skelseg.segment(mask)
    return mask, time.perf_counter() - start


class Stop(Exception):
    pass


def test_a_progress_callback_that_raises_cancels_the_run(slow_case):
    mask, whole_run = slow_case
    calls = []
    raised_at = []
    start = time.perf_counter()

    def progress(stage, fraction):
        calls.append((stage, fraction))
        if time.perf_counter() - start > 0.3:  # well inside the run
            raised_at.append(time.perf_counter())
            raise Stop(f"stopped in {stage}")

    with pytest.raises(Stop, match="stopped in"):
        skelseg.segment(mask, progress=progress)
    end = time.perf_counter()
    assert end - raised_at[0] < STOP_SECONDS, end - raised_at[0]
    assert end - start < 0.8 * whole_run, (end - start, whole_run)  # cut short
    assert len(raised_at) == 1  # not called again once it raised
    assert all(isinstance(stage, str) for stage, _ in calls)
    assert all(f is None or 0.0 <= f <= 1.0 for _, f in calls)


def test_progress_reports_stages_and_ends_with_done(figure_mask):
    calls = []
    skelseg.segment(figure_mask, progress=lambda stage, fraction: calls.append((stage, fraction)))
    assert calls[-1] == ("done", 1.0)
    assert len({stage for stage, _ in calls}) >= 2


def test_keyboard_interrupt_from_a_timer_cancels_within_a_second(slow_case, figure_mask):
    slow_mask, whole_run = slow_case
    fired = []

    def interrupt():
        fired.append(time.perf_counter())
        _thread.interrupt_main()  # as Ctrl-C: SIGINT's handler runs in the main thread

    timer = threading.Timer(0.5, interrupt)
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            skelseg.segment(slow_mask)
    finally:
        timer.cancel()
    caught = time.perf_counter()
    assert fired, "the run ended before the timer fired"
    assert caught - fired[0] < STOP_SECONDS, caught - fired[0]
    assert caught - start < 0.8 * whole_run, (caught - start, whole_run)  # cut short
    # The interpreter and the engine still work.
    labels = skelseg.segment(figure_mask).labels
    assert labels.max() >= 2


def test_a_cancelled_call_does_not_disturb_one_on_another_thread(slow_case, figure_mask):
    slow_mask, _ = slow_case
    expected = skelseg.segment(figure_mask).labels
    result = {}
    worker = threading.Thread(
        target=lambda: result.setdefault("labels", skelseg.segment(figure_mask).labels))

    def progress(stage, fraction):
        raise Stop()

    worker.start()
    with pytest.raises(Stop):
        skelseg.segment(slow_mask, progress=progress)
    worker.join()
    np.testing.assert_array_equal(result["labels"], expected)
