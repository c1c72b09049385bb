#!/usr/bin/python3
"""Lists the pieces that the small-segment merge decides, from report.json.

For every output folder (one `skelseg segment` run whose report.json has
`objects[].segments_before_merge`, docs/outputs.md), prints each piece whose
measured area is below --near times the merge threshold max(tau, noise
area), with three measures over that threshold: `core` (nodes outside every
cut's band), `area` (with the band nodes the labelling sweep gave it) and
`measured` (what the merge compares: area plus the rest of each band it
touches, docs/algorithm.md §9.2), and whether it merged. The largest piece
of each object is left out.

Usage: bench/merge_measures.py OUT_DIR [OUT_DIR ...] [--near 1.5]
"""
import argparse
import json
import sys
from pathlib import Path


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=__doc__.split("\n\n", 1)[1])
    p.add_argument("folders", nargs="+", help="skelseg output folders")
    p.add_argument("--near", type=float, default=1.5,
                   help="list pieces measured below this many thresholds (default 1.5)")
    args = p.parse_args(argv)
    for name in args.folders:
        path = Path(name) / "report.json"
        if not path.exists():
            print(f"{name}: no report.json, skipped", file=sys.stderr)
            continue
        report = json.loads(path.read_text())
        for obj in report.get("objects", []):
            pieces = obj.get("segments_before_merge")
            if pieces is None:
                print(f"{name}: report.json has no segments_before_merge", file=sys.stderr)
                break
            threshold = max(obj["tau_area"], obj["noise_area"])
            largest = max(range(len(pieces)), key=lambda i: pieces[i]["area"], default=None)
            rows = [f"core {q['core'] / threshold:.2f} area {q['area'] / threshold:.2f} "
                    f"measured {q['measured'] / threshold:.2f}" + (" merged" if q["merged"] else "")
                    for i, q in enumerate(pieces)
                    if i != largest and q["measured"] < args.near * threshold]
            print(f"{name} object {obj['index']}: {len(pieces)} pieces, "
                  f"{sum(q['merged'] for q in pieces)} merged" +
                  "".join(f"\n    {row}" for row in rows))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
