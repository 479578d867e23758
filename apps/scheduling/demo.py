"""The demo's first schedule (``load_demo``): HEFT of the first demo application on the demo cluster."""

from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from apps.tenancy.demo import Demo


def demo_schedule(demo: Demo) -> None:
    """Start a ``schedule`` job (after the demo data is committed) unless the application has a schedule."""
    app, cluster = demo.objects["applications"][0], demo.objects["cluster"]
    if not app.schedules.exists():
        arguments = {"application": app.pk, "algorithm": "heft", "cluster": cluster.pk}
        demo.after_commit.append(lambda: start_job(SchedulingJob.SCHEDULE, demo.fleet, arguments))
