"""RT-Kube (thesis 3.4): the real-time container model, admission and placement, the cluster-level
monitor (reconcile and recovery) and the discrete-event simulator.
"""

__all__ = ["rt_kube", "rt_model", "rt_sim", "rt_victims"]
