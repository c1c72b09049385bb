#!/usr/bin/python3
"""Segment and score every model of the Princeton segmentation benchmark subset.

For each model N in DATA/psb/off/N.off this runs

    skelseg segment off/N.off -o OUT/N --resolution R [--tau T] -q --force
    skelseg score off/N.off OUT/N/segmentation.seg seg/N/*.seg.gz --json

and scores two trivial baselines with the same `skelseg score` command: the
whole model one segment, and every face its own segment. It writes
OUT/results.json (every per-model number) and OUT/table.md (a table per
category, the mean over the articulated categories and over all models).

    /usr/bin/python3 bench/psb_benchmark.py --skelseg build/skelseg
    /usr/bin/python3 bench/psb_benchmark.py --models 1,2,3 --tau 1.5%
    /usr/bin/python3 bench/psb_benchmark.py --tau 1%,3% --level finest   # one level of a hierarchy run
    /usr/bin/python3 bench/psb_benchmark.py --segment-args=--joints --out out/psb-joints
    /usr/bin/python3 bench/psb_benchmark.py --check        # exit 1 if issue 3's targets are missed
    /usr/bin/python3 bench/psb_benchmark.py --update-docs  # table and pictures into docs/quality.md

Where DATA/psb is absent it prints why and exits 0. Only the standard library
is needed; Pillow (or matplotlib) is used to downscale the pictures for
--update-docs when available.
"""

import argparse
import concurrent.futures
import gzip
import json
import os
import shutil
import signal
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent

ARTICULATED = ["Human", "Ant", "Octopus", "Teddy", "Hand", "Plier", "Fish", "Bird",
               "Armadillo", "FourLeg", "Airplane"]

# Issue 3: articulated categories, default settings, resolution 256.
TARGET_RAND_INDEX_ERROR = 0.20
TARGET_HAMMING = 0.25
TARGET_WITHIN_2X = 0.5  # "most models": more than half

TABLE_BEGIN = "<!-- psb-table:begin (written by bench/psb_benchmark.py --update-docs) -->"
TABLE_END = "<!-- psb-table:end -->"
GRID_BEGIN = "<!-- psb-grid:begin (written by bench/psb_benchmark.py --update-docs) -->"
GRID_END = "<!-- psb-grid:end -->"
PICTURE_WIDTH = 480


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--skelseg", default=str(REPO / "build" / "skelseg"),
                   help="the skelseg binary (default: build/skelseg in the repository)")
    p.add_argument("--data", default=str(REPO.parent / "shared" / "data"),
                   help="folder holding psb/ (default: ../shared/data next to the repository)")
    p.add_argument("--resolution", type=int, default=256, help="voxels along the longest side (default 256)")
    p.add_argument("--tau", default=None, help="passed to skelseg segment --tau (default: the CLI default)")
    p.add_argument("--level", default=None,
                   help="with a --tau list (1%%,3%%,9%%): score this level's segmentation.seg: "
                        "finest, coarsest or a number k (levels/k/; default: the top level, the coarsest)")
    p.add_argument("--segment-args", default="",
                   help='more options for skelseg segment, one string, e.g. "--joints"')
    p.add_argument("--out", default=str(REPO / "out" / "psb"), help="output folder (default out/psb)")
    p.add_argument("--models", default=None, help='subset of model ids, e.g. "1,2,3"')
    p.add_argument("--categories", default=None,
                   help='subset of categories, e.g. "Human,Ant"; "articulated" means all articulated ones')
    p.add_argument("--jobs", type=int, default=1,
                   help="models segmented at the same time (default 1; each skelseg uses all cores anyway)")
    p.add_argument("--time-limit", type=float, default=None, help="passed to skelseg segment --time-limit")
    p.add_argument("--resume", action="store_true",
                   help="reuse OUT/N/bench.json of an earlier run with the same binary and settings")
    p.add_argument("--check", action="store_true",
                   help="exit 1 unless the articulated categories meet issue 3's targets "
                        f"(RI error <= {TARGET_RAND_INDEX_ERROR}, Hamming <= {TARGET_HAMMING}, "
                        "part count within 2x of the human median on most models)")
    p.add_argument("--update-docs", action="store_true",
                   help="write the table and the picture grid into docs/quality.md and docs/images/psb/")
    return p.parse_args(argv)


# ---------------------------------------------------------------- small helpers

def read_labels(path):
    """A .seg or .seg.gz file: one integer per line."""
    path = Path(path)
    with open(path, "rb") as f:
        data = f.read()
    if data[:2] == b"\x1f\x8b":
        data = gzip.decompress(data)
    return [int(tok) for tok in data.split()]


def write_labels(path, labels):
    with open(path, "w") as f:
        f.write("\n".join(str(v) for v in labels))
        f.write("\n")


def last_line(text):
    lines = [l for l in text.strip().splitlines() if l.strip()]
    return lines[-1] if lines else ""


def read_categories(psb):
    categories = {}
    with open(psb / "CATEGORIES.tsv") as f:
        for line in f:
            parts = line.split()
            if len(parts) >= 2:
                categories[int(parts[0])] = parts[1]
    return categories


def mean(values):
    values = [v for v in values if v is not None]
    return sum(values) / len(values) if values else None


def fmt(value, digits=3):
    return "-" if value is None else f"{value:.{digits}f}"


def fmt_count(value):
    if value is None:
        return "-"
    return str(int(value)) if float(value).is_integer() else f"{value:.1f}"


def within_factor_two(found, median):
    if found is None or median is None or median <= 0:
        return None
    return median / 2.0 <= found <= median * 2.0


# ---------------------------------------------------------------- skelseg calls

def run_score(skelseg, mesh, candidate, humans):
    cmd = [skelseg, "score", str(mesh), str(candidate)] + [str(h) for h in humans] + ["--json"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        return None, {"exit_code": proc.returncode, "stderr": last_line(proc.stderr),
                      "command": [str(part) for part in cmd]}
    doc = json.loads(proc.stdout)
    return doc["mean"], None


def baseline_files(out, model, face_count):
    """The two trivial segmentations, written once per face count."""
    folder = out / "baselines"
    folder.mkdir(parents=True, exist_ok=True)
    one = folder / f"{model}-one-segment.seg"
    every = folder / f"{model}-every-face.seg"
    if not one.exists() or len(read_labels(one)) != face_count:
        write_labels(one, [0] * face_count)
    if not every.exists() or len(read_labels(every)) != face_count:
        write_labels(every, range(face_count))
    return one, every


def settings_key(args, skelseg):
    st = os.stat(skelseg)
    return {"skelseg": str(skelseg), "skelseg_mtime": st.st_mtime, "resolution": args.resolution,
            "tau": args.tau, "level": args.level, "time_limit": args.time_limit,
            "segment_args": args.segment_args}


def level_seg_path(model_out, level):
    """segmentation.seg of the level to score: the top level (the coarsest)
    without --level, else levels/k/ of a hierarchy run (finest is 0)."""
    if level is None:
        return model_out / "segmentation.seg"
    levels = sorted((p for p in (model_out / "levels").glob("*") if p.name.isdigit()),
                    key=lambda p: int(p.name))
    if not levels:
        return model_out / "levels" / "missing (run with a --tau list)" / "segmentation.seg"
    if level == "finest":
        return levels[0] / "segmentation.seg"
    if level == "coarsest":
        return levels[-1] / "segmentation.seg"
    return model_out / "levels" / str(int(level)) / "segmentation.seg"


def benchmark_model(args, skelseg, psb, out, model, category):
    mesh = psb / "off" / f"{model}.off"
    humans = sorted((psb / "seg" / str(model)).glob("*.seg.gz"),
                    key=lambda p: (len(p.name), p.name))
    model_out = out / str(model)
    key = settings_key(args, skelseg)
    cached = model_out / "bench.json"
    if args.resume and cached.exists():
        try:
            record = json.loads(cached.read_text())
            if record.get("settings") == key:
                record["reused"] = True
                return record
        except (ValueError, OSError):
            pass

    record = {"model": model, "category": category, "articulated": category in ARTICULATED,
              "mesh": str(mesh), "humans": len(humans), "settings": key}
    human_labels = [read_labels(h) for h in humans]
    face_count = len(human_labels[0]) if human_labels else None
    record["faces"] = face_count
    human_parts = [len(set(l)) for l in human_labels]
    record["human_parts"] = human_parts
    record["human_median_parts"] = statistics.median(human_parts) if human_parts else None

    # Baselines: scored with the same command as our segmentation.
    record["baselines"] = {}
    if face_count:
        one, every = baseline_files(out, model, face_count)
        for name, path in (("one_segment", one), ("every_face", every)):
            score, error = run_score(skelseg, mesh, path, humans)
            record["baselines"][name] = score if score else {"error": error}

    # Our segmentation.
    cmd = [str(skelseg), "segment", str(mesh), "-o", str(model_out), "--resolution", str(args.resolution),
           "-q", "--force"]
    if args.tau is not None:
        cmd += ["--tau", args.tau]
    cmd += args.segment_args.split()
    if args.time_limit is not None:
        cmd += ["--time-limit", str(args.time_limit)]
    record["command"] = cmd
    start = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    record["seconds"] = time.monotonic() - start
    record["exit_code"] = proc.returncode
    if proc.returncode != 0:
        record["error"] = last_line(proc.stderr) or last_line(proc.stdout)
        if proc.returncode < 0:
            try:
                name = signal.Signals(-proc.returncode).name
            except ValueError:
                name = f"signal {-proc.returncode}"
            record["error"] = f"killed by {name}" + (f"; {record['error']}" if record["error"] else "")
        record["ok"] = False
        record["timed_out"] = proc.returncode == 3 and args.time_limit is not None
        model_out.mkdir(parents=True, exist_ok=True)
        cached.write_text(json.dumps(record, indent=2) + "\n")
        return record

    report_path = model_out / "report.json"
    try:
        report = json.loads(report_path.read_text())
        timing = report.get("timing", {})
        record["report_wall_seconds"] = timing.get("wall_seconds")
        record["report_cpu_seconds"] = timing.get("cpu_seconds")
        record["segment_count"] = report.get("segment_count")
        record["face_segments"] = report.get("face_segments")
        record["peak_resident_bytes"] = report.get("memory", {}).get("peak_resident_bytes")
        record["warnings"] = report.get("warnings", [])
        record["tau_area"] = [o.get("tau_area") for o in report.get("objects", [])]
        record["objects"] = len(report.get("objects", []))
    except (OSError, ValueError) as e:
        record["report_error"] = str(e)

    seg_path = level_seg_path(model_out, args.level)
    record["scored_file"] = str(seg_path)
    try:
        labels = read_labels(seg_path)
    except (OSError, ValueError) as e:
        # skelseg said it succeeded: a missing or unreadable output is a bug worth reporting.
        record["ok"] = False
        record["error"] = f"exit 0 but {seg_path} is unreadable: {e}"
        cached.write_text(json.dumps(record, indent=2) + "\n")
        return record
    record["parts"] = len(set(labels))
    record["parts_within_2x"] = within_factor_two(record["parts"], record["human_median_parts"])

    score, error = run_score(skelseg, mesh, seg_path, humans)
    if score is None:
        record["ok"] = False
        record["error"] = f"score failed: {error['stderr']}"
        record["score_error"] = error
    else:
        record["ok"] = True
        record["score"] = score
    record["preview"] = str(model_out / "preview.png") if (model_out / "preview.png").exists() else None
    cached.write_text(json.dumps(record, indent=2) + "\n")
    return record


# ---------------------------------------------------------------- summaries

def summarize(records):
    """Means over a list of model records (ours over the models that succeeded)."""
    ok = [r for r in records if r.get("ok")]

    def base(name, key):
        return mean([r["baselines"].get(name, {}).get(key) for r in records])

    within = [r["parts_within_2x"] for r in ok if r.get("parts_within_2x") is not None]
    return {
        "models": len(records),
        "succeeded": len(ok),
        "failed": [r["model"] for r in records if not r.get("ok")],
        "rand_index_error": mean([r["score"]["rand_index_error"] for r in ok]),
        "hamming_distance": mean([r["score"]["hamming_distance"] for r in ok]),
        "missing_rate": mean([r["score"]["missing_rate"] for r in ok]),
        "false_alarm_rate": mean([r["score"]["false_alarm_rate"] for r in ok]),
        "one_segment": {"rand_index_error": base("one_segment", "rand_index_error"),
                        "hamming_distance": base("one_segment", "hamming_distance")},
        "every_face": {"rand_index_error": base("every_face", "rand_index_error"),
                       "hamming_distance": base("every_face", "hamming_distance")},
        # A failed model counts as "not within 2x".
        "parts_within_2x": (sum(1 for w in within if w) / len(records)) if records else None,
        "seconds": mean([r.get("seconds") for r in records]),
    }


def category_order(categories):
    seen = []
    for model in sorted(categories):
        if categories[model] not in seen:
            seen.append(categories[model])
    return seen


def markdown_table(records, args):
    by_category = {}
    for r in records:
        by_category.setdefault(r["category"], []).append(r)
    order = [c for c in category_order({r["model"]: r["category"] for r in records}) if c in by_category]
    articulated = [c for c in order if c in ARTICULATED]
    other = [c for c in order if c not in ARTICULATED]

    lines = []
    lines.append("| category | models | RI error: ours \\| one segment \\| every face "
                 "| Hamming: ours \\| one segment \\| every face | parts found / human median "
                 "| within 2x | seconds per model |")
    lines.append("| --- | --- | --- | --- | --- | --- | --- |")

    def row(label, recs, models_text, parts_text):
        s = summarize(recs)
        ri = f"**{fmt(s['rand_index_error'])}** \\| {fmt(s['one_segment']['rand_index_error'])} \\| " \
             f"{fmt(s['every_face']['rand_index_error'])}"
        hd = f"**{fmt(s['hamming_distance'])}** \\| {fmt(s['one_segment']['hamming_distance'])} \\| " \
             f"{fmt(s['every_face']['hamming_distance'])}"
        within = "-" if s["parts_within_2x"] is None else \
            f"{round(s['parts_within_2x'] * s['models'])}/{s['models']}"
        seconds = fmt(s["seconds"], 1)
        if any(r.get("timed_out") for r in recs):
            seconds = "> " + seconds  # a timed-out model counts with its time limit
        lines.append(f"| {label} | {models_text} | {ri} | {hd} | {parts_text} | {within} | {seconds} |")

    def parts_cell(recs):
        cells = []
        for r in recs:
            found = fmt_count(r.get("parts")) if r.get("ok") else ("timeout" if r.get("timed_out") else "failed")
            cells.append(f"{found} / {fmt_count(r.get('human_median_parts'))}")
        return ", ".join(cells)

    for group in (articulated, other):
        for c in group:
            recs = by_category[c]
            models = ", ".join(str(r["model"]) for r in recs)
            row(c, recs, models, parts_cell(recs))
    art = [r for r in records if r["articulated"]]
    if art:
        row(f"**articulated** ({len(articulated)} categories)", art, str(len(art)), "")
    if other:
        row("other", [r for r in records if not r["articulated"]],
            str(len([r for r in records if not r["articulated"]])), "")
    if art and other:
        row("**all**", records, str(len(records)), "")

    notes = [
        "",
        "RI error: Rand Index error over faces; Hamming: Hamming distance weighted by face area "
        "(the benchmark's conventions, see docs/meshes.md). Each is the mean over a model's human "
        "segmentations, then over the category's models; the summary rows are means over models. "
        "Ours in bold; \"one segment\" and \"every face\" are the trivial baselines scored with the same command. "
        "Parts found: distinct labels in segmentation.seg; human median: median over the humans of their "
        "distinct labels. Within 2x: models whose part count is between half and twice the human median "
        "(a failed model counts as outside). Seconds: wall time of `skelseg segment` per model "
        "(voxelisation, segmentation, face labels, all outputs and the preview).",
    ]
    if args.time_limit is not None:
        notes.append(f"Each model had a time limit of {args.time_limit:g} s (`--time-limit`); a model that "
                     "reached it counts as failed and is left out of our means (the baselines keep it).")
    failed = [r for r in records if not r.get("ok")]
    if failed:
        notes.append("")
        notes.append("Failed: " + "; ".join(
            f"model {r['model']} ({r['category']}): exit {r.get('exit_code')}, {r.get('error', '')}" for r in failed))
    return "\n".join(lines + notes) + "\n"


# ---------------------------------------------------------------- pictures

def downscale_picture(src, dst, width=PICTURE_WIDTH):
    """Write src downscaled to about `width` pixels wide. Returns how (pil, matplotlib, copy)."""
    dst.parent.mkdir(parents=True, exist_ok=True)
    try:
        from PIL import Image
        with Image.open(src) as im:
            im = im.convert("RGB")
            if im.width > width:
                im = im.resize((width, max(1, round(im.height * width / im.width))), Image.LANCZOS)
            # Segment colours are few: a 256-colour palette keeps the file at about a third.
            im = im.quantize(colors=256, method=Image.FASTOCTREE, dither=Image.NONE)
            im.save(dst, optimize=True)
        return "pil"
    except ImportError:
        pass
    try:
        import matplotlib.image as mpimg
        img = mpimg.imread(str(src))
        step = max(1, int(round(img.shape[1] / width)))
        mpimg.imsave(str(dst), img[::step, ::step])
        return "matplotlib"
    except ImportError:
        shutil.copyfile(src, dst)
        return "copy"


def worst_articulated(records):
    """{model: why} for the articulated models with the worst RI error and the worst Hamming distance."""
    art = [r for r in records if r["articulated"] and r.get("ok")]
    worst = {}
    if art:
        for key, name in (("rand_index_error", "worst RI error"), ("hamming_distance", "worst Hamming")):
            m = max(art, key=lambda r: r["score"][key])["model"]
            worst[m] = worst[m] + ", " + name if m in worst else name
    return worst


def picture_models(records):
    """The first model of each category, plus the worst-scoring articulated models."""
    chosen, seen = [], set()
    for r in sorted(records, key=lambda r: r["model"]):
        if r["category"] not in seen and r.get("preview"):
            seen.add(r["category"])
            chosen.append(r["model"])
    by_model = {r["model"]: r for r in records}
    for m in worst_articulated(records):
        if m not in chosen and by_model[m].get("preview"):
            chosen.append(m)
    return chosen


def picture_grid(records, models, columns=2):
    by_model = {r["model"]: r for r in records}
    worst = worst_articulated(records)
    cells = []
    for m in models:
        r = by_model[m]
        if r.get("ok"):
            caption = (f"<b>{m}</b> {r['category']}: {fmt_count(r.get('parts'))} parts (human median "
                       f"{fmt_count(r['human_median_parts'])}), RI error {fmt(r['score']['rand_index_error'], 2)}, "
                       f"Hamming {fmt(r['score']['hamming_distance'], 2)}")
        else:
            caption = f"<b>{m}</b> {r['category']}: failed"
        if m in worst:
            caption += f" ({worst[m]} of the articulated models)"
        cells.append(f'<img src="images/psb/{m}.png" width="480" alt="model {m}"><br>{caption}')
    missing = [r for r in records if not r.get("preview") and r["category"] not in
               {by_model[m]["category"] for m in models}]
    lines = ["<table>"]
    for i in range(0, len(cells), columns):
        lines.append("<tr>" + "".join(f'<td valign="top">{c}</td>' for c in cells[i:i + columns]) + "</tr>")
    lines.append("</table>")
    if missing:
        lines.append("")
        lines.append("No picture (the run failed): " + ", ".join(f"{r['model']} {r['category']}" for r in missing) + ".")
    return "\n".join(lines) + "\n"


def replace_between(text, begin, end, body):
    if begin in text and end in text:
        head, rest = text.split(begin, 1)
        _, tail = rest.split(end, 1)
        return head + begin + "\n" + body + end + tail
    return text.rstrip("\n") + "\n\n" + begin + "\n" + body + end + "\n"


def update_docs(records, table, args):
    docs = REPO / "docs"
    images = docs / "images" / "psb"
    models = picture_models(records)
    by_model = {r["model"]: r for r in records}
    images.mkdir(parents=True, exist_ok=True)
    for m in models:
        how = downscale_picture(Path(by_model[m]["preview"]), images / f"{m}.png")
        print(f"picture {images / f'{m}.png'} ({how})")
    quality = docs / "quality.md"
    text = quality.read_text() if quality.exists() else "# Quality on the Princeton segmentation benchmark\n"
    text = replace_between(text, TABLE_BEGIN, TABLE_END, table)
    text = replace_between(text, GRID_BEGIN, GRID_END, picture_grid(records, models))
    quality.write_text(text)
    print(f"updated {quality}")


# ---------------------------------------------------------------- main

def main(argv):
    args = parse_args(argv)
    psb = Path(args.data) / "psb"
    if not (psb / "off").is_dir() or not (psb / "CATEGORIES.tsv").is_file():
        print(f"psb_benchmark: {psb} (the Princeton benchmark subset) is absent; nothing to do, skipping.")
        return 0
    skelseg = Path(args.skelseg)
    if not skelseg.is_file() or not os.access(skelseg, os.X_OK):
        print(f"psb_benchmark: {skelseg} is not an executable; build skelseg or pass --skelseg", file=sys.stderr)
        return 2
    skelseg = skelseg.resolve()
    if args.jobs < 1:
        print("psb_benchmark: --jobs must be at least 1", file=sys.stderr)
        return 2

    categories = read_categories(psb)
    models = sorted(m for m in categories if (psb / "off" / f"{m}.off").is_file())
    if args.models:
        wanted = {int(tok) for tok in args.models.replace(" ", "").split(",") if tok}
        missing = wanted - set(models)
        if missing:
            print(f"psb_benchmark: no such models: {sorted(missing)}", file=sys.stderr)
            return 2
        models = [m for m in models if m in wanted]
    if args.categories:
        wanted = set()
        for tok in args.categories.split(","):
            tok = tok.strip()
            wanted |= set(ARTICULATED) if tok.lower() == "articulated" else {tok}
        models = [m for m in models if categories[m] in wanted]
    if not models:
        print("psb_benchmark: no models selected", file=sys.stderr)
        return 2

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"psb_benchmark: {len(models)} models, resolution {args.resolution}, "
          f"tau {args.tau or 'default'}, {skelseg}, output {out}", flush=True)

    records = {}

    def done(record):
        records[record["model"]] = record
        if record.get("ok"):
            s = record["score"]
            print(f"  {record['model']:>4} {record['category']:<10} {record['seconds']:6.1f} s  "
                  f"parts {fmt_count(record['parts'])}/{fmt_count(record['human_median_parts'])}  "
                  f"RI {s['rand_index_error']:.3f}  HD {s['hamming_distance']:.3f}"
                  + ("  (reused)" if record.get("reused") else ""), flush=True)
        else:
            print(f"  {record['model']:>4} {record['category']:<10} FAILED exit {record.get('exit_code')}: "
                  f"{record.get('error')}", flush=True)

    if args.jobs == 1:
        for m in models:
            done(benchmark_model(args, skelseg, psb, out, m, categories[m]))
    else:
        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
            futures = [pool.submit(benchmark_model, args, skelseg, psb, out, m, categories[m]) for m in models]
            for f in concurrent.futures.as_completed(futures):
                done(f.result())

    ordered = [records[m] for m in models]
    articulated = [r for r in ordered if r["articulated"]]
    summary = {"articulated": summarize(articulated) if articulated else None,
               "all": summarize(ordered),
               "categories": {c: summarize([r for r in ordered if r["category"] == c])
                              for c in category_order(categories) if any(r["category"] == c for r in ordered)}}
    results = {"settings": {"skelseg": str(skelseg), "data": str(psb), "resolution": args.resolution,
                            "tau": args.tau, "models": models},
               "targets": {"rand_index_error": TARGET_RAND_INDEX_ERROR, "hamming_distance": TARGET_HAMMING,
                           "parts_within_2x_fraction": TARGET_WITHIN_2X},
               "summary": summary, "models": ordered}
    (out / "results.json").write_text(json.dumps(results, indent=2) + "\n")
    table = markdown_table(ordered, args)
    (out / "table.md").write_text(table)
    print()
    print(table)
    print(f"wrote {out / 'results.json'} and {out / 'table.md'}")

    if args.update_docs:
        update_docs(ordered, table, args)

    if args.check:
        a = summary["articulated"]
        if a is None:
            print("check: no articulated models selected", file=sys.stderr)
            return 1
        problems = []
        if a["failed"]:
            problems.append(f"failed models {a['failed']}")
        if a["rand_index_error"] is None or a["rand_index_error"] > TARGET_RAND_INDEX_ERROR:
            problems.append(f"RI error {fmt(a['rand_index_error'])} > {TARGET_RAND_INDEX_ERROR}")
        if a["hamming_distance"] is None or a["hamming_distance"] > TARGET_HAMMING:
            problems.append(f"Hamming {fmt(a['hamming_distance'])} > {TARGET_HAMMING}")
        if a["parts_within_2x"] is None or a["parts_within_2x"] <= TARGET_WITHIN_2X:
            problems.append(f"parts within 2x on {fmt(a['parts_within_2x'], 2)} of the models (need most)")
        if problems:
            print("check: targets missed on the articulated categories: " + "; ".join(problems), file=sys.stderr)
            return 1
        print("check: articulated targets met")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
