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
    open,
)

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
    "open",
]
