"""Fleet tokens hashed at rest: add prefix, key_hash, scope and expiry, and hash every existing key.

Existing tokens keep working (their keys hash to the stored value) and keep the rights they had (scope
"operator"). The clear-text column is dropped in 0003, in its own transaction.
"""

import hashlib

from django.db import migrations, models


def hash_keys(apps, schema_editor) -> None:
    FleetToken = apps.get_model("tenancy", "FleetToken")
    for token in FleetToken.objects.only("pk", "key"):
        FleetToken.objects.filter(pk=token.pk).update(
            prefix=token.key[:8], key_hash=hashlib.sha256(token.key.encode()).hexdigest()
        )


class Migration(migrations.Migration):
    dependencies = [("tenancy", "0001_initial")]

    operations = [
        migrations.AddField(
            model_name="fleettoken",
            name="prefix",
            field=models.CharField(
                db_index=True, default="", editable=False, help_text="first characters of the key", max_length=8
            ),
            preserve_default=False,
        ),
        migrations.AddField(
            model_name="fleettoken",
            name="key_hash",
            field=models.CharField(editable=False, max_length=64, null=True),
        ),
        migrations.AddField(
            model_name="fleettoken",
            name="scope",
            field=models.CharField(
                choices=[
                    ("robot", "robot: read the fleet, post reports and events"),
                    ("operator", "operator: read and change the fleet"),
                ],
                default="operator",
                max_length=16,
            ),
        ),
        migrations.AddField(
            model_name="fleettoken",
            name="expires",
            field=models.DateTimeField(blank=True, help_text="empty: never expires", null=True),
        ),
        # Irreversible on purpose: the clear-text keys are gone once hashed.
        migrations.RunPython(hash_keys, migrations.RunPython.noop),
    ]
