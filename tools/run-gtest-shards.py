#!/usr/bin/python3
"""Runs GoogleTest executables in shards, a few processes at a time.

    tools/run-gtest-shards.py [--jobs N] [--shards K] [--filter PATTERN]
                              [--exclude NAME]... [--log-dir DIR] BINARY...

Each executable is run as K processes (GoogleTest's own sharding:
GTEST_TOTAL_SHARDS / GTEST_SHARD_INDEX), N of them at once, instead of one
process per test as ctest does. Under AddressSanitizer a test process takes
0.2 to 0.4 s to start (the sanitizer's shadow memory and the executables'
size), which over some 900 tests was a third of the sanitizer suite's time
(docs/robustness.md, "One process per shard").

Every shard's whole output goes to DIR/BINARY.SHARD.log. The script prints a
line per shard, then each failed shard's failures and the end of its log,
and exits 1 when a shard fails, crashes, times out, or when the shards of an
executable together passed or skipped fewer tests than `--gtest_list_tests` names (a shard
that stopped early is a failure, not a shorter run).
"""
import argparse
import concurrent.futures
import os
import pathlib
import re
import subprocess
import sys
import time

PASSED = re.compile(r"^\[  PASSED  \] (\d+) tests?\.", re.MULTILINE)
SKIPPED = re.compile(r"^\[  SKIPPED \] (\d+) tests?, listed below", re.MULTILINE)
# A failed test's own line (Suite.Name), not the summary "[  FAILED  ] 2 tests, listed below:".
FAILED = re.compile(r"^\[  FAILED  \] ([^ ,\n]+\.[^ ,\n]+)", re.MULTILINE)


def gtest_filter(pattern, excluded):
    return pattern + ("-" + ":".join(excluded) if excluded else "")


def listed_tests(binary, filter_text):
    """The tests the filter selects, as Suite.Name."""
    out = subprocess.run([binary, "--gtest_list_tests", "--gtest_filter=" + filter_text],
                         capture_output=True, text=True, check=True).stdout
    tests, suite = [], None
    for line in out.splitlines():
        if not line.strip() or line.startswith("Running main()"):
            continue
        if not line.startswith(" "):
            suite = line.split()[0]
        else:
            tests.append(suite + line.split()[0])
    return tests


def run_shard(binary, index, shards, filter_text, log, timeout):
    env = dict(os.environ, GTEST_TOTAL_SHARDS=str(shards), GTEST_SHARD_INDEX=str(index))
    start = time.monotonic()
    with open(log, "w") as out:
        try:
            code = subprocess.run([binary, "--gtest_filter=" + filter_text], env=env,
                                  stdout=out, stderr=subprocess.STDOUT, timeout=timeout).returncode
        except subprocess.TimeoutExpired:
            code = None
    return code, time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("binaries", nargs="+", metavar="BINARY", help="GoogleTest executables")
    parser.add_argument("--jobs", type=int, default=1, help="shards run at once (default 1)")
    parser.add_argument("--shards", type=int, default=6,
                        help="processes per executable (default 6)")
    parser.add_argument("--filter", default="*",
                        help="positive GoogleTest filter, e.g. 'Nrrd*:*Robust*' (default '*')")
    parser.add_argument("--exclude", action="append", default=[], metavar="NAME",
                        help="a test (Suite.Name, wildcards allowed) not to run; repeatable")
    parser.add_argument("--log-dir", default="gtest-shard-logs",
                        help="where each shard's output goes (default ./gtest-shard-logs)")
    parser.add_argument("--timeout", type=float, default=1800, help="seconds per shard (default 1800)")
    args = parser.parse_args()
    if args.jobs < 1 or args.shards < 1:
        parser.error("--jobs and --shards must be at least 1")
    if "-" in args.filter:
        parser.error("--filter takes positive patterns only; use --exclude for the others")
    for binary in args.binaries:
        if not os.path.isfile(binary) or not os.access(binary, os.X_OK):
            parser.error(f"{binary}: not an executable")
    # A bare name would be looked up on PATH.
    args.binaries = [os.path.abspath(b) for b in args.binaries]

    filter_text = gtest_filter(args.filter, args.exclude)
    expected = {b: len(listed_tests(b, filter_text)) for b in args.binaries}
    logs = pathlib.Path(args.log_dir)
    logs.mkdir(parents=True, exist_ok=True)
    # The executable with the most tests first: its shards are the longest,
    # and the short ones fill the cores at the end.
    order = sorted(args.binaries, key=lambda b: -expected[b])
    work = [(b, i) for b in order for i in range(args.shards) if expected[b] > 0]

    failed, passed = [], {b: 0 for b in args.binaries}
    start = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = {}
        for binary, index in work:
            log = logs / f"{pathlib.Path(binary).name}.{index}.log"
            futures[pool.submit(run_shard, binary, index, args.shards, filter_text, log,
                                args.timeout)] = (binary, index, log)
        for future in concurrent.futures.as_completed(futures):
            binary, index, log = futures[future]
            code, seconds = future.result()
            text = log.read_text(errors="replace")
            count = sum(int(m) for m in PASSED.findall(text))
            skipped = sum(int(m) for m in SKIPPED.findall(text))
            passed[binary] += count + skipped
            name = pathlib.Path(binary).name
            state = ("timed out" if code is None else "passed" if code == 0 else
                     f"failed (exit {code})")
            print(f"{name} shard {index + 1}/{args.shards}: {count} tests passed"
                  + (f", {skipped} skipped" if skipped else "") + f", {state}, {seconds:.1f} s",
                  flush=True)
            if code != 0:
                failed.append((name, index, log, text))

    for name, index, log, text in failed:
        print(f"\n== {name} shard {index + 1}: {log}")
        names = sorted(set(FAILED.findall(text)))
        if names:
            print("failed tests: " + " ".join(names))
        print("\n".join(text.splitlines()[-60:]))
    short = [b for b in args.binaries if not failed and passed[b] != expected[b]]
    for binary in short:
        print(f"run-gtest-shards: {binary}: the shards passed or skipped {passed[binary]} of "
              f"{expected[binary]} tests", file=sys.stderr)
    total = sum(expected.values())
    print(f"{total} tests in {len(work)} shards, {time.monotonic() - start:.0f} s: "
          + ("failed" if failed or short else "all passed"))
    return 1 if failed or short else 0


if __name__ == "__main__":
    sys.exit(main())
