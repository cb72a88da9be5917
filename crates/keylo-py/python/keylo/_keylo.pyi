"""Type stubs of keylo's native module (crates/keylo-py)."""

import os
from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

__version__: str

class KeyloError(Exception): ...
class ConfigError(KeyloError): ...
class DataError(KeyloError): ...
class StageError(KeyloError): ...
class PluginError(KeyloError): ...

ConfigArg = str | os.PathLike[str] | Mapping[str, Any] | None

class FrameResult:
    """The result of one frame."""

    @property
    def index(self) -> int: ...
    @property
    def stamp(self) -> float: ...
    @property
    def pose(self) -> npt.NDArray[np.float64]:
        """4×4 sensor pose in the world (first-frame) frame."""
    @property
    def keypoint_count(self) -> int: ...
    @property
    def cloud_points(self) -> int: ...
    @property
    def registered_points(self) -> int: ...
    @property
    def degenerate(self) -> dict[str, Any] | None:
        """Why the registration could not constrain the pose (`reason`: `too-few-points` with
        `points`/`minimum`, `no-information` with `directions`), or None."""
    @property
    def map_points(self) -> int: ...
    @property
    def iterations(self) -> int: ...
    @property
    def converged(self) -> bool: ...
    @property
    def fitness(self) -> float | None:
        """Localisation (registrar kind "localise"): share of points fitting the map; None for odometry."""
    @property
    def tracking(self) -> bool | None:
        """Localisation: whether the fitness reached its threshold (False: pose not to be trusted)."""
    @property
    def timings(self) -> dict[str, float]:
        """Seconds per stage: image, detect, describe, downsample, register, total."""
    @property
    def degeneracy(self) -> dict[str, Any] | None: ...
    def covariance(self, sigma: float) -> npt.NDArray[np.float64] | None:
        """6×6 covariance sigma² H⁻¹ of the twist [tx, ty, tz, rx, ry, rz]."""
    @property
    def keypoints(self) -> list[dict[str, Any]]:
        """Per image: image, xy (N×2), size, angle, response, points (N×3), descriptors."""

class Frame:
    """One frame of a source; arrays are read-only views (no copy)."""

    @property
    def index(self) -> int: ...
    @property
    def timestamp(self) -> float: ...
    @property
    def rows(self) -> int: ...
    @property
    def cols(self) -> int: ...
    @property
    def range(self) -> npt.NDArray[np.float32]: ...
    @property
    def signal(self) -> npt.NDArray[np.float32]: ...
    @property
    def reflectivity(self) -> npt.NDArray[np.float32]: ...
    @property
    def near_ir(self) -> npt.NDArray[np.float32]: ...
    @property
    def valid(self) -> npt.NDArray[np.bool_]: ...
    @property
    def xyz(self) -> npt.NDArray[np.float32]:
        """rows×cols×3 sensor-frame points."""
    @property
    def column_times(self) -> npt.NDArray[np.float64]: ...
    @property
    def pixel_times(self) -> npt.NDArray[np.float64] | None:
        """rows×cols firing times (s) when rows fired at their own column offsets, else None."""
    @property
    def points(self) -> npt.NDArray[np.float64] | None:
        """Every point of an unorganised scan (N×3), None for organised sources."""
    @property
    def point_times(self) -> npt.NDArray[np.float64] | None: ...

class Reader(Iterator[Frame]):
    """The frames of a source."""

    def __iter__(self) -> Reader: ...
    def __next__(self) -> Frame: ...
    def ground_truth(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]] | None:
        """(stamps N, poses N×4×4), or None when the source has none."""

def open(
    path: str | os.PathLike[str] | None = None, kind: str | None = None, **keys: Any
) -> Reader:
    """The frames of `path` (kind detected) or of source `kind` (e.g. "sim")."""

class Odometry:
    """The per-frame stages of a config (TOML path, TOML text or dict). A config naming
    libraries of its own (plugins in its `[plugins] dirs`, an `onnxruntime` path) is refused
    unless `trust_plugins=True`: loading them runs their code (docs/python.md, "Trust")."""

    def __init__(self, config: ConfigArg = None, *, trust_plugins: bool = False) -> None: ...
    def process(
        self,
        points: npt.ArrayLike,
        times: npt.ArrayLike | None = None,
        stamp: float | None = None,
    ) -> FrameResult:
        """Registers an N×3 or N×4 (with intensity) scan."""
    def process_frame(self, frame: Frame) -> FrameResult: ...
    @property
    def kinds(self) -> dict[str, str]:
        """The backend of every stage, defaults filled in."""
    @property
    def frames(self) -> int: ...
    @property
    def trajectory(self) -> npt.NDArray[np.float64]:
        """N×4×4 poses."""
    @property
    def stamps(self) -> npt.NDArray[np.float64]: ...
    def local_map(self) -> npt.NDArray[np.float64]: ...
    def set_motion_prior(self, delta: npt.ArrayLike) -> None: ...
    def set_pose(self, pose: npt.ArrayLike) -> None: ...
    def reset(self) -> None: ...

def register_detector(name: str, obj: Any) -> None:
    """Makes `kind = "python:NAME"` a detector (obj.detect(image) -> N×2..N×5 array) and, with
    obj.describe(image, keypoints) -> (keypoints, descriptors), a descriptor, for every config
    built afterwards."""

def evaluate(
    est: str | os.PathLike[str] | npt.ArrayLike,
    gt: str | os.PathLike[str] | npt.ArrayLike,
    est_stamps: npt.ArrayLike | None = None,
    gt_stamps: npt.ArrayLike | None = None,
    align: str = "se3",
    t_max_diff: float = 0.01,
    t_offset: float = 0.0,
    rpe_delta: int = 1,
) -> dict[str, Any]:
    """ATE/RPE/drift as `keylo eval` computes them; files (TUM/KITTI) or N×4×4 arrays."""

def judge(
    est: str | os.PathLike[str] | npt.ArrayLike,
    gt: str | os.PathLike[str] | npt.ArrayLike | None = None,
    est_stamps: npt.ArrayLike | None = None,
    gt_stamps: npt.ArrayLike | None = None,
    max_ape: float = 2.0,
    max_step: float = 5.0,
    t_max_diff: float = 0.01,
) -> dict[str, Any]:
    """`keylo compare`'s verdict (`ok`/`diverged`), its reason and the aligned-APE columns."""

def evaluate_keypoints(
    images: Any,
    combos: str = "paper",
    spec: str | None = None,
    jobs: int = 1,
    *,
    trust_plugins: bool = False,
) -> tuple[list[dict[str, Any]], list[dict[str, Any]], list[tuple[str, str]]]:
    """See keylo.keypoints.evaluate."""
