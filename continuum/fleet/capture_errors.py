"""The one error of a live capture (ROS 1 or ROS 2): the master or domain cannot be reached or answered
something else. The command line prints it as one line and exits 2."""


class CaptureError(Exception):
    """The master or the DDS domain cannot be reached or answered something unexpected."""
