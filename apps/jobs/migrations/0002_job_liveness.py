from django.db import migrations, models


class Migration(migrations.Migration):
    dependencies = [("jobs", "0001_initial")]

    operations = [
        migrations.AddField(
            model_name="job",
            name="worker",
            field=models.CharField(blank=True, help_text="host:pid of the process running the job", max_length=200),
        ),
        migrations.AddField(
            model_name="job",
            name="heartbeat",
            field=models.DateTimeField(
                blank=True, help_text="last sign of life of a worker's run (in-process runs send none)", null=True
            ),
        ),
        migrations.AddField(
            model_name="job",
            name="interruption",
            field=models.CharField(
                blank=True,
                help_text="why an earlier attempt ended unfinished (e.g. its worker was lost)",
                max_length=300,
            ),
        ),
    ]
