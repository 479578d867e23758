"""Continuum's node agent: runs a command as a SCHED_DEADLINE task and reports its runtime overruns.

The node half of RT-Kube (thesis 3.4): the RealTime resource's runtime (the node's WCET), deadline and period are
applied with ``sched_setattr`` and ``SCHED_FLAG_DL_OVERRUN``; every SIGXCPU the kernel raises on an overrun is
counted (the command is traced, see :mod:`.trace`) and reported to the monitoring endpoint every 0.5 s
(:mod:`.report`). Standard library only, no Django: it runs on a robot without the rest of Continuum::

    python -m continuum.agent run --runtime-ms R --deadline-ms D --period-ms P \\
        [--realtime NAME --server URL --token T] [--json] -- COMMAND ARGS...
"""
