"""The ROS 2 message definitions a recording's schemas hold (the ``.msg``
files of ROS 2's common_interfaces, fields only), each schema the type's
definition followed by those of the types it uses, in the concatenated form
``ros2 bag`` writes (``=====`` lines and ``MSG: pkg/Type``)."""

from __future__ import annotations

__all__ = ["msgdef"]

_FIELDS = {
    "builtin_interfaces/Time": "int32 sec\nuint32 nanosec",
    "std_msgs/Header": "builtin_interfaces/Time stamp\nstring frame_id",
    "geometry_msgs/Point": "float64 x\nfloat64 y\nfloat64 z",
    "geometry_msgs/Vector3": "float64 x\nfloat64 y\nfloat64 z",
    "geometry_msgs/Quaternion": "float64 x\nfloat64 y\nfloat64 z\nfloat64 w",
    "geometry_msgs/Pose": "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation",
    "geometry_msgs/PoseStamped": "std_msgs/Header header\ngeometry_msgs/Pose pose",
    "geometry_msgs/PoseWithCovariance": "geometry_msgs/Pose pose\nfloat64[36] covariance",
    "geometry_msgs/Twist": "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular",
    "geometry_msgs/TwistWithCovariance": "geometry_msgs/Twist twist\nfloat64[36] covariance",
    "geometry_msgs/Wrench": "geometry_msgs/Vector3 force\ngeometry_msgs/Vector3 torque",
    "geometry_msgs/WrenchStamped": "std_msgs/Header header\ngeometry_msgs/Wrench wrench",
    "geometry_msgs/Transform": "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation",
    "geometry_msgs/TransformStamped": "std_msgs/Header header\nstring child_frame_id\n"
                                      "geometry_msgs/Transform transform",
    "nav_msgs/Odometry": "std_msgs/Header header\nstring child_frame_id\n"
                         "geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist",
    "sensor_msgs/Imu": "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n"
                       "float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n"
                       "float64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\n"
                       "float64[9] linear_acceleration_covariance",
    "tf2_msgs/TFMessage": "geometry_msgs/TransformStamped[] transforms",
    "std_msgs/MultiArrayDimension": "string label\nuint32 size\nuint32 stride",
    "std_msgs/MultiArrayLayout": "std_msgs/MultiArrayDimension[] dim\nuint32 data_offset",
    "std_msgs/Float64MultiArray": "std_msgs/MultiArrayLayout layout\nfloat64[] data",
}
_RULE = "=" * 80


def _uses(name: str) -> list[str]:
    """The message types `name`'s fields use, depth first, each once."""
    found: list[str] = []
    for line in _FIELDS[name].splitlines():
        kind = line.split()[0].split("[")[0]
        if "/" in kind:
            for t in (kind, *_uses(kind)):
                if t not in found:
                    found.append(t)
    return found


def msgdef(datatype: str) -> str:
    """The schema text of `datatype` (``nav_msgs/msg/Odometry``)."""
    name = datatype.replace("/msg/", "/")
    return "\n".join([_FIELDS[name], *(f"{_RULE}\nMSG: {t}\n{_FIELDS[t]}" for t in _uses(name))]) + "\n"
