# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""Conversions between the navigator's types and ROS messages (Navigate's outcome codes, poses)."""

from __future__ import annotations

import math

from builtin_interfaces.msg import Time
from geometry_msgs.msg import PoseStamped
from hexapod_msgs.action import Navigate
from hexapod_navigation.episode import Outcome
from hexapod_navigation.planner import Pose2D

#: Navigate.Result's outcome constant of each library outcome.
OUTCOME_CODES = {
    Outcome.REACHED: Navigate.Result.REACHED,
    Outcome.TIME_LIMIT: Navigate.Result.TIME_LIMIT,
    Outcome.LEFT_ARENA: Navigate.Result.LEFT_ARENA,
    Outcome.CANCELED: Navigate.Result.CANCELED,
    Outcome.FAILED: Navigate.Result.FAILED,
}


def pose_msg(pose: Pose2D, stamp: Time, frame: str = 'odom') -> PoseStamped:
    """Return a planar pose as a PoseStamped in ``frame``."""
    msg = PoseStamped()
    msg.header.stamp, msg.header.frame_id = stamp, frame
    msg.pose.position.x, msg.pose.position.y = pose.x, pose.y
    msg.pose.orientation.z = math.sin(pose.yaw / 2.0)
    msg.pose.orientation.w = math.cos(pose.yaw / 2.0)
    return msg
