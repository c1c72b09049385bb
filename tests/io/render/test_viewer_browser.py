#!/usr/bin/env python3
"""viewer.html in a real browser: headless Chromium with SwiftShader's WebGL.

Segments a generated figure with the skelseg executable, opens the
viewer.html it wrote in headless Chromium and checks what a user would see:
  - the screenshot is not blank and shows the segment colours,
  - switching the skeleton colouring (sigma -> rho_C) changes the picture,
    and so does moving the level slider when the run has more than one level,
  - an input named like an HTML tag shows as text and runs nothing.

Run by ctest (label browser) as `python3 test_viewer_browser.py`: exits 77
(ctest's SKIP_RETURN_CODE) when Chromium is absent. Also runs under pytest.
Environment: SKELSEG_BINARY (the skelseg executable), CHROMIUM (optional).
"""
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import pytest
from PIL import Image

SKIP = 77
HOSTILE_STEM = '<img src=x onerror="document.body.dataset.injected=1">'
# The first colours of io/render/Palette.cpp (labels 1..8).
PALETTE = [(31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40),
           (148, 103, 189), (140, 86, 75), (227, 119, 194), (57, 59, 121)]


def chromium():
    return os.environ.get("CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")


def skelseg():
    binary = os.environ.get("SKELSEG_BINARY", "")
    if not binary or not os.access(binary, os.X_OK):
        pytest.fail("SKELSEG_BINARY must name the skelseg executable")
    return binary


def run(arguments, timeout=300):
    done = subprocess.run(arguments, capture_output=True, text=True, timeout=timeout)
    assert done.returncode == 0, f"{arguments[:3]} exit {done.returncode}: {done.stderr[-2000:]}"
    return done


def browser(work, page, *arguments, fragment=""):
    """Runs headless Chromium on `page` (a file); returns its stdout."""
    profile = tempfile.mkdtemp(prefix="chromium-profile-", dir=work)
    url = pathlib.Path(page).resolve().as_uri() + fragment
    done = run([chromium(), "--headless", "--no-sandbox", "--enable-unsafe-swiftshader",
                "--use-angle=swiftshader", "--hide-scrollbars", "--no-first-run",
                "--disable-extensions", f"--user-data-dir={profile}", "--window-size=800,600",
                "--virtual-time-budget=5000", *arguments, url], timeout=300)
    return done.stdout


_screenshots = {}


def screenshot(work, page, fragment=""):
    """The page at 800 x 600 as an RGB array (each URL is rendered once: a
    Chromium start costs seconds)."""
    key = (str(page), fragment)
    if key not in _screenshots:
        picture = pathlib.Path(work) / f"screenshot-{len(_screenshots)}.png"
        browser(work, page, f"--screenshot={picture}", fragment=fragment)
        _screenshots[key] = np.asarray(Image.open(picture).convert("RGB")).astype(int)
    return _screenshots[key]


@pytest.fixture(scope="module")
def work():
    if not chromium():
        pytest.skip("chromium is not installed")
    with tempfile.TemporaryDirectory(prefix="skelseg-viewer-") as directory:
        yield pathlib.Path(directory)


@pytest.fixture(scope="module")
def figure_run(work):
    volume = work / "figure.nrrd"
    run([skelseg(), "generate", "figure", "-o", str(volume), "--size", "96"])
    out = work / "figure-out"
    run([skelseg(), "segment", str(volume), "-o", str(out)])
    return out


def test_screenshot_shows_the_segments(work, figure_run):
    report = json.loads((figure_run / "report.json").read_text())
    parts = report["segment_count"]
    assert parts >= 3
    picture = screenshot(work, figure_run / "viewer.html", "#skeleton=sigma")
    background = picture[5, -5]
    differs = np.abs(picture - background).sum(axis=2) > 30
    assert differs.mean() > 0.05, "the picture is (nearly) blank"
    # Surfaces facing the camera show their palette colour; count pixels near
    # each of the run's segment colours.
    shown = 0
    for colour in PALETTE[:parts]:
        near = (np.abs(picture - np.array(colour)).max(axis=2) <= 24).sum()
        shown += near >= 150
    assert shown >= min(parts, 3), f"only {shown} of {parts} segment colours on screen"


def test_skeleton_colouring_switch_changes_the_picture(work, figure_run):
    page = figure_run / "viewer.html"
    sigma = screenshot(work, page, "#skeleton=sigma")
    rho = screenshot(work, page, "#skeleton=rho_c")
    changed = (np.abs(sigma - rho).sum(axis=2) > 30).sum()
    assert changed >= 50, f"only {changed} pixels changed"


def test_level_slider_changes_the_picture(work, figure_run):
    text = (figure_run / "viewer.html").read_text()
    start = text.index('id="skelseg-data">') + len('id="skelseg-data">')
    data = json.loads(text[start:text.index("</script>", start)])
    if len(data["levels"]) < 2:
        pytest.skip("this run has one level: nothing to slide")
    page = figure_run / "viewer.html"
    first = screenshot(work, page, "#level=0")
    last = screenshot(work, page, f"#level={len(data['levels']) - 1}")
    assert (np.abs(first - last).sum(axis=2) > 30).sum() >= 200


def test_file_name_is_shown_as_text_and_runs_nothing(work, figure_run):
    hostile = work / (HOSTILE_STEM + ".nrrd")
    shutil.copyfile(work / "figure.nrrd", hostile)
    out = work / "hostile-out"
    run([skelseg(), "segment", str(hostile), "-o", str(out), "--no-preview"])
    dom = browser(work, out / "viewer.html", "--dump-dom")
    assert 'data-rendered="' in dom, "the viewer script did not run"
    assert "data-injected" not in dom, "markup from the file name ran"
    assert "<img" not in dom
    escaped = HOSTILE_STEM.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    assert f'<h1 id="title">{escaped}.nrrd</h1>' in dom
    assert f"<title>skelseg: {escaped}.nrrd</title>" in dom


if __name__ == "__main__":
    if not chromium():
        print("test_viewer_browser: chromium not found, skipped")
        sys.exit(SKIP)
    sys.exit(pytest.main([__file__, "-q", "-p", "no:cacheprovider"]))
