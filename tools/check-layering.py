#!/usr/bin/env python3
"""Checks that includes point down only: engine -> io -> kernels -> kernels/base.

Fails (exit 1, one line per offence) when
  - a file in kernels/base/ includes anything of ours outside kernels/base/,
  - a file in kernels/ includes from io/ or engine/,
  - a file in io/ includes from engine/,
  - a tracked path has a component that begins with '-' (a script once took
    an option for an output folder).
Usage: tools/check-layering.py [--root DIR]
"""
import argparse
import pathlib
import re
import subprocess
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
# (folder prefix of the including file, forbidden include prefixes)
RULES = [
    ("kernels/base/", ("kernels/", "io/", "engine/"), ("kernels/base/",)),
    ("kernels/", ("io/", "engine/"), ()),
    ("io/", ("engine/",), ()),
]


def offences(root: pathlib.Path, tracked: list[str]) -> list[str]:
    found = []
    for path in tracked:
        if any(part.startswith("-") for part in pathlib.PurePosixPath(path).parts):
            found.append(f"{path}: tracked path has a component beginning with '-'")
        if not path.endswith((".h", ".hpp", ".cpp", ".cc")):
            continue
        rule = next((r for r in RULES if path.startswith(r[0])), None)
        if rule is None:
            continue
        prefix, forbidden, allowed = rule
        text = (root / path).read_text(encoding="utf-8", errors="replace")
        for number, line in enumerate(text.splitlines(), 1):
            match = INCLUDE.match(line)
            if not match:
                continue
            target = match.group(1)
            if target.startswith(allowed) if allowed else False:
                continue
            if target.startswith(forbidden):
                found.append(f"{path}:{number}: includes \"{target}\": {prefix} may not include upward")
    return found


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=str(pathlib.Path(__file__).resolve().parent.parent),
                        help="repository root (default: this script's repository)")
    args = parser.parse_args()
    root = pathlib.Path(args.root)
    tracked = subprocess.run(["git", "-C", str(root), "ls-files"], check=True, capture_output=True,
                             text=True).stdout.splitlines()
    found = offences(root, tracked)
    for line in found:
        print(line)
    print(f"check-layering: {len(tracked)} tracked files, {len(found)} offences")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
