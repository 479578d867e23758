"""Device-level DAG scheduling (thesis 3.1): HEFT, XEFT, G-FL, VisionWorks, multi-frame pipelines,
the schedule metrics of Table 3.x and the CPU-iGPU communication advisor (3.1.2).
"""

__all__ = [
    "algorithms",
    "board",
    "compare",
    "generators",
    "gfl",
    "heft",
    "overlap",
    "pipeline",
    "registry",
    "ros_transport",
    "uma_advisor",
    "visionworks",
    "xeft",
]
