#!/usr/bin/python3
"""Regenerates the picture grid across levels in docs/quality.md.

Usage: tools/level_grid.py [--models 1,81,281] [--tau 1%,3%,9%]
           [--resolution 128] [--binary build/skelseg] [--data ../shared/data]
           [--images docs/images/levels] [--work DIR] [--view three-quarter]
           [--cell-width 190]

For each shared PSB model, runs one hierarchy run with the joint level,
`skelseg segment M.off -o WORK/M --tau LIST --joints --level-previews`, so
every level (0 = the joint level, then the junction-rule levels finest
first) is one run's nested level, drawn by skelseg's own preview renderer
(levels/k/preview.png). From each level's preview it takes one view, crops
the background, scales it to --cell-width pixels and puts the levels side by
side, finest left, captioned with the level's tau and part count: one PNG
per model in --images. It prints the Markdown that docs/quality.md holds.
Needs Pillow (Debian's python3-pil).
"""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

REPO = pathlib.Path(__file__).resolve().parents[1]
# The preview's layout (io/render/PreviewRenderer.cpp at the default
# 1536 x 640): a title bar, three panels, a caption line under each.
TITLE_BAR, CAPTION, WIDTH, HEIGHT = 38, 24, 1536, 640
VIEWS = {"front": 0, "side": 1, "three-quarter": 2}


def parse_arguments(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--models", default="1,81,281",
                    help="PSB model numbers, comma-separated (default: Human 1, Ant 81, Armadillo 281)")
    ap.add_argument("--tau", default="1%,3%,9%", help="the --tau list (default 1%%,3%%,9%%)")
    ap.add_argument("--resolution", type=int, default=128, help="voxelisation resolution (128)")
    ap.add_argument("--binary", type=pathlib.Path, default=REPO / "build" / "skelseg",
                    help="the skelseg executable (default build/skelseg)")
    ap.add_argument("--data", type=pathlib.Path, default=REPO.parent / "shared" / "data",
                    help="the shared data folder with psb/off/N.off (default ../shared/data)")
    ap.add_argument("--images", type=pathlib.Path, default=REPO / "docs" / "images" / "levels",
                    help="where the PNGs go (default docs/images/levels)")
    ap.add_argument("--work", type=pathlib.Path, default=None,
                    help="folder for the runs (default: a temporary one, removed)")
    ap.add_argument("--view", choices=sorted(VIEWS), default="three-quarter",
                    help="which preview panel to show (default three-quarter)")
    ap.add_argument("--cell-width", type=int, default=190, help="pixels per level (190)")
    return ap.parse_args(argv)


def crop_view(path, view, width):
    """One panel of a preview.png, its background trimmed, `width` pixels wide."""
    from PIL import Image, ImageChops
    with Image.open(path) as picture:
        picture = picture.convert("RGB")
        if picture.size != (WIDTH, HEIGHT):
            raise SystemExit(f"{path}: expected a {WIDTH} x {HEIGHT} preview, got {picture.size}")
        left = VIEWS[view] * WIDTH // 3
        panel = picture.crop((left + 2, TITLE_BAR, left + WIDTH // 3 - 2, HEIGHT - CAPTION))
    background = Image.new("RGB", panel.size, panel.getpixel((0, 0)))
    box = ImageChops.difference(panel, background).getbbox()
    if box:
        margin = 6
        panel = panel.crop((max(0, box[0] - margin), max(0, box[1] - margin),
                            min(panel.width, box[2] + margin), min(panel.height, box[3] + margin)))
    height = max(1, round(panel.height * width / panel.width))
    return panel.resize((width, height), Image.LANCZOS)


def compose(cells, captions, width):
    """Cells side by side on white, each with its caption above."""
    from PIL import Image, ImageDraw
    caption_height = 14
    height = max(cell.height for cell in cells) + caption_height
    grid = Image.new("RGB", (width * len(cells), height), (255, 255, 255))
    draw = ImageDraw.Draw(grid)
    for i, (cell, caption) in enumerate(zip(cells, captions)):
        grid.paste(cell, (i * width, caption_height + (height - caption_height - cell.height) // 2))
        draw.text((i * width + 4, 1), caption, fill=(0, 0, 0))
    # Segment colours are few: a palette keeps the file small.
    return grid.quantize(colors=256, method=Image.FASTOCTREE, dither=Image.NONE)


def run_model(args, model, work):
    mesh = args.data / "psb" / "off" / f"{model}.off"
    if not mesh.exists():
        raise SystemExit(f"{mesh}: no such file (give --data)")
    out = work / str(model)
    subprocess.run([str(args.binary), "segment", str(mesh), "-o", str(out), "-q", "--force",
                    "--resolution", str(args.resolution), "--tau", args.tau, "--joints",
                    "--level-previews"], check=True)
    hierarchy = json.loads((out / "hierarchy.json").read_text())
    cells, captions = [], []
    for level in hierarchy["levels"]:
        k = level["level"]
        cells.append(crop_view(out / "levels" / str(k) / "preview.png", args.view, args.cell_width))
        name = f"{level['tau']} + joints" if level.get("joints") else level["tau"]
        captions.append(f"{name}: {level['segment_count']} parts")
    picture = compose(cells, captions, args.cell_width)
    args.images.mkdir(parents=True, exist_ok=True)
    target = args.images / f"{model}.png"
    picture.save(target, optimize=True)
    return target, [(c, level) for c, level in zip(captions, hierarchy["levels"])]


def main(argv):
    args = parse_arguments(argv)
    try:
        import PIL  # noqa: F401
    except ImportError:
        raise SystemExit("tools/level_grid.py needs Pillow (apt-get install python3-pil)")
    if not args.binary.exists():
        raise SystemExit(f"{args.binary}: no such file (build skelseg or give --binary)")
    models = [m.strip() for m in args.models.split(",") if m.strip()]
    with tempfile.TemporaryDirectory() as temporary:
        work = args.work or pathlib.Path(temporary)
        lines = []
        for model in models:
            target, levels = run_model(args, model, work)
            relative = target.relative_to(REPO / "docs") if target.is_relative_to(REPO / "docs") \
                else target
            parts = ", ".join(caption for caption, _ in levels)
            lines.append(f"**Model {model}** ({parts}; {target.stat().st_size // 1024} KB)\n")
            lines.append(f"![model {model} across levels]({relative})\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
