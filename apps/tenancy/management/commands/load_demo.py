"""``python manage.py load_demo``: an administrator, a fleet with a token, a cluster and applications.

Idempotent: running it again changes nothing that exists. The administrator's password and the fleet token's
key are random, kept in var/demo-credentials.txt (the database holds only the key's hash) and printed.
"""

import secrets
from pathlib import Path

from django.conf import settings
from django.contrib.auth import get_user_model
from django.core.management.base import BaseCommand
from django.db import transaction

from apps.clusters.models import Cluster, ComputeNode, Link
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from apps.tenancy.models import Fleet, FleetToken, hash_token_key
from apps.workloads.models import Application
from continuum.engine.formats import load_dag

DATA = Path(settings.BASE_DIR) / "tests" / "data"


class Command(BaseCommand):
    help = "Load demo data: admin user, a fleet and its token, an edge cluster, two applications, a schedule."

    def handle(self, *args, **options) -> None:
        credentials = Path(settings.VAR_DIR) / "demo-credentials.txt"
        with transaction.atomic():
            password = self._admin(credentials)
            fleet, key = self._fleet(credentials)
            cluster = self._cluster(fleet)
            apps = self._applications(fleet)
        if not apps[0].schedules.exists():
            arguments = {"application": apps[0].pk, "algorithm": "heft", "cluster": cluster.pk}
            start_job(SchedulingJob.SCHEDULE, fleet, arguments)
        self.stdout.write(f"demo ready: log in as admin / {password}  (fleet token for the API: {key})")

    def _admin(self, credentials: Path) -> str:
        User = get_user_model()
        admin = User.objects.filter(username="admin").first()
        if admin is None or not credentials.exists():
            password = secrets.token_urlsafe(9)
            admin = admin or User(username="admin", is_staff=True, is_superuser=True)
            admin.set_password(password)
            admin.save()
            credentials.parent.mkdir(parents=True, exist_ok=True)
            credentials.write_text(f"admin {password}\n")
            credentials.chmod(0o600)
        return credentials.read_text().split()[1]

    def _fleet(self, credentials: Path) -> tuple[Fleet, str]:
        """The demo fleet and its token's key: the one kept in the credentials file while it still
        authenticates, else a new token (keys are stored hashed, so a lost one cannot be read back)."""
        fleet, _ = Fleet.objects.get_or_create(slug="demo", defaults={"name": "Demo fleet"})
        fleet.members.add(get_user_model().objects.get(username="admin"))
        robot, _ = get_user_model().objects.get_or_create(username="demo-robot")
        lines = credentials.read_text().splitlines()
        kept = next((line.split()[1] for line in lines if line.startswith("token ")), None)
        if kept and FleetToken.objects.filter(fleet=fleet, key_hash=hash_token_key(kept)).exists():
            return fleet, kept
        _, key = FleetToken.objects.create_token(fleet=fleet, user=robot, description="demo robot fleet")
        lines = [line for line in lines if not line.startswith("token ")] + [f"token {key}"]
        credentials.write_text("\n".join(lines) + "\n")
        return fleet, key

    def _cluster(self, fleet: Fleet) -> Cluster:
        cluster, created = Cluster.objects.get_or_create(
            fleet=fleet, name="edge-cloud", defaults={"description": "robot, edge and cloud"}
        )
        if created:
            spec = [
                ("robot-board", "arm64", 4, 4096, 1.0),
                ("jetson", "arm64", 8, 16384, 1.5),
                ("edge-server", "amd64", 16, 65536, 2.5),
                ("cloud-vm", "amd64", 32, 131072, 3.0),
            ]
            nodes = {
                name: ComputeNode.objects.create(
                    cluster=cluster, name=name, arch=arch, cpu=cpu, memory_mib=mem, speed=speed
                )
                for name, arch, cpu, mem, speed in spec
            }
            for a, b, mbps, ms in [
                ("robot-board", "jetson", 1000, 0.2),
                ("jetson", "edge-server", 866, 2.0),
                ("edge-server", "cloud-vm", 100, 20.0),
            ]:
                Link.objects.create(cluster=cluster, src=nodes[a], dst=nodes[b], bandwidth_mbps=mbps, latency_ms=ms)
        return cluster

    def _applications(self, fleet: Fleet) -> list[Application]:
        result = []
        for name, fmt in [("montage-chameleon-2mass-005d-001.json", None), ("topcuoglu.dag.json", None)]:
            graph = load_dag((DATA / name).read_text(), fmt)
            app = Application.objects.filter(fleet=fleet, name=graph.name).first()
            if app is None:
                app = Application(
                    fleet=fleet, name=graph.name, source_format=graph.meta.get("source_format", "continuum")
                )
                app.set_graph(graph)
                app.save()
            result.append(app)
        return result
