"""keylo: keypoint-assisted LiDAR odometry, from Python.

The pipeline of a keylo config fed frame by frame (``Odometry``), the frames of every source
keylo reads as numpy arrays (``open``), and keylo's exceptions. See docs/python.md.
"""

from keylo._keylo import (
    ConfigError,
    DataError,
    Frame,
    FrameResult,
    KeyloError,
    Odometry,
    PluginError,
    Reader,
    StageError,
    __version__,
    evaluate,
    open,
    register_detector,
)



def sim(scene="lab", frames=100, **keys):
    """Simulated frames and their ground truth: ``(frames, stamps, poses)``.

    ``scene`` is ``lab``, ``corridor`` or ``road``; more keys are the simulator's ``[source]``
    keys (``sensor``, ``columns``, ``motion_distortion``, …). ``poses`` is N×4×4.
    """
    reader = open(kind="sim", scene=scene, frames=frames, **keys)
    out = list(reader)
    stamps, poses = reader.ground_truth()
    return out, stamps, poses


__all__ = [
    "ConfigError",
    "DataError",
    "Frame",
    "FrameResult",
    "KeyloError",
    "Odometry",
    "PluginError",
    "Reader",
    "StageError",
    "__version__",
    "evaluate",
    "open",
    "register_detector",
    "sim",
]
