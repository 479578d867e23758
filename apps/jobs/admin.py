from django.contrib import admin

from .models import Job


@admin.register(Job)
class JobAdmin(admin.ModelAdmin):
    list_display = ["id", "kind", "fleet", "state", "progress", "created", "finished"]
    list_filter = ["state", "kind", "fleet"]
    readonly_fields = [f.name for f in Job._meta.fields]
