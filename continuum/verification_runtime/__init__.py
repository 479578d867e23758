"""Distributed runtime verification (thesis §3.5, Fig. 3.42): monitor handlers and the coordinator as
plain Python processes that talk through Redis (:mod:`.bus`). No Django.

* :mod:`.handler`: one process per computing unit; runs monitors, migrates them (Fig. 3.43), reports
  statistics, takes part in the election.
* :mod:`.coordinator`: elected among the handlers (most free CPU; re-elected when its lease lapses); runs
  the allocation MILP (:mod:`continuum.engine.verification.monitor_milp`) and sends EXEC/MIGRATE requests.
"""
