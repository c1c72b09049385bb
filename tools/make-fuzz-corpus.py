#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz targets: tests/fuzz/corpus/<format>/.

Tiny valid files (a few hundred bytes at most) covering each reader's main
paths: encodings, sample types, endianness, header variants. Deterministic, so
re-running it reproduces the committed files exactly.

    tools/make-fuzz-corpus.py [OUTDIR]     (default: tests/fuzz/corpus)
"""
import argparse
import bz2
import gzip
import os
import struct
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def parse_args():
    parser = argparse.ArgumentParser(
        description="Write the seed corpus of the fuzz targets (deterministic bytes).")
    parser.add_argument("outdir", nargs="?", default=os.path.join(ROOT, "tests", "fuzz", "corpus"),
                        help="output folder (default: tests/fuzz/corpus)")
    return parser.parse_args()


OUT = parse_args().outdir


def write(fmt, name, data):
    folder = os.path.join(OUT, fmt)
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def gz(data):
    # mtime=0: the same bytes every run
    return gzip.compress(data, mtime=0)


# --- NRRD ---------------------------------------------------------------------
cube = bytes([0, 1, 1, 0, 1, 0, 0, 1])  # 2x2x2
write("nrrd", "raw-uint8.nrrd", b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n" + cube)
write("nrrd", "gzip-uchar-space.nrrd",
      b"NRRD0005\n# comment\ntype: unsigned char\ndimension: 3\nspace: RAS\nsizes: 3 2 2\n"
      b"space directions: (0.5,0,0) (0,0.5,0) (0,0,2)\nspace origin: (1,-2,3.5)\nkinds: domain domain domain\n"
      b"encoding: gzip\nkey:=value\n\n" + gz(bytes([0, 1, 2, 0, 0, 7, 1, 1, 0, 0, 3, 0])))
write("nrrd", "raw-uint16-big.nrrd",
      b"NRRD0004\ntype: uint16\ndimension: 3\nsizes: 2 1 2\nendian: big\nencoding: raw\nspacings: 1 2 NaN\n\n"
      + struct.pack(">4H", 0, 1, 256, 65535))
write("nrrd", "raw-float-little.nrrd",
      b"NRRD0003\ntype: float\ndimension: 3\nsizes: 2 2 1\nendian: little\nencoding: raw\nspace dimension: 3\n\n"
      + struct.pack("<4f", 0.0, -0.0, 1.5, float("nan")))
write("nrrd", "zlib-int32.nrrd",
      b"NRRD0004\ntype: int32\ndimension: 3\nsizes: 1 2 2\nendian: little\nencoding: gz\n\n"
      + zlib.compress(struct.pack("<4i", 0, -1, 5, 0)))
write("nrrd", "two-members-double.nrrd",
      b"NRRD0004\ntype: double\ndimension: 3\nsizes: 2 1 1\nendian: little\nencoding: gzip\n\n"
      + gz(struct.pack("<d", 0.0)) + gz(struct.pack("<d", 2.0)))
write("nrrd", "detached.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: x.raw\n")
write("nrrd", "dim4-scalar.nrrd",
      b"NRRD0004\ntype: uint8\ndimension: 4\nsizes: 1 2 2 2\nencoding: raw\n"
      b"kinds: scalar domain domain domain\nspace directions: none (1,0,0) (0,1,0) (0,0,1)\n\n" + cube)
write("nrrd", "list.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: LIST\nz0.raw\nz1.raw\n")
write("nrrd", "pattern.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\ndata file: z%03d.gz 1 0 -1 2\n")

# --- binvox -------------------------------------------------------------------
write("binvox", "v1.binvox", b"#binvox 1\ndim 4 4 4\ntranslate -1 0 0.5\nscale 2\ndata\n" + bytes([0, 20, 1, 24, 0, 20]))
write("binvox", "v2-values.binvox", b"#binvox 2\ndim 2 3 2\nextra line\ndata\n" + bytes([3, 5, 0, 0, 0, 7]))
write("binvox", "no-translate.binvox", b"#binvox 1\ndim 1 1 3\ndata\n" + bytes([1, 3]))

# --- OFF ----------------------------------------------------------------------
write("off", "tetra.off", "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
write("off", "cube-quads.off",
      "OFF\n# a unit cube\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n")
write("off", "coff-inline.off", "COFF 4 2 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n"
      "1 1 0 9 9 9 255\n3 0 1 2 1 2 3\n3 1 3 2\n")
# A colour after a face's indices (integers, reals, a colour-map index, after
# indices wrapped onto the next line), and the header's counts one per line.
write("off", "face-colours.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1 255 0 0\n"
      "3 0 1 3 1.0 0.0 0.0 1.0\n3 0 3\n2 7\n3 1 2 3 0 128 255 255\n")
write("off", "counts-per-line.off", "OFF\n\n# the counts\n4\n4\n\n6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")

# Binary OFF: Geomview's layout (big-endian, a colour count per face) and
# pmp-library's (little-endian, none).
tetra_xyz = [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]
tetra_faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
write("off", "binary-geomview.off", b"OFF BINARY\n" + struct.pack(">3i", 4, 4, 6)
      + struct.pack(">12f", *tetra_xyz)
      + b"".join(struct.pack(">5i", 3, *f, 0) for f in tetra_faces[:3])
      + struct.pack(">5i", 3, *tetra_faces[3], 1) + struct.pack(">f", 0.5))
write("off", "binary-pmp.off", b"OFF BINARY\n" + struct.pack("<3i", 4, 4, 0)
      + struct.pack("<12f", *tetra_xyz)
      + b"".join(struct.pack("<4i", 3, *f) for f in tetra_faces))
write("nrrd", "byte-skip-end.nrrd",
      b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\nbyte skip: -1\n\nhead" + cube)
# The text and bzip2 encodings, line skip, byte skip -1 of decompressed data.
write("nrrd", "ascii-int16.nrrd",
      "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n\n0 -1, 2\n+3 0\t7.0 1e1 0\n")
write("nrrd", "text-float.nrrd",
      "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 1\nencoding: text\n\n0 -0 1.5e-3 nan\n")
write("nrrd", "hex-uint16-big.nrrd",
      "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 2 1 2\nendian: big\nencoding: hex\n\n0000 01Ff\n00 0a ffFF\n")
write("nrrd", "bzip2-uint8.nrrd",
      b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: bzip2\n\n" + bz2.compress(cube, 9))
write("nrrd", "bz2-streams-int16.nrrd",
      b"NRRD0004\ntype: int16\ndimension: 3\nsizes: 2 1 1\nendian: little\nencoding: bz2\n\n"
      + bz2.compress(struct.pack("<h", 0), 1) + bz2.compress(struct.pack("<h", -2), 1))
write("nrrd", "line-skip-gzip.nrrd",
      b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\nline skip: 2\n\nskip\nthese\n"
      + gz(cube))
write("nrrd", "gzip-byte-skip-end.nrrd",
      b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\nbyte skip: -1\n\n"
      + gz(b"a header" + cube))
write("nrrd", "bzip2-byte-skip.nrrd",
      b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: bzip2\nbyte skip: 3\n\n"
      + bz2.compress(b"abc" + cube, 9))

# --- OBJ ----------------------------------------------------------------------
write("obj", "tetra.obj", "# tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
# a tetrahedron with a small triangle standing on one edge: a fin (io/mesh/MeshFins.h)
write("obj", "fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0.5 -0.02 -0.02\n"
      "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 2 5\n")
# an octahedron split into 32 triangles, one of them missing: a small hole (io/mesh/MeshHoles.h)
octahedron = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
octahedron_faces = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
hole_vertices, midpoint, hole_faces = list(octahedron), {}, []
def middle(a, b):
    key = (min(a, b), max(a, b))
    if key not in midpoint:
        midpoint[key] = len(hole_vertices)
        hole_vertices.append(tuple((p + q) / 2 for p, q in zip(hole_vertices[a], hole_vertices[b])))
    return midpoint[key]
for a, b, c in octahedron_faces:
    ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
    hole_faces += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
write("obj", "hole.obj", "".join("v %g %g %g\n" % v for v in hole_vertices)
      + "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in hole_faces[:-1]))
# the same octahedron closed, with the four triangles of one face wound the wrong way: flipped
# faces (io/mesh/FlippedFaces.h)
write("obj", "flipped.obj", "".join("v %g %g %g\n" % v for v in hole_vertices)
      + "".join("f %d %d %d\n" % ((a + 1, c + 1, b + 1) if k < 4 else (a + 1, b + 1, c + 1))
                for k, (a, b, c) in enumerate(hole_faces)))
# the same octahedron beside a small cup (a cube without its top, too open to cap): a fin and a
# hole together (io/mesh/MeshFinsAndHoles.h)
cup = [(2 + 0.1 * (c & 1), 0.1 * ((c >> 1) & 1), 0.1 * ((c >> 2) & 1)) for c in range(8)]
cup_faces = [t for a, b, c, d in ((0, 2, 3, 1), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7), (2, 0, 4, 6))
             for t in ((a, b, c), (a, c, d))]
cup_offset = len(hole_vertices)
write("obj", "hole-cup.obj", "".join("v %g %g %g\n" % v for v in hole_vertices + cup)
      + "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in hole_faces[:-1])
      + "".join("f %d %d %d\n" % (a + cup_offset + 1, b + cup_offset + 1, c + cup_offset + 1)
                for a, b, c in cup_faces))
write("obj", "slashes.obj",
      "o quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\ng side\nusemtl red\ns off\n"
      "f 1/1/1 2/2/1 3/1/1 4/2/1\nf -4//1 -2//1 -1//1\nf 1/1 2/2 3/2\n")

# --- STL ----------------------------------------------------------------------
tri = [((0, 0, 0), (1, 0, 0), (0, 1, 0)), ((0, 0, 0), (0, 1, 0), (0, 0, 1)),
       ((0, 0, 0), (0, 0, 1), (1, 0, 0)), ((1, 0, 0), (0, 0, 1), (0, 1, 0))]
ascii = "solid tetra\n"
for t in tri:
    ascii += " facet normal 0 0 0\n  outer loop\n"
    for v in t:
        ascii += "   vertex %g %g %g\n" % v
    ascii += "  endloop\n endfacet\n"
ascii += "endsolid tetra\n"
write("stl", "tetra-ascii.stl", ascii)
binary = b"binary tetra".ljust(80, b" ") + struct.pack("<I", len(tri))
for t in tri:
    binary += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v) for v in t) + b"\0\0"
write("stl", "tetra-binary.stl", binary)
# binary whose header starts with "solid": still binary by its size
write("stl", "solid-binary.stl", b"solid but binary".ljust(80, b" ") + binary[80:])

# --- PLY ----------------------------------------------------------------------
verts = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
text = ("ply\nformat ascii 1.0\ncomment tetra\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nelement face 4\nproperty list uchar int vertex_indices\n"
        "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n")
text += "".join("%g %g %g 7\n" % v for v in verts) + "".join("3 %d %d %d\n" % f for f in faces) + "0 1\n"
write("ply", "tetra-ascii.ply", text)
for endian, tag in (("<", "binary_little_endian"), (">", "binary_big_endian")):
    head = ("ply\nformat %s 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
            "element face 4\nproperty uchar flags\nproperty list uchar uint vertex_index\nend_header\n" % tag)
    body = b"".join(struct.pack(endian + "3d", *v) for v in verts)
    body += b"".join(struct.pack(endian + "BB3I", 0, 3, *f) for f in faces)
    write("ply", "tetra-%s.ply" % tag.split("_")[1], head.encode() + body)

# --- .seg ---------------------------------------------------------------------
write("seg", "plain.seg", "0\n0\n1\n2\n1\n")
write("seg", "crlf.seg", "3\r\n-1\r\n7")
write("seg", "gzip.seg.gz", gz(b"1\n1\n2\n2\n0\n"))

# --- VDB (FuzzVdb.cpp): magic + a grid recipe, and bytes without the magic ----
magic = bytes([0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0])
for i, recipe in enumerate([bytes(range(1, 60)), bytes(range(200, 255)) * 2, bytes([7] * 80), bytes([1, 0, 2, 3] * 30)]):
    write("vdb", "recipe-%d" % i, magic + recipe)
write("vdb", "not-vdb", b"VDB but not the magic number")
