"""Continuum's fleet client for robots and operators: the typed client generated from the OpenAPI schema
(:mod:`continuum.client`, by ``scripts/gen-client``), the calls robots make (:mod:`.api`), recorded runs read
without ROS (:mod:`.rosbag`) and the command line ``python -m continuum.fleet`` (:mod:`.cli`). No Django:
install ``requirements-robot.txt`` and copy ``continuum/client`` and ``continuum/fleet`` (or the repo).
"""

from .api import ApiError, Fleet, JobFailed, MissReport

__all__ = ["ApiError", "Fleet", "JobFailed", "MissReport"]
