"""HEFT4K (thesis 3.3.2): HEFT mapping plus niceness for Kubernetes, event-driven remapping, the CFS
simulator it is evaluated on, the Kubernetes baselines and the synthetic benchmark generator.
"""

__all__ = ["cfs_sim", "heft4k", "k8s_baselines", "remap", "synthetic"]
