"""``python manage.py load_demo``: an administrator, a fleet with a token, a cluster and applications.

Idempotent: running it again changes nothing that exists. The administrator's password and the fleet token's
key are random, kept in var/demo-credentials.txt (the database holds only the key's hash) and printed.

The cluster, the applications and the first schedule come from the apps that own them: each registers a demo
step (``apps.tenancy.demo.register_demo``), so this command imports no domain app.
"""

import secrets
from pathlib import Path

from django.conf import settings
from django.contrib.auth import get_user_model
from django.core.management.base import BaseCommand
from django.db import transaction

from apps.tenancy.demo import Demo, demo_steps
from apps.tenancy.models import Fleet, FleetToken, hash_token_key


class Command(BaseCommand):
    help = "Load demo data: admin user, a fleet and its token, an edge cluster, two applications, a schedule."

    def handle(self, *args, **options) -> None:
        credentials = Path(settings.VAR_DIR) / "demo-credentials.txt"
        with transaction.atomic():
            password = self._admin(credentials)
            fleet, key = self._fleet(credentials)
            demo = Demo(fleet=fleet)
            for step in demo_steps():
                step(demo)
        for then in demo.after_commit:
            then()
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
