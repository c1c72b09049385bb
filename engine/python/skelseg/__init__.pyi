# Type stubs of the skelseg package (the implementation is __init__.py over
# the compiled _skelseg); editors show these signatures.
import os
from typing import Any, Callable, List, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

ProgressCallback = Callable[[str, Optional[float]], Any]
PathLike = Union[str, os.PathLike[str]]

class SkelsegWarning(UserWarning): ...

class Skeleton:
    points: npt.NDArray[np.float64]
    voxels: npt.NDArray[np.int32]
    edges: npt.NDArray[np.int64]
    rho_s: npt.NDArray[np.float32]
    rho_c: npt.NDArray[np.float64]
    sigma: npt.NDArray[np.float32]
    junction: npt.NDArray[np.bool_]
    critical: npt.NDArray[np.bool_]
    object: npt.NDArray[np.int32]
    def __len__(self) -> int: ...

class Level:
    tau: str
    labels: npt.NDArray[np.uint16]
    parents: Optional[npt.NDArray[np.uint16]]
    n_segments: int
    cuts: List[npt.NDArray[np.float64]]
    face_labels: Optional[npt.NDArray[np.int32]]
    joints: bool

class SegmentationResult:
    labels: npt.NDArray[np.uint16]
    skeleton: Skeleton
    cuts: List[npt.NDArray[np.float64]]
    report: dict[str, Any]
    levels: Tuple[Level, ...]
    @property
    def n_segments(self) -> int: ...

class MeshSegmentationResult(SegmentationResult):
    face_labels: npt.NDArray[np.int32]

class Mesh:
    vertices: npt.NDArray[np.float64]
    faces: npt.NDArray[np.int64]
    triangle_face: npt.NDArray[np.int64]
    face_count: int
    def face_areas(self) -> npt.NDArray[np.float64]: ...

class SequenceConsensus:
    reference: int
    modal_parts: int
    parts: Tuple[int, ...]
    mean_error_to_others: Tuple[float, ...]
    pair_errors: npt.NDArray[np.float64]
    mean_pair_error: float
    voted: Tuple[bool, ...]

class Score:
    rand_index_error: float
    hamming_distance: float
    missing_rate: float
    false_alarm_rate: float
    per_human: Tuple[Score, ...]

def segment(
    mask: npt.ArrayLike,
    *,
    tau: Union[str, float, Sequence[Union[str, float]]] = "3%",
    sigma_min: float = 0.8,
    body_ratio: float = 0.6,
    mode: Literal["junction-rule", "junctions"] = "junction-rule",
    joints: bool = False,
    spacing: Sequence[float] = (1, 1, 1),
    keep_voxel_aspect: bool = False,
    threads: Optional[int] = None,
    time_limit: Optional[float] = None,
    max_memory: Union[None, int, str] = None,
    progress: Optional[ProgressCallback] = None,
    time_budget: Optional[float] = None,
    budget_passes: Literal[1, 2] = 2,
    exhaustive: bool = False,
    skeleton_search: Optional[Literal["band", "exhaustive"]] = None,
    sibling_tolerance: float = 0.25,
    end_body_ratio: float = 0.75,
    limb_taper: float = 0.3,
    corner_length: float = 0.5,
    corner_reach: float = 1.16,
    junction_merge_radii: float = 0.8,
    limb_sigma_margin: float = 0.05,
    limb_loop_variation: float = 0.065,
    no_limbs_below_sigma_min: bool = False,
    no_passages_as_body: bool = False,
    no_shared_body_reference: bool = False,
    no_two_sided_siblings: bool = False,
    no_body_check_below_sigma_min: bool = False,
    no_passage_area_check: bool = False,
    no_body_end_check: bool = False,
    no_body_radius_window: bool = False,
    surface_loops: bool = False,
    tight_levels_in_runs: bool = False,
    no_stub_limbs: bool = False,
    no_separation_check: bool = False,
    no_fork_junctions: bool = False,
    no_grow_regions: bool = False,
    handles_on_genus_zero: bool = False,
    joint_ratio: float = 0.82,
    bend_angle: float = 360.0,
    joint_min_part: float = 0.25,
) -> SegmentationResult: ...
def segment_mesh(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    *,
    resolution: int = 256,
    self_overlap_clearance: int = 4,
    triangle_face: Optional[npt.ArrayLike] = None,
    tau: Union[str, float, Sequence[Union[str, float]]] = "3%",
    sigma_min: float = 0.8,
    body_ratio: float = 0.6,
    mode: Literal["junction-rule", "junctions"] = "junction-rule",
    joints: bool = False,
    threads: Optional[int] = None,
    time_limit: Optional[float] = None,
    max_memory: Union[None, int, str] = None,
    progress: Optional[ProgressCallback] = None,
    contact_patch_seams: bool = False,
    no_grown_contact_seams: bool = False,
    keep_handle_areas: bool = False,
    budget_calibration: Literal["probe", "cpu"] = "probe",
    time_budget: Optional[float] = None,
    budget_passes: Literal[1, 2] = 2,
    exhaustive: bool = False,
    skeleton_search: Optional[Literal["band", "exhaustive"]] = None,
    sibling_tolerance: float = 0.25,
    end_body_ratio: float = 0.75,
    limb_taper: float = 0.3,
    corner_length: float = 0.5,
    corner_reach: float = 1.16,
    junction_merge_radii: float = 0.8,
    limb_sigma_margin: float = 0.05,
    limb_loop_variation: float = 0.065,
    no_limbs_below_sigma_min: bool = False,
    no_passages_as_body: bool = False,
    no_shared_body_reference: bool = False,
    no_two_sided_siblings: bool = False,
    no_body_check_below_sigma_min: bool = False,
    no_passage_area_check: bool = False,
    no_body_end_check: bool = False,
    no_body_radius_window: bool = False,
    surface_loops: bool = False,
    tight_levels_in_runs: bool = False,
    no_stub_limbs: bool = False,
    no_separation_check: bool = False,
    no_fork_junctions: bool = False,
    no_grow_regions: bool = False,
    handles_on_genus_zero: bool = False,
    joint_ratio: float = 0.82,
    bend_angle: float = 360.0,
    joint_min_part: float = 0.25,
) -> MeshSegmentationResult: ...
@overload
def read_volume(
    path: PathLike,
    *,
    grid: Optional[str] = None,
    with_spacing: Literal[False] = False,
    max_memory: Union[None, int, str] = None,
    time_limit: Optional[float] = None,
) -> npt.NDArray[np.bool_]: ...
@overload
def read_volume(
    path: PathLike,
    *,
    grid: Optional[str] = None,
    with_spacing: Literal[True],
    max_memory: Union[None, int, str] = None,
    time_limit: Optional[float] = None,
) -> Tuple[npt.NDArray[np.bool_], Tuple[float, float, float]]: ...
def read_mesh(path: PathLike) -> Mesh: ...
def read_seg(path: PathLike) -> npt.NDArray[np.int64]: ...
def score(
    labels: npt.ArrayLike,
    human_labels: Union[npt.ArrayLike, Sequence[npt.ArrayLike]],
    *,
    face_areas: Optional[npt.ArrayLike] = None,
) -> Score: ...
def sequence_consensus(
    frame_labels: Sequence[npt.ArrayLike], trusted: Optional[Sequence[bool]] = ...
) -> SequenceConsensus: ...
