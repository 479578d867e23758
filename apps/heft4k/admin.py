from django.contrib import admin

from .models import RemapEvent


@admin.register(RemapEvent)
class RemapEventAdmin(admin.ModelAdmin):
    list_display = ["id", "application", "schedule", "new_schedule", "trigger", "decision", "status", "created"]
    list_filter = ["trigger", "decision", "status", "fleet"]
    readonly_fields = [f.name for f in RemapEvent._meta.fields]
