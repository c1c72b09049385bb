"""skelseg: split 3-D shapes into their parts with the junction rule.

The engine of the ``skelseg`` command line, on numpy arrays:

    >>> import numpy as np, skelseg
    >>> mask = skelseg.read_volume("figure.nrrd")       # or any 3-D array
    >>> result = skelseg.segment(mask, tau="3%")
    >>> result.labels.shape == mask.shape, result.n_segments
    (True, 6)

Functions: segment, segment_mesh, read_volume, read_mesh, read_seg, score.
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
    "SegmentationResult",
    "MeshSegmentationResult",
    "Level",
    "Skeleton",
    "Mesh",
    "Score",
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


def _options(tau: Union[str, float], sigma_min: float, body_ratio: float, mode: str,
             joints: bool, threads: Optional[int], time_limit: Optional[float],
             max_memory: Union[None, int, str], progress: Optional[ProgressCallback]) -> dict:
    def one_tau(value: Any) -> str:
        if isinstance(value, bool) or not isinstance(value, (str, numbers.Real)):
            raise TypeError(f"tau must be a string such as '3%' or a number of voxels, "
                            f"or a list of them, not {value!r}")
        return repr(float(value)) if isinstance(value, numbers.Real) else value

    if isinstance(tau, (list, tuple)):
        # A hierarchy run: the CLI's --tau 1%,3%,9%.
        if not tau:
            raise ValueError("tau: the list is empty")
        tau = ",".join(one_tau(t) for t in tau)
    else:
        tau = one_tau(tau)
    for name, value in (("sigma_min", sigma_min), ("body_ratio", body_ratio)):
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise TypeError(f"{name} must be a number, not {value!r}")
        if not 0.0 <= float(value) <= 1.0:
            raise ValueError(f"{name} {value!r} is not in [0, 1]")
    if mode not in ("junction-rule", "junctions"):
        raise ValueError(f"mode {mode!r} is not 'junction-rule' or 'junctions'")
    if not isinstance(joints, bool):
        raise TypeError(f"joints must be True or False, not {joints!r}")
    if threads is None:
        threads = 0
    elif isinstance(threads, bool) or not isinstance(threads, numbers.Integral) or threads < 1:
        raise ValueError(f"threads must be None or a positive integer, not {threads!r}")
    if time_limit is None:
        time_limit = 0.0
    elif (isinstance(time_limit, bool) or not isinstance(time_limit, numbers.Real)
          or not 0 < float(time_limit) < 1e9):
        raise ValueError(f"time_limit must be None or a positive number of seconds, "
                         f"not {time_limit!r}")
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be None or a callable (stage, fraction), not {progress!r}")
    return dict(tau=tau, sigma_min=float(sigma_min), body_ratio=float(body_ratio), mode=mode,
                joints=joints, threads=int(threads), time_limit=float(time_limit),
                max_memory=_bytes(max_memory), progress=progress)


def _bytes(size: Union[None, int, str]) -> int:
    """max_memory as bytes: None (0: 75% of RAM), an int, or '4G', '512M', '100K'."""
    if size is None:
        return 0
    if isinstance(size, str):
        scale = {"K": 1e3, "KB": 1e3, "M": 1e6, "MB": 1e6, "G": 1e9, "GB": 1e9}
        text = size.strip()
        unit = text.lstrip("0123456789.eE+-")
        number = text[: len(text) - len(unit)]
        try:
            value = float(number) * (scale[unit] if unit else 1.0)
        except (ValueError, KeyError):
            raise ValueError(f"max_memory {size!r} is not a size such as 4G or 512M") from None
        size = int(value)
    if isinstance(size, bool) or not isinstance(size, numbers.Integral) or size <= 0:
        raise ValueError(f"max_memory must be None, a positive number of bytes or a size "
                         f"such as '4G', not {size!r}")
    return int(size)


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


def segment(mask: np.ndarray, *, tau: Union[str, float, Sequence[Union[str, float]]] = "3%", sigma_min: float = 0.8,
            body_ratio: float = 0.6, mode: str = "junction-rule", joints: bool = False,
            spacing: Sequence[float] = (1, 1, 1), threads: Optional[int] = None,
            time_limit: Optional[float] = None, max_memory: Union[None, int, str] = None,
            progress: Optional[ProgressCallback] = None) -> SegmentationResult:
    """Segments the object(s) of a 3-D mask into parts.

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
            --joints (with its default thresholds): one more level, below
            the finest (.levels[0]); with a single tau the result is that
            joint level, as the CLI's top-level files. Each cut's kind is in
            report["cuts"].
        spacing: voxel size along the three axes; scales the skeleton's and
            the cuts' coordinates (the segmentation works in voxels, as the CLI).
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

    Returns:
        SegmentationResult with .labels (uint16, the mask's shape), .skeleton,
        .cuts, .report (report.json's content) and .n_segments.

    Raises:
        ValueError: not 3-D, an empty shape, NaN, bad parameters
            ("mask: must be a 3-D array, got 2-D of shape (4, 5)").
        TypeError: a dtype that is not bool, integer or float.
        MemoryError: estimated memory over max_memory.
        TimeoutError: time_limit reached.
        KeyboardInterrupt: Ctrl-C; the engine stops within a second.

    Warnings (SkelsegWarning) go through the warnings module; nothing is
    printed.
    """
    array = np.asarray(mask)
    if array.dtype.kind == "f" and not array.dtype.isnative:
        array = array.astype(array.dtype.newbyteorder("="))
    if len(spacing) != 3:
        raise ValueError(f"spacing must have three entries, not {len(spacing)}")
    spacing3 = tuple(float(s) for s in spacing)
    if not all(math.isfinite(s) and s > 0 for s in spacing3):
        raise ValueError(f"spacing must be three positive finite numbers, not {tuple(spacing)}")
    options = _options(tau, sigma_min, body_ratio, mode, joints, threads, time_limit,
                       max_memory, progress)
    return _result(_skelseg.segment_array(array, spacing3, **options))


def segment_mesh(vertices: np.ndarray, faces: np.ndarray, *, resolution: int = 256,
                 self_overlap_clearance: int = 4, triangle_face: Optional[np.ndarray] = None, tau: Union[str, float, Sequence[Union[str, float]]] = "3%",
                 sigma_min: float = 0.8, body_ratio: float = 0.6, mode: str = "junction-rule",
                 joints: bool = False, threads: Optional[int] = None, time_limit: Optional[float] = None,
                 max_memory: Union[None, int, str] = None,
                 progress: Optional[ProgressCallback] = None) -> MeshSegmentationResult:
    """Voxelises a closed triangle mesh, segments it and labels its faces.

    The CLI's `skelseg segment MESH` on arrays: the face labels equal its
    segmentation.seg for the same mesh and resolution.

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
        tau, sigma_min, body_ratio, mode, joints, threads, time_limit,
            max_memory, progress: as segment().

    Returns:
        MeshSegmentationResult: .face_labels (int32, one per input face in
        input order, 0..K-1) beside .labels (the voxel labels), .skeleton and
        .cuts (in the mesh's coordinates), .report, .n_segments, and
        .levels, each with its own .face_labels and .cuts (a tau list or
        joints=True: nested level to level, as the CLI's levels/k/).

    Raises:
        ValueError: bad arrays (shapes, indices out of range, non-finite
            coordinates) or parameters. MemoryError, TimeoutError,
            KeyboardInterrupt: as segment().
    """
    vertex_array = np.ascontiguousarray(vertices, dtype=np.float64)
    face_array = np.asarray(faces)
    if face_array.ndim != 2 or face_array.shape[1] < 3:
        raise ValueError(f"mesh: faces must have shape (F, k) with k >= 3, "
                         f"not {face_array.shape}")
    if face_array.dtype.kind not in "iu":
        raise TypeError(f"mesh: faces must be integers, not {face_array.dtype}")
    face_array = face_array.astype(np.int64, copy=False)
    if triangle_face is not None:
        if face_array.shape[1] != 3:
            raise ValueError("mesh: triangle_face needs faces of shape (T, 3)")
        triangles = face_array
        triangle_of = np.asarray(triangle_face, dtype=np.int64)
    elif face_array.shape[1] == 3:
        triangles = face_array
        triangle_of = np.zeros(0, np.int64)
    else:  # fan-triangulate (v0 v1 v2), (v0 v2 v3), ... as the file readers do
        k = face_array.shape[1]
        fan = [np.stack([face_array[:, 0], face_array[:, i], face_array[:, i + 1]], axis=1)
               for i in range(1, k - 1)]
        triangles = np.stack(fan, axis=1).reshape(-1, 3)
        triangle_of = np.repeat(np.arange(len(face_array), dtype=np.int64), k - 2)
    if isinstance(resolution, bool) or not isinstance(resolution, numbers.Integral):
        raise TypeError(f"resolution must be an integer, not {resolution!r}")
    if not 8 <= resolution <= 2048:
        raise ValueError(f"resolution {resolution} is not in [8, 2048]")
    if isinstance(self_overlap_clearance, bool) or not isinstance(self_overlap_clearance,
                                                                  numbers.Integral):
        raise TypeError(f"self_overlap_clearance must be an integer, "
                        f"not {self_overlap_clearance!r}")
    if not 2 <= self_overlap_clearance <= 4:
        raise ValueError(f"self_overlap_clearance {self_overlap_clearance} is not in [2, 4]")
    options = _options(tau, sigma_min, body_ratio, mode, joints, threads, time_limit,
                       max_memory, progress)
    raw = _skelseg.segment_mesh(vertex_array, np.ascontiguousarray(triangles), triangle_of,
                                int(resolution), int(self_overlap_clearance), **options)
    return _result(raw, MeshSegmentationResult, face_labels=raw["face_labels"])


def read_volume(path: Union[str, os.PathLike], *, grid: Optional[str] = None,
                with_spacing: bool = False) -> Union[np.ndarray, Tuple[np.ndarray, tuple]]:
    """Reads a volume file (.nrrd/.nhdr, .binvox, .vdb) as a bool mask.

    The array's axis 0 is the file's x (the fastest axis in NRRD): shape
    (nx, ny, nz), Fortran order, the file's voxels without reordering, as
    pynrrd reads them. grid: .vdb only, the grid to read (default: the
    first). with_spacing: also return the voxel spacing per axis.

    Raises ValueError with the CLI's message ("FILE: no such file", ...).
    """
    array, spacing, _origin = _skelseg.read_volume(os.fspath(path), grid or "")
    return (array, spacing) if with_spacing else array


def read_mesh(path: Union[str, os.PathLike]) -> Mesh:
    """Reads a mesh file (.off, .obj, .stl, .ply) as a Mesh.

    Polygons are fan-triangulated; Mesh.triangle_face maps each triangle to
    the file's face, so segment_mesh(m.vertices, m.faces,
    triangle_face=m.triangle_face) labels the file's faces.
    Raises ValueError with the CLI's message.
    """
    vertices, triangles, triangle_face, face_count = _skelseg.read_mesh(os.fspath(path))
    return Mesh(vertices, triangles, triangle_face, int(face_count))


def read_seg(path: Union[str, os.PathLike]) -> np.ndarray:
    """Reads a .seg or .seg.gz face segmentation (one int64 label per face)."""
    return _skelseg.read_seg(os.fspath(path))


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
    """
    candidate = np.ascontiguousarray(labels, dtype=np.int64)
    if isinstance(human_labels, np.ndarray):
        humans = [human_labels] if human_labels.ndim == 1 else list(human_labels)
    else:
        listed = list(human_labels)
        humans = [listed] if listed and np.ndim(listed[0]) == 0 else listed
    humans = [np.ascontiguousarray(h, dtype=np.int64) for h in humans]
    areas = None if face_areas is None else np.ascontiguousarray(face_areas, dtype=np.float64)
    raw = _skelseg.score(candidate, humans, areas)
    return _score(raw, tuple(_score(h) for h in raw["per_human"]))
