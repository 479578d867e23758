"""Signals of the scheduling app, so that apps above it extend what its jobs do without it importing them."""

from django.dispatch import Signal

#: Sent by a job once it has stored a schedule (and its assignments), outside the storing transaction, with
#: ``schedule`` (the :class:`~apps.scheduling.models.Schedule` row) and ``progress`` (the job's progress
#: callback, or None). HEFT4K simulates its schedules here (``apps.heft4k.simulation``).
schedule_stored = Signal()
