from django.contrib import admin

from .models import Application


@admin.register(Application)
class ApplicationAdmin(admin.ModelAdmin):
    list_display = ["name", "fleet", "source_format", "task_count", "edge_count", "created"]
    list_filter = ["fleet", "source_format"]
    search_fields = ["name"]
    readonly_fields = ["task_count", "edge_count"]
