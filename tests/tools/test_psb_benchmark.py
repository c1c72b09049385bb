"""bench/psb_benchmark.py: a model whose scoring fails is recorded, not a crash.

The benchmark runs a stand-in for skelseg whose `score` command fails, so the
record of the failure (written to the model's cache as JSON) is checked."""
import json
import pathlib
import stat
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))
import psb_benchmark  # noqa: E402


def test_a_failing_score_gives_an_error_record_that_is_json(tmp_path):
    fake = tmp_path / "skelseg"
    fake.write_text("#!/bin/sh\necho 'score: the candidate has 3 labels for 4 faces' >&2\nexit 2\n")
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    score, error = psb_benchmark.run_score(fake, tmp_path / "1.off", tmp_path / "1.seg",
                                           [tmp_path / "1_0.seg"])
    assert score is None
    assert error["exit_code"] == 2
    assert error["stderr"] == "score: the candidate has 3 labels for 4 faces"
    record = json.loads(json.dumps({"score_error": error}))
    assert record["score_error"]["command"][1] == "score"
    assert record["score_error"]["command"][0] == str(fake)
