"""Core types and input handling shared by every method: DAGs, platforms, clusters, the one schedule
and the one placement type, taints, limits and the safe loaders for untrusted input.
"""

__all__ = [
    "artifact_names",
    "cluster",
    "dag",
    "errors",
    "limits",
    "placement",
    "platform",
    "safeload",
    "schedule",
    "taints",
    "unique",
]
