"""Continuum's scheduling engine: plain Python, no Django.

One module per method of the thesis, named after it, grouped by thesis chapter:

    core/          types, formats of record, limits and safe loaders every method shares
    formats/       the outside DAG formats (DAX, STG, WfFormat, the thesis' CSV)
    device/        device-level DAG scheduling (3.1)
    containers/    ROS nodes -> containers -> nodes (3.2-3.3.1)
    heft4k/        HEFT4K placement, niceness and remapping (3.3.2)
    rtkube/        RT-Kube real-time containers (3.4)
    verification/  STL assertion monitors and their placement (3.5)

The apps call these modules; the engine never imports Django or ``apps`` (an import-linter contract
checks it), so the algorithms can be tested, benchmarked and reused on their own.

Core types:
    :class:`~continuum.engine.core.dag.TaskGraph`      an application DAG (``continuum.dag/v1``)
    :class:`~continuum.engine.core.platform.Platform`  processors and the network between them
    :class:`~continuum.engine.core.schedule.Schedule`  the one schedule type that flows from the engine to the
                                                  database, the charts, the API and Kubernetes
"""

from continuum.engine.core.dag import Edge, Task, TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform, Processor
from continuum.engine.core.schedule import Assignment, Schedule

# Methods of the later chapters add themselves to the scheduler list of continuum.engine.device.registry
# when imported; importing them here makes that list complete whichever engine module is imported first.
from continuum.engine.heft4k import heft4k as _heft4k  # noqa: F401  (registers "heft4k")

__all__ = ["Assignment", "Edge", "InputError", "Platform", "Processor", "Schedule", "Task", "TaskGraph"]
