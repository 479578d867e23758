"""Runtime verification (thesis 3.5): the STL assertion language, Boolean monitors with lossless
migration, the monitor-allocation MILP and the ABV case-study simulation.
"""

__all__ = ["abv_simulation", "monitor_milp", "stl_monitor", "stl_parser"]
