"""Fleet tokens hashed at rest (second step): drop the clear-text key, the hash becomes unique and required."""

from django.db import migrations, models


class Migration(migrations.Migration):
    dependencies = [("tenancy", "0002_token_hashing")]

    operations = [
        migrations.RemoveField(model_name="fleettoken", name="key"),
        migrations.AlterField(
            model_name="fleettoken",
            name="key_hash",
            field=models.CharField(editable=False, help_text="SHA-256 of the key", max_length=64, unique=True),
        ),
    ]
