"""skelseg.segment on numpy arrays: equal to the CLI, any layout and dtype."""
import json
import pathlib
import subprocess
import zlib

import numpy as np
import pytest

import skelseg
from conftest import cli_binary, read_nrrd

# Generated shapes and sizes: small enough for a quick suite, each with parts.
CLI_CASES = [("figure", 96, 1), ("figure", 96, 2), ("y-arms", 48, 0), ("box-tubes", 48, 0)]


@pytest.mark.parametrize("name,size,pose", CLI_CASES)
def test_labels_equal_the_cli_labels_nrrd_byte_for_byte(shapes, name, size, pose):
    mask = skelseg.read_volume(shapes.nrrd(name, size, pose))
    result = skelseg.segment(mask)
    fields, data = read_nrrd(shapes.cli_output(name, size, pose) / "labels.nrrd")
    assert fields["type"] in ("uint16", "unsigned short", "ushort")
    assert [int(s) for s in fields["sizes"].split()] == list(mask.shape)
    assert result.labels.dtype == np.uint16
    assert result.labels.shape == mask.shape
    assert result.n_segments >= 2
    assert result.labels.tobytes(order="F") == data


def test_report_has_the_cli_report_content(shapes):
    mask = skelseg.read_volume(shapes.nrrd("figure", 96, 1))
    result = skelseg.segment(mask)
    cli = json.loads((shapes.cli_output("figure", 96, 1) / "report.json").read_text())
    assert set(cli) == set(result.report)

    # World positions differ: the file has its own geometry, the array unit spacing.
    def without_positions(items):
        return [{k: v for k, v in item.items() if k != "position"} for item in items]

    for key in ("counts", "objects", "segments", "segment_count", "status", "skelseg_version"):
        assert result.report[key] == cli[key], key
    # Work counters depend on how threads share the path caches; the keys do not.
    assert set(result.report["work"]) == set(cli["work"])
    for key in ("junctions", "critical_points"):
        assert without_positions(result.report[key]) == without_positions(cli[key]), key
    assert result.report["grid"]["size"] == cli["grid"]["size"] == list(mask.shape)
    assert {k: v for k, v in result.report["parameters"].items() if k != "threads"} == \
        {k: v for k, v in cli["parameters"].items() if k != "threads"}
    assert {s["name"] for s in result.report["stages"]} <= {s["name"] for s in cli["stages"]}
    assert result.report["input"] == {"kind": "array", "shape": list(mask.shape), "dtype": "bool",
                                      "spacing": [1.0, 1.0, 1.0], "voxel_steps": [1.0, 1.0, 1.0],
                                      "cubic_voxels": None}
    assert result.n_segments == cli["segment_count"] == len(np.unique(result.labels)) - 1


def build_id(path):
    """engine/Version.h's build id of a file: its size and CRC-32 in hexadecimal."""
    data = pathlib.Path(path).read_bytes()
    return f"{len(data):x}-{zlib.crc32(data):08x}"


def test_report_names_the_build_that_made_it(shapes):
    """The module's report names the module's file, the CLI's the executable
    (not the Python interpreter that loaded the module)."""
    result = skelseg.segment(skelseg.read_volume(shapes.nrrd("figure", 96, 1)))
    cli = json.loads((shapes.cli_output("figure", 96, 1) / "report.json").read_text())
    assert result.report["skelseg_build"] == build_id(skelseg._skelseg.__file__)
    assert cli["skelseg_build"] == build_id(cli_binary())


def test_skeleton_and_cuts_match_the_report(figure_mask):
    result = skelseg.segment(figure_mask)
    skeleton = result.skeleton
    n = len(skeleton)
    assert n == result.report["counts"]["skeleton_points"]
    assert skeleton.points.shape == (n, 3) and skeleton.voxels.shape == (n, 3)
    for field in ("rho_s", "rho_c", "sigma", "junction", "critical", "object"):
        assert getattr(skeleton, field).shape == (n,), field
    assert skeleton.edges.ndim == 2 and skeleton.edges.shape[1] == 2
    assert skeleton.edges.min() >= 0 and skeleton.edges.max() < n
    assert skeleton.junction.sum() == result.report["counts"]["junction_voxels"]
    # Skeleton voxels lie inside the object (unit spacing: points are voxels).
    np.testing.assert_array_equal(skeleton.points, skeleton.voxels)
    x, y, z = skeleton.voxels.T
    assert figure_mask[x, y, z].all()
    assert len(result.cuts) == sum(o["cuts"] for o in result.report["objects"]) > 0
    assert all(c.ndim == 2 and c.shape[1] == 3 and len(c) > 2 for c in result.cuts)


def test_c_and_fortran_order_give_the_same_labels_in_the_callers_axis_order(figure_mask):
    fortran = np.asfortranarray(figure_mask)
    c_order = np.ascontiguousarray(figure_mask)
    assert fortran.flags.f_contiguous and c_order.flags.c_contiguous
    from_fortran = skelseg.segment(fortran).labels
    from_c = skelseg.segment(c_order).labels
    assert from_c.shape == from_fortran.shape == figure_mask.shape
    np.testing.assert_array_equal(from_c, from_fortran)
    # A strided, reversed view is read in place and labels follow its axes.
    view = figure_mask[::-1, :, ::-1]
    np.testing.assert_array_equal(skelseg.segment(view).labels,
                                  skelseg.segment(np.ascontiguousarray(view)).labels)


def test_labels_follow_the_callers_axes_for_a_c_order_volume(figure_mask):
    zyx = np.ascontiguousarray(figure_mask.transpose(2, 1, 0))  # scikit-image's (z, y, x)
    labels = skelseg.segment(zyx).labels
    assert labels.shape == zyx.shape
    assert (labels[zyx] > 0).all()
    assert (labels[~zyx] == 0).all()


@pytest.mark.parametrize("dtype", [np.uint8, np.int32, np.int64, np.uint16, np.float32,
                                   np.float64, np.float16])
def test_bool_and_numeric_dtypes_agree(figure_mask, dtype):
    expected = skelseg.segment(figure_mask).labels
    values = figure_mask.astype(dtype)
    if np.issubdtype(dtype, np.signedinteger):
        values *= -3  # any nonzero value is object
    np.testing.assert_array_equal(skelseg.segment(values).labels, expected)


def test_big_endian_integers_and_floats_agree(figure_mask):
    expected = skelseg.segment(figure_mask).labels
    for dtype in (">i4", ">f8"):
        np.testing.assert_array_equal(skelseg.segment(figure_mask.astype(dtype)).labels,
                                      expected)


def test_spacing_scales_world_coordinates_only(figure_mask):
    plain = skelseg.segment(figure_mask)
    spaced = skelseg.segment(figure_mask, spacing=(0.5, 2.0, 1.5), keep_voxel_aspect=True)
    np.testing.assert_array_equal(spaced.labels, plain.labels)
    np.testing.assert_allclose(spaced.skeleton.points,
                               plain.skeleton.voxels * np.array([0.5, 2.0, 1.5]))
    assert spaced.report["input"]["spacing"] == [0.5, 2.0, 1.5]
    assert spaced.report["input"]["cubic_voxels"] is None
    # Equal steps, whatever their size, are cubic voxels.
    uniform = skelseg.segment(figure_mask, spacing=(0.3, 0.3, 0.3))
    np.testing.assert_array_equal(uniform.labels, plain.labels)
    assert uniform.report["input"]["cubic_voxels"] is None


def write_raw_nrrd(path, mask, spacing):
    header = ("NRRD0004\ntype: uint8\ndimension: 3\nsizes: {} {} {}\n"
              "spacings: {} {} {}\nencoding: raw\n\n").format(*mask.shape, *spacing)
    path.write_bytes(header.encode() + mask.astype(np.uint8).tobytes(order="F"))


def test_anisotropic_spacing_segments_cubic_voxels_as_the_cli_does(figure_mask, tmp_path):
    # Every other slice of the figure, 2.5 times as deep: what a scan gives.
    mask = np.ascontiguousarray(figure_mask[:, :, ::2])
    spacing = (1.0, 1.0, 2.5)
    result = skelseg.segment(mask, spacing=spacing)
    cubic = result.report["input"]["cubic_voxels"]
    assert cubic["grid"] == [mask.shape[0], mask.shape[1], round(mask.shape[2] * 2.5)]
    assert result.report["input"]["voxel_steps"] == [1.0, 1.0, 2.5]
    assert result.labels.shape == mask.shape
    np.testing.assert_array_equal(result.labels > 0, mask > 0)
    assert result.n_segments >= 2
    path = tmp_path / "deep.nrrd"
    write_raw_nrrd(path, mask, spacing)
    subprocess.run([str(cli_binary()), "segment", str(path), "-o", str(tmp_path / "out"), "-q",
                    "--no-preview"], check=True)
    fields, data = read_nrrd(tmp_path / "out" / "labels.nrrd")
    assert result.labels.tobytes(order="F") == data
    cli = json.loads((tmp_path / "out" / "report.json").read_text())
    assert cli["input"]["cubic_voxels"] == cubic


def test_parameters_reach_the_engine(figure_mask):
    result = skelseg.segment(figure_mask, tau=250, sigma_min=0.7, body_ratio=0.5,
                             mode="junctions", threads=1)
    parameters = result.report["parameters"]
    assert parameters["tau"] == "250"
    assert parameters["sigma_min"] == 0.7 and parameters["body_ratio"] == 0.5
    assert parameters["mode"] == "junctions" and parameters["threads"] == 1


def test_an_empty_mask_has_no_segments():
    with pytest.warns(skelseg.SkelsegWarning, match="no object voxels"):
        result = skelseg.segment(np.zeros((8, 9, 10), dtype=bool))
    assert result.n_segments == 0
    assert result.labels.shape == (8, 9, 10) and not result.labels.any()
    assert len(result.skeleton) == 0 and result.cuts == []


def test_results_pickle(figure_mask):
    import pickle
    result = skelseg.segment(figure_mask)
    copy = pickle.loads(pickle.dumps(result))
    np.testing.assert_array_equal(copy.labels, result.labels)
    np.testing.assert_array_equal(copy.skeleton.edges, result.skeleton.edges)
    assert copy.report == result.report and copy.n_segments == result.n_segments


def test_help_shows_the_signature_and_parameters():
    doc = skelseg.segment.__doc__
    for word in ("tau", "sigma_min", "body_ratio", "spacing", "threads", "time_limit",
                 "progress", "ValueError", "MemoryError", "TimeoutError"):
        assert word in doc, word


def test_a_tau_list_gives_nested_levels_equal_to_the_cli(shapes):
    """tau=[...] is the CLI's --tau list: the levels' labels are the files of
    levels/k/, their parents hierarchy.json's, and the result the coarsest."""
    mask = skelseg.read_volume(shapes.nrrd("figure", 96, 0))
    result = skelseg.segment(mask, tau=["9%", "1%", "3%"])
    assert [level.tau for level in result.levels] == ["1%", "3%", "9%"]
    assert result.levels[-1].labels is result.labels
    assert result.levels[-1].parents is None
    out = shapes.cli_output("figure", 96, 0, "--tau", "1%,3%,9%")
    hierarchy = json.loads((out / "hierarchy.json").read_text())
    for k, level in enumerate(result.levels):
        _, data = read_nrrd(out / "levels" / str(k) / "labels.nrrd")
        assert level.labels.tobytes(order="F") == data
        assert level.n_segments == hierarchy["levels"][k]["segment_count"]
        if level.parents is not None:
            assert level.parents.tolist() == [s["parent"] for s in hierarchy["levels"][k]["segments"]]
            # Every voxel's label maps to its coarser label through the parents.
            coarser = result.levels[k + 1].labels
            inside = level.labels > 0
            assert np.array_equal(level.parents[level.labels[inside].astype(int) - 1],
                                  coarser[inside])
    assert result.report["parameters"]["tau"] == "1%,3%,9%"
    # The band search is found at one tau: a hierarchy runs the exhaustive one.
    assert result.report["parameters"]["skeleton_search"] == "exhaustive"
    assert len(result.report["levels"]) == 3
    single = skelseg.segment(mask, tau="9%")
    assert np.array_equal(single.labels, result.labels)
    assert len(single.levels) == 1 and single.levels[0].labels is single.labels


@pytest.mark.parametrize("tau", [[], ["1%", "1%"], ["1%", "x"], ["1%", 250]])
def test_bad_tau_lists_are_refused(figure_mask, tau):
    with pytest.raises(ValueError):
        skelseg.segment(figure_mask, tau=tau)


def test_joints_cut_a_capsule_chain_as_the_cli_does(shapes):
    mask = skelseg.read_volume(shapes.nrrd("capsule-chain", 96))
    assert skelseg.segment(mask).n_segments == 1
    result = skelseg.segment(mask, joints=True)
    assert result.n_segments == 3
    assert result.report["parameters"]["joints"] is True
    assert result.report["joint_cuts"] == 2
    assert [c["kind"] for c in result.report["cuts"]] == ["joint", "joint"]
    _, data = read_nrrd(shapes.cli_output("capsule-chain", 96, 0, "--joints") / "labels.nrrd")
    assert result.labels.tobytes(order="F") == data
    with pytest.raises(TypeError, match="joints"):
        skelseg.segment(mask, joints="yes")


def test_a_level_prints_on_one_line(figure_mask):
    # The dataclass repr printed the level's whole label volume and cuts.
    result = skelseg.segment(figure_mask, tau=["1%", "3%"], threads=1)
    text = repr(result.levels[0])
    assert "\n" not in text and len(text) < 200, text
    assert text.startswith("Level(tau='1%', joints=False, n_segments=")
    assert f"labels=uint16{list(figure_mask.shape)}" in text
