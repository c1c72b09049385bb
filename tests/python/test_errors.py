"""Bad input: the documented exceptions, the engine's one-line messages,
and nothing printed to stdout."""
import os
import pathlib

import numpy as np
import pytest

import skelseg


def check_quiet(capfd):
    out, _ = capfd.readouterr()
    assert out == ""


def test_a_2d_array_is_a_value_error(capfd):
    with pytest.raises(ValueError, match=r"^mask: must be a 3-D array, got 2-D of shape \(4, 5\)$"):
        skelseg.segment(np.ones((4, 5), dtype=bool))
    check_quiet(capfd)


def test_an_empty_array_is_a_value_error(capfd):
    with pytest.raises(ValueError, match=r"^mask: grid size 0 along axis 1 is not positive$"):
        skelseg.segment(np.ones((3, 0, 5), dtype=np.uint8))
    check_quiet(capfd)


def test_nan_is_a_value_error_naming_the_first_nan(capfd):
    mask = np.zeros((6, 7, 8), dtype=np.float32)
    mask[2:5, 2:5, 2:5] = 1.0
    mask[4, 1, 3] = np.nan
    mask[1, 5, 6] = np.nan
    with pytest.raises(ValueError, match=r"^mask: NaN at index \[4, 1, 3\]"):
        skelseg.segment(mask)
    check_quiet(capfd)


def test_a_mask_over_the_memory_limit_is_a_memory_error(capfd, figure_mask):
    with pytest.raises(MemoryError, match=r"^mask: needs about .* over the limit of 1.00 MB "
                                          r"\(max_memory\)$"):
        skelseg.segment(figure_mask, max_memory="1M")
    check_quiet(capfd)


def test_a_grid_over_the_voxel_cap_is_a_value_error_without_reading_it(capfd):
    # A broadcast array: 8.6e9 voxels, no memory behind them.
    huge = np.broadcast_to(np.uint8(1), (2048, 2048, 2048))
    with pytest.raises(ValueError, match=r"^mask: grid of 2048x2048x2048 voxels is over the limit"):
        skelseg.segment(huge)
    check_quiet(capfd)


def test_the_time_limit_is_a_timeout_error(capfd, shapes):
    # A whole run takes 0.5 s on a fast machine: far longer than the limit.
    mask = skelseg.read_volume(shapes.nrrd("figure", 224, 1))
    with pytest.raises(TimeoutError, match=r"^time limit reached$"):
        skelseg.segment(mask, time_limit=0.02)
    check_quiet(capfd)


@pytest.mark.parametrize("dtype", [np.complex64, object, "U3"])
def test_unsupported_dtypes_are_type_errors(capfd, dtype):
    with pytest.raises(TypeError, match=r"^mask: dtype .* is not supported"):
        skelseg.segment(np.zeros((3, 3, 3), dtype=dtype))
    check_quiet(capfd)


@pytest.mark.parametrize("kwargs,message", [
    ({"tau": "3x"}, r"^tau '3x' is not a number of voxels or a percentage"),
    ({"tau": "150%"}, r"^tau '150%' is out of range"),
    ({"sigma_min": 1.5}, r"^sigma_min: Value 1.5 not in range 0.000000 to 1.000000$"),
    ({"mode": "magic"}, r"^mode: magic not in \{junction-rule,junctions\}$"),
    ({"threads": 0}, r"^threads: Value 0 not in range 1 to 1024$"),
    # Not "Value 2.5 not in range 1 to 1024": the value is in the range.
    ({"threads": 2.5}, r"^threads: '2\.5' is not an integer$"),
    ({"time_limit": -1}, r"^time_limit: '-1' is not a positive number of seconds$"),
    ({"spacing": (1, 0, 1)}, r"spacing must be three positive finite numbers"),
    ({"max_memory": "4X"}, r"^max_memory '4X': unknown unit 'X'$"),
])
def test_bad_parameters_are_value_errors(capfd, kwargs, message):
    with pytest.raises(ValueError, match=message):
        skelseg.segment(np.ones((5, 5, 5), dtype=bool), **kwargs)
    check_quiet(capfd)


def test_unreadable_files_are_value_errors_naming_the_file(capfd, tmp_path):
    missing = tmp_path / "missing.nrrd"
    with pytest.raises(ValueError, match=rf"^{missing}: no such file$"):
        skelseg.read_volume(missing)
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    with pytest.raises(ValueError, match=rf"^{bad}: "):
        skelseg.read_mesh(bad)
    # A directory is said to be one, whatever its name's extension says.
    for directory in (tmp_path, tmp_path / "folder.off"):
        directory.mkdir(exist_ok=True)
        with pytest.raises(ValueError, match=rf"^{directory}: is a directory, not a file$"):
            skelseg.read_mesh(directory)
    check_quiet(capfd)


def test_file_names_that_are_not_utf8_are_named_in_the_message(capfd, tmp_path):
    # The engine's message held the byte 0xe9, which Python's strict decoding
    # refused: a ValueError with no text at all.
    folder = bytes(tmp_path)
    for read, name in ((skelseg.read_volume, b"caf\xe9.nrrd"), (skelseg.read_mesh, b"caf\xe9.off"),
                       (skelseg.read_seg, b"caf\xe9.seg")):
        path = folder + b"/" + name
        expected = os.fsdecode(folder) + "/" + name.decode("utf-8", "backslashreplace")
        with pytest.raises(ValueError) as raised:
            read(path)
        assert str(raised.value) == expected + ": no such file"
    check_quiet(capfd)


def test_a_path_with_a_nul_byte_is_refused_as_open_refuses_it(capfd, tmp_path):
    # The system reads a path up to its NUL: "f.nrrd\0.off" read f.nrrd.
    (tmp_path / "f.nrrd").write_bytes(
        b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n" + bytes(8))
    assert skelseg.read_volume(tmp_path / "f.nrrd").shape == (2, 2, 2)
    for read, name in ((skelseg.read_volume, "f.nrrd\0.nrrd"), (skelseg.read_mesh, "f.nrrd\0.off"),
                       (skelseg.read_seg, "f.nrrd\0.seg")):
        for path in (str(tmp_path / name), os.fsencode(str(tmp_path / name))):
            with pytest.raises(ValueError, match="embedded null byte"):
                read(path)
    check_quiet(capfd)


def test_a_tau_past_any_voxel_count_gives_one_segment(capfd):
    # tau 1e20 and more hung in the labelling (the lone segment's area was
    # set past tau in a 64-bit integer), ignoring Ctrl-C too.
    mask = np.zeros((16, 16, 20), bool)
    mask[4:12, 4:12, 2:12] = True
    mask[7:9, 7:9, 12:19] = True
    for tau in (1e20, 1e300, [1e20, 1e300]):
        result = skelseg.segment(mask, tau=tau)
        assert result.n_segments == 1
        assert np.array_equal(result.labels != 0, mask)
    check_quiet(capfd)


def test_bad_mesh_arrays_are_value_errors(capfd):
    vertices = np.zeros((3, 3))
    with pytest.raises(ValueError, match=r"^mesh: face 0 uses vertex 7 of 3$"):
        skelseg.segment_mesh(vertices, np.array([[0, 1, 7]]))
    with pytest.raises(ValueError, match=r"^mesh: vertex 1 has a coordinate that is not finite$"):
        skelseg.segment_mesh(np.array([[0, 0, 0], [np.inf, 0, 0], [0, 1, 0]]),
                             np.array([[0, 1, 2]]))
    with pytest.raises(ValueError, match=r"faces must have shape \(F, k\) with k >= 3"):
        skelseg.segment_mesh(vertices, np.array([[0, 1]]))
    # Complex vertices lost their imaginary parts with only a ComplexWarning.
    with pytest.raises(TypeError, match=r"^mesh: vertices must be real numbers, not complex128$"):
        skelseg.segment_mesh(vertices + 1j, np.array([[0, 1, 2]]))
    # An unsigned index past int64 was cast to a negative one and named so.
    huge = np.array([[0, 1, 2**63]], dtype=np.uint64)
    with pytest.raises(ValueError, match=r"^mesh: faces: index 9223372036854775808 is out of "
                                         r"range$"):
        skelseg.segment_mesh(vertices, huge)
    with pytest.raises(ValueError, match=r"^mesh: triangle_face: index 9223372036854775808 is "
                                         r"out of range$"):
        skelseg.segment_mesh(vertices, np.array([[0, 1, 2]]), triangle_face=huge[0, 2:])
    check_quiet(capfd)


@pytest.mark.parametrize("bad", [np.array([0.0, 0.0, 1.0, 1.0]),   # whole numbers: no cast either
                                 np.array([0.0, 0.5, 1.0, 1.5]),
                                 [0.0, 0.0, 1.0, 1.0],
                                 np.array([True, True, False, False]),
                                 np.array(["0", "0", "1", "1"])])
def test_labels_that_are_not_integers_are_type_errors(capfd, bad):
    labels = np.array([0, 0, 1, 1])
    dtype = np.asarray(bad).dtype
    with pytest.raises(TypeError, match=rf"^labels must be integers, not {dtype} "):
        skelseg.score(bad, labels)
    with pytest.raises(TypeError, match=rf"^human_labels must be integers, not {dtype} "):
        skelseg.score(labels, bad)
    with pytest.raises(TypeError, match=rf"^human_labels must be integers, not {dtype} "):
        skelseg.score(labels, [labels, bad])
    with pytest.raises(TypeError, match=rf"^frame_labels must be integers, not {dtype} "):
        skelseg.sequence_consensus([labels, bad])
    vertices = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    with pytest.raises(TypeError, match=rf"^mesh: triangle_face must be integers, not {dtype} "):
        skelseg.segment_mesh(vertices, faces, triangle_face=bad, resolution=16)
    with pytest.raises(TypeError, match=r"^mesh: faces must be integers, not float64 "):
        skelseg.segment_mesh(vertices, faces.astype(float), resolution=16)
    check_quiet(capfd)


def test_integer_labels_of_any_width_are_accepted():
    labels = np.array([0, 0, 1, 1])
    for dtype in (np.int8, np.uint16, np.int32, np.uint64):
        assert skelseg.score(labels.astype(dtype), labels).rand_index_error == 0
    # Empty lists (float64 to numpy) have nothing to cast: the engine's own
    # ValueError, not a TypeError.
    with pytest.raises(ValueError, match=r"^segmentations without faces cannot be compared$"):
        skelseg.score([], [[]])


def test_meshes_without_area_or_out_of_scale_are_value_errors(capfd):
    triangle = np.array([[0, 1, 2]])
    with pytest.raises(ValueError, match=r"^mesh: its only face has zero area"):
        skelseg.segment_mesh(np.array([[0., 0, 0], [1, 0, 0], [2, 0, 0]]), triangle,
                             resolution=16)
    with pytest.raises(ValueError, match=r"^mesh: the mesh is flat \(every vertex of its faces "
                                         r"lies in one plane\): it encloses no volume"):
        skelseg.segment_mesh(np.array([[1., 0, 0], [0, 1, 0], [0, 0, 1]]), triangle,
                             resolution=16)
    with pytest.raises(ValueError, match=r"^mesh: cannot voxelise the mesh: .* too large"):
        skelseg.segment_mesh(np.array([[0., 0, 0], [1e300, 0, 0], [0, 1e300, 0]]), triangle,
                             resolution=16)
    with pytest.raises(ValueError, match=r"^sigma_min: Value nan is not a number$"):
        skelseg.segment_mesh(np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0]]), triangle,
                             resolution=16, sigma_min=float("nan"))
    check_quiet(capfd)


CUBE_VERTICES = np.array([[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                          [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]])
CUBE_FACES = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                       [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])


def test_faces_collapsed_to_one_vertex_are_named_as_such(capfd):
    """The cube's 8 distinct vertices with every face (0, 0, 0): the message
    said "all its vertices lie at one point", which they do not."""
    with pytest.raises(ValueError, match=r"^mesh: cannot voxelise the mesh: the vertices its "
                                         r"faces use all lie at one point \(no face has an "
                                         r"area\)$"):
        skelseg.segment_mesh(CUBE_VERTICES, np.array([[0, 0, 0]] * 12), resolution=16)
    check_quiet(capfd)


def test_a_far_vertex_no_face_uses_changes_nothing_but_a_warning(capfd):
    """A vertex no face uses, 1e7 away, made every face of the cube "zero
    area" (ValueError)."""
    plain = skelseg.segment_mesh(CUBE_VERTICES, CUBE_FACES, resolution=16)
    with pytest.warns(skelseg.SkelsegWarning,
                      match=r"^mesh: 1 vertex is used by no face; it is ignored$"):
        stray = skelseg.segment_mesh(np.vstack([CUBE_VERTICES, [[1e7, 0, 0]]]), CUBE_FACES,
                                     resolution=16)
    assert np.array_equal(stray.face_labels, plain.face_labels)
    assert stray.report["warnings"] == [
        "mesh: 1 vertex is used by no face; it is ignored"]
    check_quiet(capfd)


def test_mesh_in_tiny_units_is_segmented(capfd):
    """A 0.1 mm tetrahedron in metres: OpenVDB refuses such voxel sizes; the
    voxeliser measures in voxels instead."""
    vertices = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    tiny = skelseg.segment_mesh(vertices * 1e-4, faces, resolution=16)
    plain = skelseg.segment_mesh(vertices, faces, resolution=16)
    assert np.array_equal(tiny.face_labels, plain.face_labels)


def _binvox_of_zeros(path, side):
    """A valid binvox of side^3 empty voxels: runs of 255, a few bytes per
    16 million voxels of the grid it claims."""
    runs, left = bytearray(), side ** 3
    while left:
        count = min(255, left)
        runs += bytes((0, count))
        left -= count
    path.write_bytes(f"#binvox 1\ndim {side} {side} {side}\ndata\n".encode() + bytes(runs))


def test_read_volume_refuses_a_grid_over_max_memory_before_allocating_it(capfd, tmp_path):
    # 400^3 voxels (64 MB of mask) from a file of 1 MB: the CLI's check, on
    # the mask alone (reading is all the call does).
    path = tmp_path / "large.binvox"
    _binvox_of_zeros(path, 400)
    with pytest.raises(MemoryError, match=rf"^{path}: its grid of 400 x 400 x 400 voxels needs "
                                          r"64.00 MB, over the limit of 10.00 MB \(max_memory\)$"):
        skelseg.read_volume(path, max_memory="10M")
    with pytest.raises(MemoryError, match=r"over the limit of 1.00 MB \(max_memory\)$"):
        skelseg.read_volume(path, max_memory=10**6)
    # The control: the same file within the limit (and by default, 75% of
    # physical memory) is read.
    assert skelseg.read_volume(path, max_memory="100M").shape == (400, 400, 400)
    assert not skelseg.read_volume(path).any()
    check_quiet(capfd)


def test_read_volume_keywords_of_the_wrong_kind_are_one_line(capfd, tmp_path):
    path = tmp_path / "small.binvox"
    _binvox_of_zeros(path, 4)
    for keywords, error, message in (
            ({"grid": 5}, TypeError, r"^grid must be a string or None, not 5$"),
            ({"with_spacing": "x"}, TypeError, r"^with_spacing must be True or False, not 'x'$"),
            ({"time_limit": -1}, ValueError,
             r"^time_limit must be a positive number of seconds, not -1$"),
            ({"time_limit": "soon"}, ValueError,
             r"^time_limit must be a positive number of seconds, not 'soon'$"),
            ({"max_memory": "12Q"}, ValueError, r"^max_memory '12Q': unknown unit 'Q'$"),
            ({"max_memory": [1]}, TypeError, r"^max_memory must be a number or a string")):
        with pytest.raises(error, match=message):
            skelseg.read_volume(path, **keywords)
    assert skelseg.read_volume(path, time_limit=30, max_memory="1G").shape == (4, 4, 4)
    check_quiet(capfd)


def test_spacing_vertices_and_mask_of_the_wrong_kind_are_refused(capfd):
    mask = np.zeros((8, 8, 8), dtype=bool)
    mask[2:6, 2:6, 2:6] = True
    # A string has three characters that convert: "111" was (1, 1, 1).
    with pytest.raises(TypeError, match=r"^spacing must be three numbers, not '111'$"):
        skelseg.segment(mask, spacing="111")
    with pytest.raises(TypeError, match=r"^spacing must be three numbers"):
        skelseg.segment(mask, spacing=(1, 1, True))
    # One number was Python's own "object of type 'int' has no len()".
    for single in (2, 2.0, np.float64(2)):
        with pytest.raises(TypeError, match=r"^spacing must be three numbers, not 2"):
            skelseg.segment(mask, spacing=single)
    # A file name where the mask goes was "got 0-D of shape ()".
    for path in ("f.nrrd", b"f.nrrd", pathlib.Path("f.nrrd")):
        with pytest.raises(TypeError, match=r"^mask must be a 3-D array, not the path .*"
                                            r"read_volume\(\) first$"):
            skelseg.segment(path)
    # The volume headers' rule: a voxel volume past the doubles' range.
    with pytest.raises(ValueError, match=r"^spacing: the voxel volume .* is outside the range"):
        skelseg.segment(mask, spacing=(1e-300,) * 3)
    with pytest.raises(TypeError, match=r"^mask must be a 3-D array, not None$"):
        skelseg.segment(None)
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    with pytest.raises(TypeError, match=r"^mesh: vertices must be real numbers, not <U"):
        skelseg.segment_mesh(vertices.astype(str), faces, resolution=16)
    # The controls: numbers in any sequence are taken.
    assert skelseg.segment(mask, spacing=np.array([1.0, 2.0, 3.0])).n_segments == 1
    assert skelseg.segment(mask, spacing=[1, 2, 3]).n_segments == 1
    check_quiet(capfd)


def test_more_segments_than_uint16_labels_hold_is_a_value_error():
    # 41^3 separate voxels, one segment each: the CLI's exit 2 naming the
    # input (was RuntimeError, the CLI's exit 1 "internal error"); refused
    # from the count of objects, before any is segmented.
    mask = np.zeros((82, 82, 82), dtype=bool)
    mask[::2, ::2, ::2] = True
    with pytest.raises(ValueError, match=r"^mask: the volume has 68921 objects, so at least "
                                         r"68921 segments, more than a 16-bit label volume"):
        skelseg.segment(mask, threads=1)


def test_a_value_given_in_the_wrong_place_is_shown_cut_to_one_short_line(capfd):
    # A file's contents where the mask goes wrote all 32 MB of them into the
    # TypeError, and a long list as spacing or a flag wrote its every entry.
    mask = np.zeros((8, 8, 8), dtype=bool)
    mask[2:6, 2:6, 2:6] = True
    cases = [
        (lambda: skelseg.segment(bytes(2_000_000)),
         r"^mask must be a 3-D array, not 2000000 bytes of data: read a file with"),
        (lambda: skelseg.segment("x" * 1_000_000), r"^mask must be a 3-D array, not the path 'xxx"),
        (lambda: skelseg.segment(mask, spacing=["1"] * 100_000),
         r"^spacing must be three numbers, not \['1', '1'"),
        (lambda: skelseg.segment(mask, joints=[True] * 100_000),
         r"^joints must be True or False, not \[True"),
        (lambda: skelseg.segment(mask, tau=[["3%"] * 100_000]), r"^tau must be a number or a"),
        (lambda: skelseg.read_volume("f.nrrd", grid=["g"] * 100_000), r"^grid must be a string"),
    ]
    for call, start in cases:
        with pytest.raises(TypeError, match=start) as raised:
            call()
        message = str(raised.value)
        assert "\n" not in message
        assert len(message) < 300, message[:300]
    check_quiet(capfd)
