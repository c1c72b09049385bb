"""skelseg: split 3-D shapes into their parts with the junction rule.

The engine of the ``skelseg`` command line, on numpy arrays:

    >>> import numpy as np, skelseg
    >>> mask = skelseg.read_volume("figure.nrrd")       # or any 3-D array
    >>> result = skelseg.segment(mask, tau="3%")
    >>> result.labels.shape == mask.shape, result.n_segments
    (True, 6)

Functions: segment, segment_mesh, read_volume, read_mesh, read_seg, score,
sequence_consensus.
The engine runs without the GIL (several threads may segment at once), can
be cancelled with Ctrl-C, and raises ValueError for bad input, MemoryError
over the memory limit and TimeoutError at the time limit, with the CLI's
one-line messages. docs/python.md in the repository has examples, including
Dask.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import os
import warnings
from typing import Any, Callable, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _skelseg

__all__ = [
    "segment",
    "segment_mesh",
    "read_volume",
    "read_mesh",
    "read_seg",
    "score",
    "sequence_consensus",
    "SegmentationResult",
    "MeshSegmentationResult",
    "Level",
    "Skeleton",
    "Mesh",
    "Score",
    "SequenceConsensus",
    "SkelsegWarning",
]

__version__: str = _skelseg.version

ProgressCallback = Callable[[str, Optional[float]], Any]


class SkelsegWarning(UserWarning):
    """A warning of the engine (e.g. an open mesh whose inside is estimated)."""


@dataclasses.dataclass(frozen=True, eq=False)
class Skeleton:
    """The simplified curve skeleton, every object's in object order.

    Attributes:
        points: (N, 3) float64, world coordinates of the skeleton voxels
            (voxel index times ``spacing`` for arrays; the mesh's coordinates
            for meshes).
        voxels: (N, 3) int32, voxel indices in the array's axis order (may
            be -1 or the extent for objects touching the grid's border).
        edges: (M, 2) int64, pairs of point indices.
        rho_s: (N,) float32, skeleton importance (boundary area collapsing
            onto the point).
        rho_c: (N,) float64, circumference of the point's shortest loop;
            inf on handle loops.
        sigma: (N,) float32, geodesicness of the point's cut loop (-1: none).
        junction: (N,) bool, the point is a junction.
        critical: (N,) bool, the point is a critical (cut) point.
        object: (N,) int32, the object (connected component) of the point.
    """

    points: np.ndarray
    voxels: np.ndarray
    edges: np.ndarray
    rho_s: np.ndarray
    rho_c: np.ndarray
    sigma: np.ndarray
    junction: np.ndarray
    critical: np.ndarray
    object: np.ndarray

    def __len__(self) -> int:
        return len(self.points)


@dataclasses.dataclass(frozen=True, eq=False)
class SegmentationResult:
    """What segment() returns. Plain data: it pickles (for Dask).

    Attributes:
        labels: uint16 array, the mask's shape and axis order: 0 background,
            1..K segments by decreasing boundary area (the CLI's labels.nrrd).
        skeleton: the curve skeleton (Skeleton).
        cuts: list of (K, 3) float64 arrays, the cut loops in world
            coordinates (cuts.ply).
        report: dict with the content of the CLI's report.json ("input"
            describes the array or mesh instead of a file).
        n_segments: the number of segments K.
        levels: every level, finest first (Level); one for a single tau
            without joints. The last is the coarsest, whose labels are
            ``labels`` except with joints=True and a single tau (docs/python.md).
    """

    labels: np.ndarray
    skeleton: Skeleton
    cuts: List[np.ndarray]
    report: dict
    levels: Tuple["Level", ...] = ()

    @property
    def n_segments(self) -> int:
        return int(self.report["segment_count"])

    def __repr__(self) -> str:
        return (f"{type(self).__name__}(labels={self.labels.dtype}{list(self.labels.shape)}, "
                f"n_segments={self.n_segments}, skeleton_points={len(self.skeleton)}, "
                f"cuts={len(self.cuts)})")


@dataclasses.dataclass(frozen=True, eq=False)
class Level:
    """One level of a hierarchy run (tau=[...] or joints=True), as the CLI's levels/k/.

    Attributes:
        tau: the level's tau as given ("1%"); the joint level has the finest
            junction-rule level's.
        labels: uint16 labels of the level (the mask's shape), nested: every
            segment lies inside one segment of the next coarser level.
        parents: uint16 array of n_segments entries, parents[l - 1] = the
            label at the next coarser level of label l (hierarchy.json's
            parent); None at the coarsest level.
        n_segments: the number of segments at this level.
        cuts: the level's cut loops, (K, 3) float64 arrays in world (mesh)
            coordinates: its own and every coarser level's (levels/k/cuts.ply).
        face_labels: segment_mesh() only: int32, one label per input face,
            0..F-1 (levels/k/segmentation.seg); nested like ``labels``:
            faces with one label here have one label at the next coarser
            level. None for segment().
        joints: True for the joint level (joints=True), the finest.
    """

    tau: str
    labels: np.ndarray
    parents: Optional[np.ndarray]
    n_segments: int
    cuts: List[np.ndarray] = dataclasses.field(default_factory=list)
    face_labels: Optional[np.ndarray] = None
    joints: bool = False

    def __repr__(self) -> str:
        # One line, as SegmentationResult's: the dataclass repr printed every
        # label and cut point.
        faces = ("" if self.face_labels is None else
                 f", face_labels={self.face_labels.dtype}{list(self.face_labels.shape)}")
        return (f"{type(self).__name__}(tau={self.tau!r}, joints={self.joints}, "
                f"n_segments={self.n_segments}, labels={self.labels.dtype}"
                f"{list(self.labels.shape)}, cuts={len(self.cuts)}{faces})")


@dataclasses.dataclass(frozen=True, eq=False, repr=False)
class MeshSegmentationResult(SegmentationResult):
    """What segment_mesh() returns: SegmentationResult plus face labels.

    Attributes:
        face_labels: int32, one label per input face in input order, 0..F-1
            (the CLI's segmentation.seg). ``labels`` holds the voxel labels of
            the voxelised mesh.
    """

    face_labels: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0, np.int32))


@dataclasses.dataclass(frozen=True, eq=False)
class Mesh:
    """A triangle mesh as read_mesh() returns it.

    Attributes:
        vertices: (V, 3) float64 positions.
        faces: (T, 3) int64 triangles (polygons of the file are fan-triangulated).
        triangle_face: (T,) int64, the file's face each triangle came from.
        face_count: number of faces in the file (lines of its .seg file).
    """

    vertices: np.ndarray
    faces: np.ndarray
    triangle_face: np.ndarray
    face_count: int

    def face_areas(self) -> np.ndarray:
        """Area of every input face (face_count entries), as `skelseg score` weighs them."""
        return _skelseg.face_areas(self.vertices, self.faces, self.triangle_face)


@dataclasses.dataclass(frozen=True)
class Score:
    """Princeton segmentation benchmark measures, in [0, 1], 0 = identical.

    The mean over the human segmentations, and per_human in their order.
    """

    rand_index_error: float
    hamming_distance: float
    missing_rate: float
    false_alarm_rate: float
    per_human: Tuple["Score", ...] = ()


@dataclasses.dataclass(frozen=True, eq=False)
class SequenceConsensus:
    """One segmentation for every frame of a pose sequence (`skelseg sequence`).

    reference: the frame whose labels every frame takes, the one with the
    least mean Rand Index error to the others among the frames with the part
    count most frames have (modal_parts; a tie goes to the earlier frame).
    parts and mean_error_to_others are per frame; pair_errors[a, b] is the
    Rand Index error (faces counted once each) of frames a and b;
    mean_pair_error the mean over all pairs. voted: per frame, whether it
    voted for the part count and could be chosen (the trusted frames, or
    every frame when none is).
    """

    reference: int
    modal_parts: int
    parts: Tuple[int, ...]
    mean_error_to_others: Tuple[float, ...]
    pair_errors: np.ndarray
    mean_pair_error: float
    voted: Tuple[bool, ...] = ()


# The options of `skelseg segment` (engine/SegmentOptions.h), by keyword:
# {"name": "--sigma-min", "flag": bool, "default": text, "help": text}. The
# keywords of segment() and segment_mesh() are their names in snake_case
# (--no-stub-limbs: no_stub_limbs=True); the engine parses and checks them as
# the CLI does, with its messages.
# Not keywords: the options that only concern files the module does not
# write (force, quiet, no_preview, level_previews) and grid (read_volume's);
# the mesh options are keywords of segment_mesh() only.
_OPTIONS = {option["keyword"]: option for option in _skelseg.segment_options()}


# Keywords whose value is a word: a number there is a wrong type (mode=1 was
# a ValueError, "1 not in {junction-rule,junctions}").
_WORD_KEYWORDS = {"mode", "skeleton_search", "budget_calibration"}


def _shown(value: Any, limit: int = 80) -> str:
    """repr(value) cut to `limit` characters, for an error message: a
    message is one readable line, and the value given in the wrong place may
    be a file's whole contents (segment(open(f, "rb").read()) wrote 32 MB of
    bytes into its TypeError) or a list of a million entries."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit] + f"... ({len(text)} characters)"


def _option_text(keyword: str, value: Any) -> str:
    """One option value as the command line spells it."""
    if isinstance(value, str):
        return value
    if keyword in _WORD_KEYWORDS:
        raise TypeError(f"{keyword} must be a string, not {_shown(value)}")
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{keyword} must be a number or a string as the CLI takes it, "
                        f"not {_shown(value)}")
    if isinstance(value, numbers.Integral):
        return str(int(value))
    return repr(float(value))


def _arguments(keywords: dict) -> List[str]:
    """The keywords as `skelseg segment` options: None leaves an option out,
    a flag is given when True, tau may be a list (the CLI's --tau 1%,3%,9%)."""
    arguments: List[str] = []
    for keyword, value in keywords.items():
        option = _OPTIONS[keyword]
        if option["flag"]:
            if not isinstance(value, (bool, np.bool_)):
                raise TypeError(f"{keyword} must be True or False, not {_shown(value)}")
            if value:
                arguments.append(option["name"])
        elif value is not None:
            if keyword == "tau" and isinstance(value, (list, tuple)):
                if not value:
                    raise ValueError("tau: the list is empty")
                text = ",".join(_option_text(keyword, v) for v in value)
            else:
                text = _option_text(keyword, value)
            arguments += [option["name"], text]
    return arguments


def _call_arguments(given: dict, progress: Optional[ProgressCallback]) -> List[str]:
    """The options among a call's arguments (its locals()) as command-line options."""
    if progress is not None and not callable(progress):
        raise TypeError("progress must be None or a callable (stage, fraction), "
                        f"not {_shown(progress)}")
    return _arguments({keyword: value for keyword, value in given.items()
                       if keyword in _OPTIONS})


def _with_option_help(function: Callable) -> Callable:
    """Appends the CLI's help of every option keyword of `function` that its
    docstring does not describe, so help() documents each one."""
    import inspect
    import textwrap
    lines = []
    for keyword in inspect.signature(function).parameters:
        option = _OPTIONS.get(keyword)
        if option is None or f"        {keyword}:" in (function.__doc__ or ""):
            continue
        default = f"; default {option['default']}" if option["default"] else ""
        lines.append(textwrap.fill(f"{keyword}: {option['help']} (the CLI's {option['name']}"
                                   f"{default})", width=79, initial_indent="    ",
                                   subsequent_indent="        "))
    function.__doc__ = (function.__doc__ or "") + (
        "\n    The other options, as `skelseg segment --help` describes them:\n\n"
        + "\n".join(lines) + "\n")
    return function


def _integer_array(value: Any, what: str, indices: bool = False) -> np.ndarray:
    """value as a C-contiguous int64 array; TypeError unless its dtype is an
    integer one. Floats are refused even when every value is whole: a cast
    would turn 1.7 into 1 without a word, and labels or indices computed in
    floating point are a bug to show, not to round. An empty list (float64
    to numpy) has nothing to cast and passes. Indices (not labels, which only
    need to stay distinct) past int64 are a ValueError: the cast made 2**63 a
    negative index, and the message named vertex -9223372036854775808."""
    array = np.asarray(value)
    if array.dtype.kind not in "iu" and array.size > 0:
        raise TypeError(f"{what} must be integers, not {array.dtype} (cast with .astype(int) "
                        f"if the values are whole)")
    if indices and array.dtype.kind == "u" and array.size > 0:
        largest = int(array.max())
        if largest > np.iinfo(np.int64).max:
            raise ValueError(f"{what}: index {largest} is out of range")
    return np.ascontiguousarray(array, dtype=np.int64)


def _label_vector(value: Any, what: str) -> np.ndarray:
    """_integer_array of one label per face: 1-D. A number became a frame of
    one face (ascontiguousarray makes 0-D arrays 1-D), so score(3, [3]) was
    0.0 and sequence_consensus({0: a, 1: b}) compared the dict's keys."""
    if np.ndim(value) != 1:
        raise ValueError(f"{what} must be 1-D arrays of labels (one per face), "
                         f"not {np.ndim(value)}-D: {type(value).__name__}")
    return _integer_array(value, what)


def _result(raw: dict, cls: type = SegmentationResult, **extra: Any) -> SegmentationResult:
    for message in raw["warnings"]:
        warnings.warn(message, SkelsegWarning, stacklevel=3)
    levels = tuple(Level(tau=level["tau"],
                         labels=raw["labels"] if level["labels"] is None else level["labels"],
                         parents=level["parents"], n_segments=int(level["segments"]),
                         cuts=list(level["cuts"]), face_labels=level["face_labels"],
                         joints=bool(level["joints"]))
                   for level in raw["levels"])
    return cls(labels=raw["labels"], skeleton=Skeleton(**raw["skeleton"]), cuts=raw["cuts"],
               report=raw["report"], levels=levels, **extra)


@_with_option_help
def segment(mask: np.ndarray, *, tau: Union[str, float, Sequence[Union[str, float]]] = "3%",
            sigma_min: float = 0.8, body_ratio: float = 0.6, mode: str = "junction-rule",
            joints: bool = False, spacing: Sequence[float] = (1, 1, 1),
            keep_voxel_aspect: bool = False,
            threads: Optional[int] = None, time_limit: Optional[float] = None,
            max_memory: Union[None, int, str] = None,
            progress: Optional[ProgressCallback] = None,
            time_budget: Optional[float] = None, budget_passes: int = 2,
            exhaustive: bool = False, skeleton_search: Optional[str] = None,
            sibling_tolerance: float = 0.25, end_body_ratio: float = 0.75,
            limb_taper: float = 0.3,
            corner_length: float = 0.5, corner_reach: float = 1.16,
            junction_merge_radii: float = 0.8, limb_sigma_margin: float = 0.05,
            limb_loop_variation: float = 0.065, no_limbs_below_sigma_min: bool = False,
            no_passages_as_body: bool = False, no_shared_body_reference: bool = False,
            no_two_sided_siblings: bool = False, no_body_check_below_sigma_min: bool = False,
            no_passage_area_check: bool = False, no_body_end_check: bool = False,
            no_body_radius_window: bool = False, surface_loops: bool = False,
            tight_levels_in_runs: bool = False, no_stub_limbs: bool = False,
            no_separation_check: bool = False, no_fork_junctions: bool = False,
            no_grow_regions: bool = False, handles_on_genus_zero: bool = False,
            joint_ratio: float = 0.82, bend_angle: float = 360.0,
            joint_min_part: float = 0.25) -> SegmentationResult:
    """Segments the object(s) of a 3-D mask into parts.

    Every option of `skelseg segment` that changes the result or the run is a
    keyword, named as the option in snake_case (--sigma-min: sigma_min,
    --no-stub-limbs: no_stub_limbs=True), with the CLI's default; the engine
    checks the values as the CLI does and refuses bad ones with its message
    (ValueError). None leaves an option out (the CLI's default).

    Args:
        mask: any 3-D array-like; nonzero is object. bool, any integer or
            float dtype (NaN refused), C or Fortran order or any strides. It
            is read in place once; labels come back in its shape and axis
            order. Axis 0 is the engine's x (as in NRRD files and pynrrd), so
            read_volume() output gives the CLI's labels.nrrd byte for byte.
        tau: skeleton simplification: a percentage of each object's boundary
            area ("3%") or an area in voxels (250). Larger is coarser; about
            "1%" keeps fingers. A list (["1%", "3%", "9%"]) gives nested
            levels in one run (.levels); the result is then the coarsest's.
        sigma_min: minimum geodesicness (smoothness) of a cut loop, in [0, 1].
        body_ratio: a candidate cut this similar in circumference to its
            junction lies on the body and is not cut, in [0, 1].
        mode: "junction-rule" (default) or "junctions" (the junctions' own
            loops are the cuts: the RT07 baseline).
        joints: also cut inside parts where a limb narrows clearly between
            two wider stretches (elbows, knees, necks), like the CLI's
            --joints (thresholds: joint_ratio, bend_angle, joint_min_part):
            one more level, below the finest (.levels[0]); with a single tau
            the result is that joint level, as the CLI's top-level files.
            Each cut's kind is in report["cuts"].
        spacing: voxel size along the three axes; scales the skeleton's and
            the cuts' coordinates. Unequal sizes (more than 1% apart): the mask
            is segmented resampled to cubic voxels and the labels come back in
            its own shape, as the CLI does with an anisotropic file.
        keep_voxel_aspect: segment the mask's own voxels as if they were
            cubes, whatever the spacing (the CLI's --keep-voxel-aspect).
        threads: worker threads for this call (None: all cores). Results do
            not depend on it.
        time_limit: seconds; past it the call raises TimeoutError.
        max_memory: refuse runs estimated to need more: bytes or "4G"
            (None: 75% of physical memory). Raises MemoryError.
        progress: callable(stage: str, fraction: float | None), called on the
            calling thread about ten times a second while the engine works
            (fraction None when the stage has no measure), and ("done", 1.0)
            at the end. If it raises, the run is cancelled and the exception
            propagates.
        time_budget: seconds, counted from the call: segment the mask as
            many times coarser as is predicted to finish within it (the
            labels come back on the mask's grid), as the CLI's --time-budget.
            report["time_budget"] says what was chosen (coarsening, predicted
            and actual seconds, "fits"). When nothing is predicted to fit,
            the coarsest run goes ahead with the budget as its time limit:
            it returns if it finishes in time, else raises TimeoutError, as
            the CLI stops with exit code 3.
        budget_passes: with time_budget, 2 (default): a first pass that
            ends early leaves its time to a finer pass (a smaller
            coarsening), whose result is returned if it finishes by the
            budget, else the first pass's; report["time_budget"]
            ["refinement"] says which. 1 keeps the first choice. The CLI's
            --budget-passes.
        exhaustive: the reference search, which measures every candidate
            (slower on large grids, same answer); the CLI's --exhaustive.
        skeleton_search: "band" or "exhaustive" (None: band for a single
            tau, exhaustive for a list); exhaustive=True is the same as
            "exhaustive" and contradicts "band".

    Returns:
        SegmentationResult with .labels (uint16, the mask's shape), .skeleton,
        .cuts, .report (report.json's content) and .n_segments.

    Raises:
        ValueError: not 3-D, an empty shape, NaN, bad parameters, with the
            CLI's message and the keyword's name ("sigma_min: Value 2 not in
            range 0.000000 to 1.000000").
        TypeError: a dtype that is not bool, integer or float; a keyword of
            the wrong type (joints="yes").
        MemoryError: estimated memory over max_memory.
        TimeoutError: time_limit reached (or a time_budget nothing fits).
        KeyboardInterrupt: Ctrl-C; the engine stops within a second.

    Warnings (SkelsegWarning) go through the warnings module; nothing is
    printed.
    """
    arguments = _call_arguments(locals(), progress)
    if mask is None:
        raise TypeError("mask must be a 3-D array, not None")
    # A file name read as a 0-D array of text was "got 0-D of shape ()".
    if isinstance(mask, (bytes, bytearray)) and (b"\0" in mask or len(mask) > 4096):
        raise TypeError(f"mask must be a 3-D array, not {len(mask)} bytes of data: read a file "
                        "with skelseg.read_volume(), or wrap a buffer with "
                        "np.frombuffer(data, dtype).reshape(shape)")
    if isinstance(mask, (str, bytes, os.PathLike)):
        raise TypeError(f"mask must be a 3-D array, not the path {_shown(mask)}: read the file "
                        "with skelseg.read_volume() first")
    array = np.asarray(mask)
    if array.dtype.kind == "f" and not array.dtype.isnative:
        array = array.astype(array.dtype.newbyteorder("="))
    # A string has a length and its characters convert: "111" read as (1, 1, 1).
    if isinstance(spacing, (str, bytes)) or np.ndim(spacing) != 1 or not all(
            isinstance(s, numbers.Real) and not isinstance(s, (bool, np.bool_))
            for s in np.ravel(np.asarray(spacing, dtype=object))):
        raise TypeError(f"spacing must be three numbers, not {_shown(spacing)}")
    if len(spacing) != 3:
        raise ValueError(f"spacing must have three entries, not {len(spacing)}")
    spacing3 = tuple(float(s) for s in spacing)
    if not all(math.isfinite(s) and s > 0 for s in spacing3):
        raise ValueError(f"spacing must be three positive finite numbers, not {tuple(spacing)}")
    return _result(_skelseg.segment_array(array, spacing3, arguments, progress))


@_with_option_help
def segment_mesh(vertices: np.ndarray, faces: np.ndarray, *, resolution: int = 256,
                 self_overlap_clearance: int = 4, triangle_face: Optional[np.ndarray] = None,
                 tau: Union[str, float, Sequence[Union[str, float]]] = "3%",
                 sigma_min: float = 0.8, body_ratio: float = 0.6, mode: str = "junction-rule",
                 joints: bool = False, threads: Optional[int] = None,
                 time_limit: Optional[float] = None, max_memory: Union[None, int, str] = None,
                 progress: Optional[ProgressCallback] = None,
                 contact_patch_seams: bool = False, no_grown_contact_seams: bool = False,
                 keep_handle_areas: bool = False,
                 time_budget: Optional[float] = None, budget_passes: int = 2,
                 budget_calibration: str = "probe", exhaustive: bool = False,
                 skeleton_search: Optional[str] = None,
                 sibling_tolerance: float = 0.25, end_body_ratio: float = 0.75,
                 limb_taper: float = 0.3,
                 corner_length: float = 0.5, corner_reach: float = 1.16,
                 junction_merge_radii: float = 0.8, limb_sigma_margin: float = 0.05,
                 limb_loop_variation: float = 0.065, no_limbs_below_sigma_min: bool = False,
                 no_passages_as_body: bool = False, no_shared_body_reference: bool = False,
                 no_two_sided_siblings: bool = False,
                 no_body_check_below_sigma_min: bool = False,
                 no_passage_area_check: bool = False, no_body_end_check: bool = False,
                 no_body_radius_window: bool = False, surface_loops: bool = False,
                 tight_levels_in_runs: bool = False, no_stub_limbs: bool = False,
                 no_separation_check: bool = False, no_fork_junctions: bool = False,
                 no_grow_regions: bool = False, handles_on_genus_zero: bool = False,
                 joint_ratio: float = 0.82, bend_angle: float = 360.0,
                 joint_min_part: float = 0.25) -> MeshSegmentationResult:
    """Voxelises a closed triangle mesh, segments it and labels its faces.

    The CLI's `skelseg segment MESH` on arrays: the face labels equal its
    segmentation.seg for the same mesh and options.

    Args:
        vertices: (V, 3) float positions.
        faces: (F, k) integer vertex indices, k >= 3; polygons (k > 3) are
            fan-triangulated and labelled as one face.
        resolution: voxels along the longest side of the bounding box [8, 2048].
        self_overlap_clearance: where the mesh passes through itself and
            clearing 2 voxels would add a handle, retry up to this many
            voxels wide [2, 4]; the CLI's --self-overlap-clearance.
        triangle_face: with faces of shape (T, 3), the input face of each
            triangle (as read_mesh() gives it); labels are then per input face.
            Integers, like faces (floats raise TypeError, whole or not).
        contact_patch_seams: where a contact's seam is refused, try a seam
            between the two mesh patches of the contact (the CLI's
            --contact-patch-seams); report["input"]["contacts_patch_seamed"].
        no_grown_contact_seams: do not retry a refused contact seam grown by
            one voxel (the CLI's --no-grown-contact-seams);
            report["input"]["contacts_grown"] counts the seams it kept.
        keep_handle_areas: where the voxel model has handles the mesh lacks,
            let the cut placement read loops round them as carrying infinite
            area, as on other inputs (the CLI's --keep-handle-areas);
            report["parameters"]["handle_loops_carry_no_area"] says whether
            they carried none.
        time_budget: seconds, counted from the call: the resolution (at most
            `resolution`) predicted to finish within it, as the CLI's
            --time-budget; report["time_budget"] says what was chosen
            (resolution, predicted and actual seconds, calibration, "fits").
            When nothing fits, the coarsest run goes ahead with the budget as
            its time limit: it returns if it finishes in time, else raises
            TimeoutError, as the CLI stops with exit code 3.
        budget_passes: with time_budget, 2 (default) lets a first pass that
            ends early leave its time to a finer resolution, as segment().
        budget_calibration: with time_budget, "probe" (the probe's own time
            turns predicted CPU seconds into this machine's wall seconds now)
            or "cpu" (CPU seconds compared with the budget).
        tau, sigma_min, body_ratio, mode, joints, threads, time_limit,
            max_memory, progress, exhaustive, skeleton_search: as segment().

    Returns:
        MeshSegmentationResult: .face_labels (int32, one per input face in
        input order, 0..K-1) beside .labels (the voxel labels), .skeleton and
        .cuts (in the mesh's coordinates), .report, .n_segments, and
        .levels, each with its own .face_labels and .cuts (a tau list or
        joints=True: nested level to level, as the CLI's levels/k/).

    Raises:
        ValueError: bad arrays (shapes, indices out of range, non-finite
            coordinates) or parameters. TypeError: faces or triangle_face
            that are not integers (a float array, even of whole numbers),
            complex vertices.
            MemoryError, TimeoutError, KeyboardInterrupt: as segment().
    """
    arguments = _call_arguments(locals(), progress)
    vertex_array = np.asarray(vertices)
    # The cast below would drop imaginary parts with only a ComplexWarning,
    # and would read text ("1.5") as numbers.
    if vertex_array.dtype.kind not in "biuf" and vertex_array.size > 0:
        raise TypeError(f"mesh: vertices must be real numbers, not {vertex_array.dtype}")
    vertex_array = np.ascontiguousarray(vertex_array, dtype=np.float64)
    face_array = np.asarray(faces)
    if face_array.ndim != 2 or face_array.shape[1] < 3:
        raise ValueError(f"mesh: faces must have shape (F, k) with k >= 3, "
                         f"not {face_array.shape}")
    face_array = _integer_array(face_array, "mesh: faces", indices=True)
    if triangle_face is not None:
        if face_array.shape[1] != 3:
            raise ValueError("mesh: triangle_face needs faces of shape (T, 3)")
        triangles = face_array
        triangle_of = _integer_array(triangle_face, "mesh: triangle_face", indices=True)
    elif face_array.shape[1] == 3:
        triangles = face_array
        triangle_of = np.zeros(0, np.int64)
    else:  # fan-triangulate (v0 v1 v2), (v0 v2 v3), ... as the file readers do
        k = face_array.shape[1]
        fan = [np.stack([face_array[:, 0], face_array[:, i], face_array[:, i + 1]], axis=1)
               for i in range(1, k - 1)]
        triangles = np.stack(fan, axis=1).reshape(-1, 3)
        triangle_of = np.repeat(np.arange(len(face_array), dtype=np.int64), k - 2)
    raw = _skelseg.segment_mesh(vertex_array, np.ascontiguousarray(triangles), triangle_of,
                                arguments, progress)
    return _result(raw, MeshSegmentationResult, face_labels=raw["face_labels"])


def _file_path(path: Union[str, bytes, os.PathLike]) -> Union[str, bytes]:
    """The path as the engine opens it (str or bytes, as given).

    A NUL byte ends a path for the system, so "a.nrrd\\0.off" opened a.nrrd
    after the name's extension had been checked; refused as open() refuses it.
    """
    text = os.fspath(path)
    if ("\0" if isinstance(text, str) else b"\0") in text:
        raise ValueError(f"embedded null byte in the path {_shown(text)}")
    return text


def read_volume(path: Union[str, os.PathLike], *, grid: Optional[str] = None,
                with_spacing: bool = False, max_memory: Union[None, int, str] = None,
                time_limit: Optional[float] = None
                ) -> Union[np.ndarray, Tuple[np.ndarray, tuple]]:
    """Reads a volume file (.nrrd/.nhdr, .binvox, .vdb) as a bool mask.

    The array's axis 0 is the file's x (the fastest axis in NRRD): shape
    (nx, ny, nz), Fortran order, the file's voxels without reordering, as
    pynrrd reads them. grid: .vdb only, the grid to read (default: the
    first). with_spacing: also return the voxel spacing per axis.
    max_memory: bytes or "4G" (None: 75% of physical memory, the CLI's
    default): a grid whose mask (a byte per voxel) needs more is refused
    before it is allocated, and an OpenVDB parse may take no more.
    time_limit: seconds; stops an OpenVDB parse past it (the other formats
    are read whole: their size is checked before, against max_memory).

    Raises ValueError with the CLI's message ("FILE: no such file", ...),
    MemoryError over max_memory, TimeoutError past time_limit,
    KeyboardInterrupt on Ctrl-C during an OpenVDB parse.
    """
    if grid is not None and not isinstance(grid, str):
        raise TypeError(f"grid must be a string or None, not {_shown(grid)}")
    if not isinstance(with_spacing, (bool, np.bool_)):
        raise TypeError(f"with_spacing must be True or False, not {_shown(with_spacing)}")
    memory = "" if max_memory is None else _option_text("max_memory", max_memory)
    seconds = 0.0
    if time_limit is not None:
        try:
            seconds = float(_option_text("time_limit", time_limit))
        except ValueError:
            seconds = math.nan
        if not (math.isfinite(seconds) and seconds > 0):
            raise ValueError("time_limit must be a positive number of seconds, "
                             f"not {_shown(time_limit)}")
    array, spacing, _origin = _skelseg.read_volume(_file_path(path), grid or "", memory, seconds)
    return (array, spacing) if with_spacing else array


def read_mesh(path: Union[str, os.PathLike]) -> Mesh:
    """Reads a mesh file (.off, .obj, .stl, .ply) as a Mesh.

    Polygons are fan-triangulated; Mesh.triangle_face maps each triangle to
    the file's face, so segment_mesh(m.vertices, m.faces,
    triangle_face=m.triangle_face) labels the file's faces.
    Raises ValueError with the CLI's message.
    """
    vertices, triangles, triangle_face, face_count = _skelseg.read_mesh(_file_path(path))
    return Mesh(vertices, triangles, triangle_face, int(face_count))


def read_seg(path: Union[str, os.PathLike]) -> np.ndarray:
    """Reads a .seg or .seg.gz face segmentation (one int64 label per face)."""
    return _skelseg.read_seg(_file_path(path))


def _score(raw: dict, per_human: Tuple[Score, ...] = ()) -> Score:
    return Score(raw["rand_index_error"], raw["hamming_distance"], raw["missing_rate"],
                 raw["false_alarm_rate"], per_human)


def score(labels: np.ndarray, human_labels: Union[np.ndarray, Sequence[np.ndarray]], *,
          face_areas: Optional[np.ndarray] = None) -> Score:
    """Rand Index error and Hamming distance of a face segmentation.

    As `skelseg score` (Princeton benchmark, Chen et al. 2009): labels and
    each human segmentation give one label per face (any integers). With
    face_areas (e.g. read_mesh(path).face_areas()) the Hamming distance is
    weighted by area, as the benchmark and the CLI do; without, every face
    counts once. Returns the mean over the humans with .per_human.
    Raises TypeError for labels that are not integers (a float array, even
    of whole numbers: no silent rounding) and ValueError for a scalar or
    arrays of different lengths.
    """
    candidate = _label_vector(labels, "labels")
    if isinstance(human_labels, np.ndarray):
        if human_labels.ndim == 0:
            raise ValueError("human_labels must be one or more arrays of labels, not a scalar")
        humans = [human_labels] if human_labels.ndim == 1 else list(human_labels)
    else:
        listed = list(human_labels)
        humans = [listed] if listed and np.ndim(listed[0]) == 0 else listed
    humans = [_label_vector(h, "human_labels") for h in humans]
    areas = None if face_areas is None else np.ascontiguousarray(face_areas, dtype=np.float64)
    raw = _skelseg.score(candidate, humans, areas)
    return _score(raw, tuple(_score(h) for h in raw["per_human"]))


def sequence_consensus(frame_labels: Sequence[np.ndarray],
                       trusted: Optional[Sequence[bool]] = None) -> SequenceConsensus:
    """The consensus of the face labels of a pose sequence's frames.

    The frames of an animated character share their faces, so one frame's
    labels segment every frame: frame_labels[consensus.reference]. As
    `skelseg sequence` chooses (docs/outputs.md, "skelseg sequence").
    trusted: per frame, whether it may vote for the part count and be
    chosen (`skelseg sequence` trusts a frame unless it is a closed mesh
    whose voxel model has handles the mesh lacks: report["input"]
    "mesh_closed", "mesh_pieces_without_genus" 0 and "voxel_genus" above
    "mesh_genus"); None or no frame
    trusted: every frame.
    Raises ValueError for a scalar instead of a sequence of frames, fewer
    than two frames, no faces, frames of different face counts or a trusted
    of another length, and
    TypeError for labels that are not integers (a float array, even of whole
    numbers: no silent rounding).
    """
    if isinstance(frame_labels, (numbers.Number, np.generic)) or (
            isinstance(frame_labels, np.ndarray) and frame_labels.ndim == 0):
        raise ValueError(f"frame_labels must be a sequence of per-frame label arrays, "
                         f"not the scalar {_shown(frame_labels)}")
    if isinstance(frame_labels, dict):
        raise TypeError("frame_labels must be a sequence of per-frame label arrays, not a dict "
                        "(pass list(d.values()) in frame order)")
    frames = [_label_vector(f, "frame_labels") for f in frame_labels]
    trust = [] if trusted is None else [bool(t) for t in trusted]
    raw = _skelseg.sequence_consensus(frames, trust)
    return SequenceConsensus(int(raw["reference"]), int(raw["modal_parts"]),
                             tuple(int(p) for p in raw["parts"]),
                             tuple(float(e) for e in raw["mean_error_to_others"]),
                             raw["pair_errors"], float(raw["mean_pair_error"]),
                             tuple(bool(v) for v in raw["voted"]))
