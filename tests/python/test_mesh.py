"""segment_mesh, read_mesh, read_seg and score: equal to the CLI."""
import json

import numpy as np
import pytest

import skelseg
from conftest import run_cli, shared_data


def box(lo, hi, first):
    """A closed box: 8 vertices, 6 outward quads (vertex indices from `first`)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    vertices = [(x, y, z) for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return vertices, [[first + i for i in q] for q in quads]


@pytest.fixture(scope="module")
def body_and_limb(tmp_path_factory):
    """A thick box with a thin box through its top: two overlapping closed pieces,
    as quads, and the same mesh as an OFF file."""
    body_v, body_f = box((0, 0, 0), (4, 4, 4), 0)
    limb_v, limb_f = box((1.5, 1.5, 3), (2.5, 2.5, 10), 8)
    vertices = np.array(body_v + limb_v, dtype=float)
    quads = np.array(body_f + limb_f)
    path = tmp_path_factory.mktemp("mesh") / "body-limb.off"
    lines = ["OFF", f"{len(vertices)} {len(quads)} 0"]
    lines += [" ".join(repr(c) for c in v) for v in vertices]
    lines += ["4 " + " ".join(str(i) for i in q) for q in quads]
    path.write_text("\n".join(lines) + "\n")
    return vertices, quads, path


def cli_face_labels(shapes, mesh_path, resolution, *extra):
    outdir = shapes.directory / f"{mesh_path.stem}-{resolution}-out"
    run_cli("segment", mesh_path, "-o", outdir, "-q", "--no-preview", "--force",
            "--resolution", resolution, *extra)
    return outdir, skelseg.read_seg(outdir / "segmentation.seg")


def test_quad_mesh_face_labels_equal_the_cli_segmentation_seg(shapes, body_and_limb):
    vertices, quads, path = body_and_limb
    with pytest.warns(skelseg.SkelsegWarning, match=r"^mesh: mesh has 2 separate pieces"):
        result = skelseg.segment_mesh(vertices, quads, resolution=64)
    outdir, expected = cli_face_labels(shapes, path, 64)
    assert result.face_labels.dtype == np.int32
    assert result.face_labels.shape == (len(quads),)
    np.testing.assert_array_equal(result.face_labels, expected)
    assert len(np.unique(result.face_labels)) == 2  # the body and the limb
    report = json.loads((outdir / "report.json").read_text())
    assert result.report["face_segments"] == report["face_segments"] == 2
    assert result.report["segment_count"] == report["segment_count"]
    for key in ("faces", "vertices", "resolution", "mesh_closed", "mesh_pieces"):
        assert result.report["input"][key] == report["input"][key], key


@pytest.mark.filterwarnings("ignore:mesh. mesh has 2 separate pieces")
def test_self_overlap_clearance_reaches_the_report_and_is_checked(shapes, body_and_limb):
    vertices, quads, path = body_and_limb
    result = skelseg.segment_mesh(vertices, quads, resolution=32, self_overlap_clearance=2)
    assert result.report["input"]["self_overlap_clearance"] == 2
    assert skelseg.segment_mesh(vertices, quads, resolution=32).report["input"][
        "self_overlap_clearance"] == 4
    outdir, expected = cli_face_labels(shapes, path, 32, "--self-overlap-clearance", "2")
    np.testing.assert_array_equal(result.face_labels, expected)
    report = json.loads((outdir / "report.json").read_text())
    assert report["input"]["self_overlap_clearance"] == 2
    for bad in (1, 5):
        with pytest.raises(ValueError, match=rf"^self_overlap_clearance: Value {bad} not in "
                                             r"range 2 to 4$"):
            skelseg.segment_mesh(vertices, quads, resolution=32, self_overlap_clearance=bad)
    with pytest.raises(ValueError, match="^self_overlap_clearance: '2.5' is not an integer$"):
        skelseg.segment_mesh(vertices, quads, resolution=32, self_overlap_clearance=2.5)


@pytest.mark.filterwarnings("ignore:mesh. mesh has 2 separate pieces")
def test_read_mesh_gives_triangles_and_their_faces(body_and_limb):
    vertices, quads, path = body_and_limb
    mesh = skelseg.read_mesh(path)
    np.testing.assert_array_equal(mesh.vertices, vertices)
    assert mesh.face_count == len(quads)
    assert mesh.faces.shape == (2 * len(quads), 3)
    np.testing.assert_array_equal(mesh.triangle_face, np.repeat(np.arange(len(quads)), 2))
    from_file = skelseg.segment_mesh(mesh.vertices, mesh.faces, triangle_face=mesh.triangle_face,
                                     resolution=64)
    from_quads = skelseg.segment_mesh(vertices, quads, resolution=64)
    np.testing.assert_array_equal(from_file.face_labels, from_quads.face_labels)
    # Without triangle_face every triangle is a face; both halves of a quad agree.
    per_triangle = skelseg.segment_mesh(mesh.vertices, mesh.faces, resolution=64).face_labels
    np.testing.assert_array_equal(per_triangle, np.repeat(from_quads.face_labels, 2))


def test_an_open_mesh_warns_and_still_segments(body_and_limb):
    vertices, quads, _ = body_and_limb
    with pytest.warns(skelseg.SkelsegWarning, match=r"^mesh: mesh is not closed"):
        result = skelseg.segment_mesh(vertices, quads[1:], resolution=32)
    assert result.face_labels.shape == (len(quads) - 1,)
    assert any("not closed" in w for w in result.report["warnings"])


def write_triangle_off(path, vertices, triangles):
    lines = ["OFF", f"{len(vertices)} {len(triangles)} 0"]
    lines += [" ".join(repr(float(c)) for c in v) for v in vertices]
    lines += ["3 " + " ".join(str(i) for i in t) for t in triangles]
    path.write_text("\n".join(lines) + "\n")


def cli_report_with_the_same_labels(shapes, name, vertices, triangles, result):
    """Writes the mesh as NAME.off, segments it with the CLI at 32, checks
    that the CLI labels its faces as the module did, and gives the CLI's
    report."""
    path = shapes.directory / f"{name}.off"
    write_triangle_off(path, vertices, triangles)
    outdir, expected = cli_face_labels(shapes, path, 32)
    np.testing.assert_array_equal(result.face_labels, expected)
    return json.loads((outdir / "report.json").read_text())


def test_a_fin_is_left_out_of_the_voxel_model_as_in_the_cli(shapes, body_and_limb):
    """A triangle standing on an edge of the body (a fin) keeps the mesh open
    as read; without it the mesh is closed, and both the module and the CLI
    voxelise it so and label every face."""
    vertices, quads, _ = body_and_limb
    triangles = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    fin_vertices = np.vstack([vertices, [(2.0, -0.2, -0.2)]])
    triangles.append((0, 1, len(vertices)))  # on the body's edge (0,0,0)-(4,0,0)
    triangles = np.array(triangles)
    with pytest.warns(skelseg.SkelsegWarning, match=r"^mesh: 1 face lies on fins"):
        result = skelseg.segment_mesh(fin_vertices, triangles, resolution=32)
    assert result.report["input"]["mesh_fin_faces"] == 1
    assert result.report["input"]["mesh_closed"] is True
    assert not any("not closed" in w for w in result.report["warnings"])
    assert result.face_labels.shape == (len(triangles),)
    assert result.face_labels[-1] == result.face_labels[0]  # the face it stands on

    report = cli_report_with_the_same_labels(shapes, "body-limb-fin", fin_vertices, triangles,
                                             result)
    assert report["input"]["mesh_fin_faces"] == 1


def grid_box(n):
    """The surface of the box [0, n]^3 in unit squares, two outward triangles
    each: one closed piece."""
    index, vertices, triangles = {}, [], []

    def vertex(p):
        if p not in index:
            index[p] = len(vertices)
            vertices.append(p)
        return index[p]

    for axis in range(3):
        for side in (0, n):
            for i in range(n):
                for j in range(n):
                    corners = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = [0, 0, 0]
                        p[axis], p[(axis + 1) % 3], p[(axis + 2) % 3] = side, i + di, j + dj
                        corners.append(vertex(tuple(p)))
                    if side == 0:
                        corners.reverse()
                    a, b, c, d = corners
                    triangles += [(a, b, c), (a, c, d)]
    return np.array(vertices, dtype=float), np.array(triangles)


def test_a_small_hole_is_capped_in_the_voxel_model_as_in_the_cli(shapes):
    """One triangle missing of 192: the mesh as read is open, capped it is
    closed, and both the module and the CLI voxelise it as the closed box and
    label the faces given."""
    vertices, triangles = grid_box(4)
    with_hole = triangles[:-1]
    with pytest.warns(skelseg.SkelsegWarning, match=r"^mesh: the mesh has 1 hole"):
        result = skelseg.segment_mesh(vertices, with_hole, resolution=32)
    assert result.report["input"]["mesh_holes_capped"] == 1
    assert result.report["input"]["mesh_closed"] is True
    assert not any("not closed" in w for w in result.report["warnings"])
    assert result.face_labels.shape == (len(with_hole),)
    closed = skelseg.segment_mesh(vertices, triangles, resolution=32)
    assert closed.report["input"]["mesh_holes_capped"] == 0
    assert result.report["counts"]["object_voxels"] == closed.report["counts"]["object_voxels"]

    report = cli_report_with_the_same_labels(shapes, "grid-box-hole", vertices, with_hole, result)
    assert report["input"]["mesh_holes_capped"] == 1


def open_cup(low, side):
    """A cube of side `side` at `low` without its top face: ten triangles
    whose opening is a fifth of them, too large to cap (a fin)."""
    vertices = [[low[0] + side * (c & 1), low[1] + side * ((c >> 1) & 1),
                 low[2] + side * ((c >> 2) & 1)] for c in range(8)]
    quads = [(0, 2, 3, 1), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7), (2, 0, 4, 6)]
    triangles = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    return np.array(vertices, dtype=float), np.array(triangles)


def test_a_hole_and_an_open_cup_are_capped_and_dropped_as_in_the_cli(shapes):
    """The box missing one triangle with a small cup beside it: neither rule
    takes the mesh alone; together the cup is dropped as a fin and the hole
    capped, and both the module and the CLI voxelise the closed box."""
    vertices, triangles = grid_box(4)
    cup_vertices, cup_triangles = open_cup((6.0, 1.0, 1.0), 0.3)
    both_vertices = np.vstack([vertices, cup_vertices])
    both = np.vstack([triangles[:-1], cup_triangles + len(vertices)])
    with pytest.warns(skelseg.SkelsegWarning, match=r"^mesh: 10 faces lie on fins .* 1 hole"):
        result = skelseg.segment_mesh(both_vertices, both, resolution=32)
    assert result.report["input"]["mesh_fin_faces"] == 10
    assert result.report["input"]["mesh_holes_capped"] == 1
    assert result.report["input"]["mesh_closed"] is True
    assert result.face_labels.shape == (len(both),)
    closed = skelseg.segment_mesh(vertices, triangles, resolution=32)
    assert result.report["counts"]["object_voxels"] == closed.report["counts"]["object_voxels"]

    report = cli_report_with_the_same_labels(shapes, "grid-box-hole-cup", both_vertices, both,
                                             result)
    assert report["input"]["mesh_fin_faces"] == 10
    assert report["input"]["mesh_holes_capped"] == 1


def test_flipped_faces_are_turned_in_the_voxel_model_as_in_the_cli(shapes):
    """A patch of the box wound the wrong way: the module and the CLI turn it,
    say so, and voxelise the box as the one wound right."""
    vertices, triangles = grid_box(4)
    flipped = triangles.copy()
    patch = np.arange(10, 16)
    flipped[patch] = flipped[patch][:, [0, 2, 1]]
    with pytest.warns(skelseg.SkelsegWarning, match=r"^mesh: 6 faces were wound against"):
        result = skelseg.segment_mesh(vertices, flipped, resolution=32)
    assert result.report["input"]["mesh_faces_turned"] == 6
    assert not any("wound against each other" in w for w in result.report["warnings"])
    wound = skelseg.segment_mesh(vertices, triangles, resolution=32)
    assert wound.report["input"]["mesh_faces_turned"] == 0
    np.testing.assert_array_equal(result.face_labels, wound.face_labels)

    report = cli_report_with_the_same_labels(shapes, "grid-box-flipped", vertices, flipped, result)
    assert report["input"]["mesh_faces_turned"] == 6


def psb_model(number):
    data = shared_data() / "psb"
    off = data / "off" / f"{number}.off"
    humans = sorted((data / "seg" / str(number)).glob("*.seg*"))
    if not off.exists() or not humans:
        pytest.skip(f"no PSB model {number} in {data}")
    return off, humans


def test_psb_model_labels_and_scores_equal_the_cli(shapes):
    off, humans = psb_model(1)
    mesh = skelseg.read_mesh(off)
    result = skelseg.segment_mesh(mesh.vertices, mesh.faces, triangle_face=mesh.triangle_face,
                                  resolution=64)
    outdir, expected = cli_face_labels(shapes, off, 64)
    np.testing.assert_array_equal(result.face_labels, expected)

    human_labels = [skelseg.read_seg(h) for h in humans]
    score = skelseg.score(result.face_labels, human_labels, face_areas=mesh.face_areas())
    cli = json.loads(run_cli("score", off, outdir / "segmentation.seg", *humans, "--json").stdout)
    for field in ("rand_index_error", "hamming_distance", "missing_rate", "false_alarm_rate"):
        assert getattr(score, field) == pytest.approx(cli["mean"][field], abs=1e-12), field
    assert len(score.per_human) == len(humans)
    assert score.per_human[0].rand_index_error == \
        pytest.approx(cli["humans"][0]["rand_index_error"], abs=1e-12)


def test_score_of_identical_partitions_is_zero_and_of_one_segment_is_not():
    labels = np.array([0, 0, 1, 1, 2, 2, 2])
    same = skelseg.score(labels + 5, labels)  # label values do not matter
    assert same.rand_index_error == 0 and same.hamming_distance == 0
    whole = skelseg.score(np.zeros(7, int), [labels, labels])
    assert whole.rand_index_error > 0 and whole.missing_rate == 0
    assert len(whole.per_human) == 2
    with pytest.raises(ValueError):
        skelseg.score(labels, labels[:3])


def assert_faces_nest(fine, coarse):
    """Faces with one label at the finer level share one label at the coarser."""
    pairs = np.unique(np.stack([fine, coarse], axis=1), axis=0)
    assert len(np.unique(pairs[:, 0])) == len(pairs), "a fine face label spans coarse labels"


@pytest.mark.parametrize("joints", [False, True])
def test_mesh_levels_give_nested_face_labels_and_cuts_equal_to_the_cli(shapes, joints):
    """tau=[...] on a mesh: per level face labels (levels/k/segmentation.seg)
    and cut loops (levels/k/cuts.ply), nested level to level; joints=True adds
    the joint level below the finest."""
    off, _ = psb_model(1)
    mesh = skelseg.read_mesh(off)
    taus = ["1%", "3%", "9%"]
    result = skelseg.segment_mesh(mesh.vertices, mesh.faces, triangle_face=mesh.triangle_face,
                                  resolution=64, tau=taus, joints=joints)
    assert len(result.levels) == len(taus) + (1 if joints else 0)
    assert [level.joints for level in result.levels] == \
        [joints] + [False] * (len(result.levels) - 1)
    np.testing.assert_array_equal(result.levels[-1].face_labels, result.face_labels)
    for k in range(len(result.levels) - 1):
        fine, coarse = result.levels[k], result.levels[k + 1]
        assert len(fine.face_labels) == mesh.face_count == len(coarse.face_labels)
        assert_faces_nest(fine.face_labels, coarse.face_labels)
        assert len(np.unique(fine.face_labels)) >= len(np.unique(coarse.face_labels))
        # A coarser cut is a cut of every finer level.
        fine_cuts = {c.tobytes() for c in fine.cuts}
        assert all(c.tobytes() in fine_cuts for c in coarse.cuts)
    assert len(np.unique(result.levels[0].face_labels)) > len(np.unique(result.face_labels))
    extra = ("--joints",) if joints else ()
    outdir, top = cli_face_labels(shapes, off, 64, "--tau", ",".join(taus), *extra)
    np.testing.assert_array_equal(result.face_labels, top)
    for k, level in enumerate(result.levels):
        seg = skelseg.read_seg(outdir / "levels" / str(k) / "segmentation.seg")
        np.testing.assert_array_equal(level.face_labels, seg)
        assert len(level.cuts) == len(read_ply_loops(outdir / "levels" / str(k) / "cuts.ply"))


def read_ply_loops(path):
    """The loop indices of a cuts.ply (binary little-endian, as PlyWriter writes it)."""
    data = path.read_bytes()
    header, body = data.split(b"end_header\n", 1)
    vertices = int([line for line in header.decode().splitlines()
                    if line.startswith("element vertex")][0].split()[2])
    records = np.frombuffer(body[:vertices * 16], dtype=[("xyz", "<f4", 3), ("cut", "<i4")])
    return np.unique(records["cut"])


def test_one_tau_with_joints_has_two_levels_and_the_joint_level_on_top(shapes):
    off, _ = psb_model(1)
    mesh = skelseg.read_mesh(off)
    result = skelseg.segment_mesh(mesh.vertices, mesh.faces, triangle_face=mesh.triangle_face,
                                  resolution=64, joints=True)
    plain = skelseg.segment_mesh(mesh.vertices, mesh.faces, triangle_face=mesh.triangle_face,
                                 resolution=64)
    assert len(result.levels) == 2 and result.levels[0].joints
    assert len(plain.levels) == 1
    np.testing.assert_array_equal(result.levels[1].face_labels, plain.face_labels)
    np.testing.assert_array_equal(result.levels[1].labels, plain.labels)
    assert_faces_nest(result.levels[0].face_labels, result.levels[1].face_labels)
    # The result is the joint level (the CLI's top-level files).
    assert result.levels[0].cuts and len(result.cuts) == len(result.levels[0].cuts)


def test_a_mesh_runs_the_cli_input_steps_thin_part_fill_included():
    # PSB 1 at 128: the voxel model first has a handle the mesh has not, and
    # the CLI's second voxelisation with thin parts filled removes it
    # (engine/SegmentSteps.h); equal to the CLI's segmentation.seg
    # (reference outputs, docs/python.md python18).
    off, _ = psb_model(1)
    mesh = skelseg.read_mesh(off)
    result = skelseg.segment_mesh(mesh.vertices, mesh.faces, triangle_face=mesh.triangle_face,
                                  resolution=128)
    assert result.report["input"]["thin_part_fill"] == "kept"
    assert result.report["input"]["voxel_genus"] == result.report["input"]["mesh_genus"] == 0
    assert {s["name"] for s in result.report["stages"]} >= {
        "voxelise", "voxelise with thin parts filled", "genus", "face labels"}
    assert result.n_segments == 6
