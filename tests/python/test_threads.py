"""The GIL is released: Python threads segment at once, with the same labels."""
import os
import threading
import time

import numpy as np

import skelseg


def test_four_threads_at_once_give_the_labels_of_one_and_overlap(shapes):
    # Long enough (0.2 s a call on a fast machine) that the four runs overlap
    # by several of the caller's 50 ms polls.
    mask = skelseg.read_volume(shapes.nrrd("figure", 128, 1))
    expected = skelseg.segment(mask, threads=1).labels

    # No wall-time ratio is asserted: on a shared machine it measures the
    # load; the overlap of the four runs below is what a held GIL would break.
    barrier = threading.Barrier(4)
    labels = [None] * 4
    # While the engine runs, progress is called on the calling thread: the
    # first and last calls bracket the time each engine run was under way.
    running = [[None, None] for _ in range(4)]

    def work(i):
        def progress(stage, fraction):
            now = time.perf_counter()
            if running[i][0] is None:
                running[i][0] = now
            running[i][1] = now

        barrier.wait()
        labels[i] = skelseg.segment(mask, threads=1, progress=progress).labels

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()

    for result in labels:
        np.testing.assert_array_equal(result, expected)
    # Every run was under way while every other one was: no call waited for
    # another to finish (a held GIL would serialise them).
    latest_start = max(begin for begin, _ in running)
    earliest_end = min(end for _, end in running)
    assert latest_start < earliest_end, running


def test_threads_do_not_change_the_labels(figure_mask):
    one = skelseg.segment(figure_mask, threads=1)
    two = skelseg.segment(figure_mask, threads=2)
    np.testing.assert_array_equal(one.labels, two.labels)
    assert one.report["parameters"]["threads"] == 1
    assert two.report["parameters"]["threads"] == 2


def test_more_threads_than_cores_print_nothing(capfd, figure_mask):
    # oneTBB printed "TBB Warning: The number of workers is currently limited
    # to ..." on stderr; the module prints nothing.
    threads = min(1024, 2 * (os.cpu_count() or 1) + 1)
    result = skelseg.segment(figure_mask, threads=threads)
    # The call runs on the cores it may use, not on the threads asked for.
    assert 1 <= result.report["parameters"]["threads"] <= len(os.sched_getaffinity(0))
    assert capfd.readouterr() == ("", "")


# A daemon thread inside the engine when the program ends: the thread that
# waits for the engine must not take the GIL during the shutdown (CPython
# ends it with pthread_exit, whose unwinding destroyed the running worker's
# std::thread: "terminate called without an active exception", SIGABRT).
DAEMON_AT_EXIT = """
import sys, threading
import skelseg
mask = skelseg.read_volume(sys.argv[1])
in_engine = threading.Event()

def work():
    while True:  # always inside a call when the main thread ends
        skelseg.segment(mask, threads=1, progress=lambda stage, fraction: in_engine.set())

threading.Thread(target=work, daemon=True).start()
in_engine.wait()
if sys.argv[2] == "exit":
    sys.exit(0)
"""


def test_the_program_ends_cleanly_while_a_daemon_thread_segments(shapes):
    import subprocess
    import sys

    path = shapes.nrrd("figure", 128, 1)
    # The abort was a race (about 3 in 100 exits on a loaded machine): a few
    # more exits than one of each.
    for how in ("end", "exit") * 4:
        done = subprocess.run([sys.executable, "-c", DAEMON_AT_EXIT, str(path), how],
                              capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, f"{how}: exit {done.returncode}: {done.stderr[-500:]}"
        assert "terminate" not in done.stderr


# An exit handler registered before skelseg is imported runs after skelseg's
# own (atexit calls them last first): by then the daemon thread's engine call
# must have been stopped and must not return, so nothing the interpreter
# tears down later is still in use by a worker (the static destructors that
# exit() runs next; a worker still unwinding through oneTBB's aborted with
# "pure virtual method called"). The daemon thread keeps finishing calls
# until the program ends, then none.
STOPPED_AT_EXIT = """
import atexit, sys, threading, time
finished = []

def after_skelseg_stopped_its_calls():
    before = len(finished)
    time.sleep(1.0)  # about five of the daemon thread's calls
    print(before, len(finished), flush=True)

atexit.register(after_skelseg_stopped_its_calls)
import skelseg
mask = skelseg.read_volume(sys.argv[1])
in_engine = threading.Event()

def work():
    while True:
        skelseg.segment(mask, threads=1, progress=lambda stage, fraction: in_engine.set())
        finished.append(1)

threading.Thread(target=work, daemon=True).start()
in_engine.wait()
while len(finished) < 2:
    time.sleep(0.01)
"""


def test_the_programs_exit_stops_the_calls_of_daemon_threads_before_its_teardown(shapes):
    import subprocess
    import sys

    path = shapes.nrrd("figure", 128, 1)
    done = subprocess.run([sys.executable, "-c", STOPPED_AT_EXIT, str(path)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-500:]
    before, after = (int(n) for n in done.stdout.split())
    assert before >= 2
    assert after == before, "a call of the daemon thread returned while the program ended"


# A child of fork() has only the thread that forked: a call another thread of
# the parent had under way is not the child's to wait for when it ends. The
# child runs its Python exit handlers (skelseg's among them) and leaves with
# os._exit, as multiprocessing's children do: a forked child that ends
# through exit() hangs in liblog4cplus's exit handler, OpenVDB's logging
# library, whatever skelseg does (docs/python.md, "Threads").
FORK_DURING_A_CALL = """
import os, sys, threading, time
import skelseg
mask = skelseg.read_volume(sys.argv[1])
in_callback = threading.Event()
go_on = threading.Event()

def progress(stage, fraction):
    in_callback.set()
    go_on.wait()  # the call stays under way while the main thread forks

worker = threading.Thread(target=lambda: skelseg.segment(mask, threads=1, progress=progress))
worker.start()
in_callback.wait()
child = os.fork()
if child == 0:
    import atexit
    atexit._run_exitfuncs()
    os._exit(0)
deadline = time.monotonic() + 30
while True:
    ended, status = os.waitpid(child, os.WNOHANG)
    if ended:
        break
    if time.monotonic() > deadline:
        os.kill(child, 9)
        os.waitpid(child, 0)
        status = None
        break
    time.sleep(0.05)
go_on.set()
worker.join()
print("hung" if status is None else os.waitstatus_to_exitcode(status), flush=True)
"""


def test_a_forked_child_ends_without_waiting_for_its_parents_calls(shapes):
    import subprocess
    import sys

    path = shapes.nrrd("figure", 128, 1)
    done = subprocess.run([sys.executable, "-c", FORK_DURING_A_CALL, str(path)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-500:]
    assert done.stdout.split() == ["0"], done.stdout
