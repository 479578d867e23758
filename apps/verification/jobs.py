"""Job kinds of the verification app: ``allocate_monitors`` (the MILP on a cluster's statistics or a given
``continuum.monitorstats/v1`` document) and ``verification_simulation`` (a thesis case study, stored as a
series of allocation runs so the dashboard can draw it)."""

from django.db import transaction
from django.urls import reverse

from apps.jobs.registry import job_kind
from apps.verification.kinds import VerificationJob
from continuum.engine.verification.abv_simulation import scenario as make_scenario
from continuum.engine.verification.abv_simulation import simulate

from . import services
from .models import AllocationRun


@job_kind(VerificationJob.ALLOCATE_MONITORS)
def allocate_monitors(job, progress) -> tuple[dict, str]:
    """Arguments: ``cluster`` (id) or ``stats`` (a monitorstats document), ``apply`` (bool), ``work_limit``
    (branch-and-bound nodes per solve; default the engine's), optional ``time_limit`` (a wall-clock cap)."""
    run = services.run_allocation(job, progress)
    result = {
        "allocation_run": run.pk,
        "status": run.status,
        "feasible": run.feasible,
        "objective": run.objective,
        "migrations": run.migrations.count(),
        "solve_time_ms": run.solve_time_ms,
        # How far from proven: the relative gap and the best bound on the objective it leaves.
        "gap": (run.result or {}).get("gap"),
        "bound": _bound(run.objective, (run.result or {}).get("gap")),
        "applied": run.applied,
        "page": reverse("verification:run", args=[run.pk]),
    }
    return result, f"/api/v1/allocations/{run.pk}/"


def _bound(objective: float | None, gap: float | None) -> float | None:
    """The solver's best bound on the total delay: HiGHS's gap is (objective - bound) / objective."""
    if objective is None or gap is None:
        return None
    return objective * (1 - gap)


@job_kind(VerificationJob.VERIFICATION_SIMULATION)
def verification_simulation(job, progress) -> tuple[dict, str]:
    """Arguments: ``scenario`` ("kairos" or "synthetic"), optional ``duration_s`` and ``time_limit``.

    A re-delivered job replaces what a previous attempt stored."""
    args = job.arguments or {}
    options = {}
    for key in ("duration_s", "time_limit"):
        if args.get(key) is not None:
            value = args[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or value <= 0:
                raise ValueError(f"argument {key!r} must be a positive number, got {value!r}")
            options[key] = float(value)
    sc = make_scenario(str(args.get("scenario", "kairos")), **options)
    progress(2, f"simulating {sc.name}: {len(sc.monitors)} monitors, {sc.duration_s:g} s")
    result = simulate(sc, progress=lambda pct, msg: progress(2 + 0.9 * pct, msg))
    with transaction.atomic():
        AllocationRun.objects.filter(job=job).delete()
        series, _runs = services.store_simulation(job.fleet, result, job=job)
    summary = result.summary()
    page = reverse("verification:series", args=[series])
    return {"series": str(series), "scenario": sc.name, "summary": summary, "page": page}, page
