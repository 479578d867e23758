"""Continuum's scheduling engine: plain Python, no Django.

One module per method of the thesis, named after it. The apps call these modules; they never import
Django, so the algorithms can be tested, benchmarked and reused on their own.

Core types:
    :class:`~continuum.engine.dag.TaskGraph`      an application DAG (``continuum.dag/v1``)
    :class:`~continuum.engine.platform.Platform`  processors and the network between them
    :class:`~continuum.engine.schedule.Schedule`  the one schedule type that flows from the engine to the
                                                  database, the charts, the API and Kubernetes
"""

from .dag import Edge, Task, TaskGraph
from .errors import InputError
from .platform import Platform, Processor
from .schedule import Assignment, Schedule

__all__ = ["Assignment", "Edge", "InputError", "Platform", "Processor", "Schedule", "Task", "TaskGraph"]
