#!/usr/bin/python3
"""Per-stage breakdown of one or more skelseg report.json files.

Usage: profiles/stage_table.py OUTDIR/report.json [...]
Prints a Markdown table: stage, parallel?, wall s, CPU s, share of the wall
time; then total wall, CPU, serial share, peak memory and the work counters.
"""
import argparse
import json

parser = argparse.ArgumentParser(description="Per-stage breakdown of skelseg report.json files (Markdown).")
parser.add_argument("reports", nargs="+", metavar="REPORT", help="a report.json written by skelseg segment")
for path in parser.parse_args().reports:
    with open(path) as f:
        r = json.load(f)
    wall = r["timing"]["wall_seconds"]
    print(f"### {r['input']['file']} (grid {' x '.join(map(str, r['grid']['size']))}, "
          f"{r['segment_count']} segments)\n")
    print("| stage | parallel | wall s | CPU s | share |")
    print("| --- | --- | ---: | ---: | ---: |")
    for s in sorted(r["stages"], key=lambda s: -s["wall_seconds"]):
        print(f"| {s['name']} | {'yes' if s['parallel'] else 'no'} | {s['wall_seconds']:.2f} | "
              f"{s['cpu_seconds']:.2f} | {100 * s['wall_seconds'] / wall:.1f}% |")
    t = r["timing"]
    print(f"\nwall {t['wall_seconds']:.2f} s, CPU {t['cpu_seconds']:.2f} s, serial stages "
          f"{t['serial_stage_seconds']:.2f} s ({100 * t['serial_share']:.1f}%), peak memory "
          f"{r['memory']['peak_resident_bytes'] / 1e9:.2f} GB\n")
    print("work: " + ", ".join(f"{k} {v:,}" for k, v in r["work"].items()) + "\n")
