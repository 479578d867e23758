"""Kubeconfigs encrypted at rest (Fernet, apps.kube.credentials) and the permission to set them."""

from django.db import migrations

import apps.kube.credentials


def encrypt_existing(apps, schema_editor):
    """Encrypt every plain-text kubeconfig written before this migration (re-encrypt with the newest key)."""
    from apps.kube.credentials import Undecryptable, decrypt, rotate

    table = apps.get_model("clusters", "Cluster")._meta.db_table
    connection = schema_editor.connection
    qn = connection.ops.quote_name
    with connection.cursor() as cursor:
        cursor.execute(f"SELECT id, kubeconfig FROM {qn(table)} WHERE kubeconfig <> ''")
        rows = cursor.fetchall()
        for pk, stored in rows:
            if isinstance(decrypt(stored), Undecryptable):
                continue  # encrypted with a key not configured here: leave it for that key
            cursor.execute(f"UPDATE {qn(table)} SET kubeconfig = %s WHERE id = %s", [rotate(stored), pk])


def decrypt_existing(apps, schema_editor):
    """Back to plain text (the field before this migration); a value no key opens is left as it is."""
    from apps.kube.credentials import Undecryptable, decrypt

    table = apps.get_model("clusters", "Cluster")._meta.db_table
    connection = schema_editor.connection
    qn = connection.ops.quote_name
    with connection.cursor() as cursor:
        cursor.execute(f"SELECT id, kubeconfig FROM {qn(table)} WHERE kubeconfig <> ''")
        for pk, stored in cursor.fetchall():
            plain = decrypt(stored)
            if not isinstance(plain, Undecryptable):
                cursor.execute(f"UPDATE {qn(table)} SET kubeconfig = %s WHERE id = %s", [plain, pk])


class Migration(migrations.Migration):
    dependencies = [
        ("clusters", "0001_initial"),
    ]

    operations = [
        migrations.AlterModelOptions(
            name="cluster",
            options={
                "ordering": ["name"],
                "permissions": [
                    ("change_cluster_credentials", "Can set a cluster's Kubernetes credentials (kubeconfig, context)")
                ],
            },
        ),
        migrations.AlterField(
            model_name="cluster",
            name="kubeconfig",
            field=apps.kube.credentials.EncryptedTextField(
                blank=True,
                help_text="kubeconfig (YAML) of this cluster's Kubernetes API; empty for a model-only cluster",
            ),
        ),
        migrations.RunPython(encrypt_existing, decrypt_existing),
    ]
