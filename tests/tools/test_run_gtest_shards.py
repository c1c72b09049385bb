"""tools/run-gtest-shards.py: shards cover every selected test once, and a
failing, crashing or short shard fails the run.

The executable is a stand-in written here that speaks GoogleTest's protocol
(--gtest_list_tests, --gtest_filter with one exclusion list, the sharding
variables, the summary lines); it records every test it runs in a file, and
FAKE_GTEST_MODE makes it fail a test, crash, or report fewer tests than it
lists.

Run with: /usr/bin/python3 -m pytest tests/tools/test_run_gtest_shards.py
"""
import pathlib
import subprocess
import textwrap

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
RUNNER = REPO / "tools" / "run-gtest-shards.py"

FAKE = textwrap.dedent('''\
    #!/usr/bin/python3
    import fnmatch, os, sys
    TESTS = ["Alpha.One", "Alpha.Two", "Beta.Three", "Beta.Four", "Gamma.Five", "Gamma.Six",
             "Gamma.Seven"]
    flt = next((a.split("=", 1)[1] for a in sys.argv if a.startswith("--gtest_filter=")), "*")
    positive, _, negative = flt.partition("-")
    def selected(name):
        return (any(fnmatch.fnmatchcase(name, p) for p in positive.split(":"))
                and not any(fnmatch.fnmatchcase(name, p) for p in negative.split(":") if p))
    tests = [t for t in TESTS if selected(t)]
    if "--gtest_list_tests" in sys.argv:
        suite = None
        for t in tests:
            s, n = t.split(".")
            if s != suite:
                print(s + ".")
                suite = s
            print("  " + n)
        sys.exit(0)
    total = int(os.environ.get("GTEST_TOTAL_SHARDS", "1"))
    index = int(os.environ.get("GTEST_SHARD_INDEX", "0"))
    mine = [t for i, t in enumerate(tests) if i % total == index]
    mode = os.environ.get("FAKE_GTEST_MODE", "ok")
    with open(os.environ["FAKE_GTEST_RECORD"], "a") as record:
        for t in mine:
            record.write(t + "\\n")
    if mode == "crash" and index == 1:
        os.abort()
    failed = [t for t in mine if mode == "fail:" + t]
    passed = len(mine) - len(failed) - (1 if mode == "short" and index == 0 and mine else 0)
    print("[  PASSED  ] %d tests." % passed)
    if failed:
        print("[  FAILED  ] %d test, listed below:" % len(failed))
    for t in failed:
        print("[  FAILED  ] %s" % t)
    sys.exit(1 if failed else 0)
    ''')


def make_fake(tmp_path):
    fake = tmp_path / "test_fake"
    fake.write_text(FAKE)
    fake.chmod(0o755)
    return fake


def run(tmp_path, *arguments, mode="ok", cwd=None):
    record = tmp_path / "ran.txt"
    record.write_text("")
    env = {"PATH": "/usr/bin:/bin", "FAKE_GTEST_MODE": mode, "FAKE_GTEST_RECORD": str(record)}
    result = subprocess.run(["/usr/bin/python3", str(RUNNER), "--log-dir", str(tmp_path / "logs"),
                             *arguments], capture_output=True, text=True, env=env, cwd=cwd,
                            timeout=60)
    return result, record.read_text().split()


def test_every_selected_test_runs_exactly_once(tmp_path):
    fake = make_fake(tmp_path)
    result, ran = run(tmp_path, "--jobs", "2", "--shards", "3", "--exclude", "Beta.*",
                      "--exclude", "Gamma.Six", str(fake))
    assert result.returncode == 0, result.stdout + result.stderr
    assert sorted(ran) == sorted(["Alpha.One", "Alpha.Two", "Gamma.Five", "Gamma.Seven"])
    assert "4 tests in 3 shards" in result.stdout
    assert len(list((tmp_path / "logs").glob("test_fake.*.log"))) == 3


def test_a_positive_filter_selects(tmp_path):
    fake = make_fake(tmp_path)
    result, ran = run(tmp_path, "--shards", "4", "--filter", "Gamma.*:Alpha.One", str(fake))
    assert result.returncode == 0, result.stdout + result.stderr
    assert sorted(ran) == sorted(["Alpha.One", "Gamma.Five", "Gamma.Six", "Gamma.Seven"])


@pytest.mark.parametrize("mode, shards, stream, says", [
    ("fail:Beta.Four", 2, "stdout", "failed tests: Beta.Four\n"),
    ("crash", 3, "stdout", "shard 2/3: 0 tests passed, failed (exit -6)"),
    ("short", 2, "stderr", "passed or skipped 6 of 7 tests"),
])
def test_a_failing_crashing_or_short_shard_fails_the_run(tmp_path, mode, shards, stream, says):
    fake = make_fake(tmp_path)
    result, _ = run(tmp_path, "--shards", str(shards), str(fake), mode=mode)
    assert result.returncode == 1
    assert says in getattr(result, stream), result.stdout + result.stderr


def test_a_relative_path_is_the_file_not_a_command_on_path(tmp_path):
    make_fake(tmp_path)
    result, ran = run(tmp_path, "test_fake", cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert len(ran) == 7


def test_a_missing_executable_is_a_one_line_error(tmp_path):
    result, ran = run(tmp_path, str(tmp_path / "no_such_test"))
    assert result.returncode == 2
    assert "no_such_test: not an executable" in result.stderr.splitlines()[-1]


def test_a_negative_filter_is_refused(tmp_path):
    fake = make_fake(tmp_path)
    result, ran = run(tmp_path, "--filter", "Alpha.*-Alpha.One", str(fake))
    assert result.returncode == 2
    assert ran == []
    assert "--exclude" in result.stderr.splitlines()[-1]
