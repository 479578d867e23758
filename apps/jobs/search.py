"""Finding jobs: the ``?search=`` of the jobs list and of ``GET /api/v1/jobs/`` (one function, so both answer
alike), and what a list row shows of a job's arguments without loading them (a job's arguments may hold a
platform document of megabytes)."""

from __future__ import annotations

from functools import reduce
from operator import and_

from django.db.models import Q, QuerySet
from django.db.models.fields.json import KT

from apps.ui.links import objects_named

#: Text columns a search word is looked for in (case-insensitive), besides the named rows below.
TEXT_FIELDS = ("kind", "state", "message", "arguments__algorithm")
#: Arguments naming a row by pk: a word matches a job whose argument names a row whose name contains it.
NAMED_ARGUMENTS = ("application", "cluster")


def search_jobs(jobs: QuerySet, term: str) -> QuerySet:
    """``jobs`` whose every word of ``term`` is in their kind, state, message or algorithm, or in the name
    of the application or cluster they work on."""
    words = term.split()
    if not words:
        return jobs

    def one(word: str) -> Q:
        q = Q()
        for field in TEXT_FIELDS:
            q |= Q(**{f"{field}__icontains": word})
        for key in NAMED_ARGUMENTS:
            ids = objects_named(key, word)
            if ids:
                q |= Q(**{f"arguments__{key}__in": ids})
        return q

    return jobs.filter(reduce(and_, (one(w) for w in words)))


def with_subject(jobs: QuerySet) -> QuerySet:
    """``jobs`` annotated with what a list row shows: ``subject_application`` (pk) and ``subject_algorithm``,
    read from the arguments by the database (the list defers the arguments themselves)."""
    return jobs.annotate(subject_application=KT("arguments__application"), subject_algorithm=KT("arguments__algorithm"))
