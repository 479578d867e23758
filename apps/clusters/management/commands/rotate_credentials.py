"""``manage.py rotate_credentials``: re-encrypt every stored kubeconfig with the newest key.

Rotation: put the new key first in CONTINUUM_CREDENTIALS_KEY (``new,old``), run this, then drop the old key.
Plain-text rows (written before encryption existed) are encrypted too. A row no key opens is reported and
left as it is (exit status 1).
"""

from django.core.management.base import BaseCommand, CommandError
from django.db import connection, transaction

from apps.clusters.models import Cluster
from apps.kube.credentials import Undecryptable, decrypt, rotate


class Command(BaseCommand):
    help = "Re-encrypt every cluster's kubeconfig with the newest CONTINUUM_CREDENTIALS_KEY."

    def handle(self, *args, **options):
        table = connection.ops.quote_name(Cluster._meta.db_table)
        done, lost = 0, []
        with transaction.atomic(), connection.cursor() as cursor:
            # Raw rows: the model field would decrypt on read and hide which rows are legacy plain text.
            lock = " FOR UPDATE" if connection.features.has_select_for_update else ""
            cursor.execute(f"SELECT id, name, kubeconfig FROM {table} WHERE kubeconfig <> ''{lock}")
            for pk, name, stored in cursor.fetchall():
                if isinstance(decrypt(stored), Undecryptable):
                    lost.append(name)
                    continue
                cursor.execute(f"UPDATE {table} SET kubeconfig = %s WHERE id = %s", [rotate(stored), pk])
                done += 1
        self.stdout.write(f"re-encrypted {done} kubeconfig(s)")
        if lost:
            raise CommandError(f"no configured key opens the kubeconfig of: {', '.join(sorted(lost))}")
