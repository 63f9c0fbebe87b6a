"""linkage_ros: the ROS 2 side of the linkage solver.

``Motion`` (the time law), ``Engine`` (time → :class:`Frame`) and the message builder are plain
Python; only :mod:`linkage_ros.node` imports rclpy.
"""

from __future__ import annotations

from .engine import Engine
from .frame import Frame, JointState, PointState
from .motion import Motion, Segment

__all__ = ["Engine", "Frame", "JointState", "Motion", "PointState", "Segment"]
__version__ = "0.1.0"
