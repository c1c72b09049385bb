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


# A cancellation must land well inside the run it cuts short, on a slow
# shared machine and on a fast one alike: the slow case grows until a whole
# run takes this long, and requests come at a fraction of it.
SLOW_RUN_SECONDS = 2.0


@pytest.fixture(scope="module")
def slow_case(shapes):
    """A figure that takes seconds to segment, and how long a whole run takes."""
    for size in (224, 288, 352, 416):
        mask = skelseg.read_volume(shapes.nrrd("figure", size, 1))
        start = time.perf_counter()
        skelseg.segment(mask)
        whole_run = time.perf_counter() - start
        if whole_run >= SLOW_RUN_SECONDS:
            break
    return mask, whole_run


class Stop(Exception):
    pass


def test_a_progress_callback_that_raises_cancels_the_run(slow_case):
    mask, whole_run = slow_case
    calls = []
    raised_at = []
    start = time.perf_counter()

    def progress(stage, fraction):
        calls.append((stage, fraction))
        if time.perf_counter() - start > 0.2 * whole_run:  # well inside the run
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


def test_progress_reports_every_stage_in_order_and_ends_with_done(figure_mask):
    calls = []
    result = skelseg.segment(figure_mask,
                             progress=lambda stage, fraction: calls.append((stage, fraction)))
    assert calls[-1] == ("done", 1.0)
    assert all(f is None or 0.0 <= f <= 1.0 for _, f in calls)
    # Every stage the report times was announced, however short the run, and
    # in the order the stages ran (a stage may be reported more than once).
    announced = [stage for stage, _ in calls[:-1]]
    first_seen = list(dict.fromkeys(announced))
    timed = [entry["name"] for entry in result.report["stages"]]
    for stage in set(timed) - {"total"}:
        assert stage in first_seen, (stage, first_seen)
    assert len(first_seen) >= 5, first_seen


def test_a_run_shorter_than_one_poll_still_reports_its_stages(shapes):
    tiny = skelseg.read_volume(shapes.nrrd("figure", 48, 1))
    calls = []
    skelseg.segment(tiny, progress=lambda stage, fraction: calls.append((stage, fraction)))
    assert calls[-1] == ("done", 1.0)
    assert len({stage for stage, _ in calls[:-1]}) >= 5, calls


def test_keyboard_interrupt_from_a_timer_cancels_within_a_second(slow_case, figure_mask):
    slow_mask, whole_run = slow_case
    fired = []

    def interrupt():
        fired.append(time.perf_counter())
        _thread.interrupt_main()  # as Ctrl-C: SIGINT's handler runs in the main thread

    timer = threading.Timer(0.25 * whole_run, interrupt)
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
