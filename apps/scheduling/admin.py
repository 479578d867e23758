from django.contrib import admin

from .models import Assignment, Schedule


class AssignmentInline(admin.TabularInline):
    model = Assignment
    extra = 0
    readonly_fields = ["task", "frame", "processor", "start", "finish", "niceness", "placement", "pod_name"]


@admin.register(Schedule)
class ScheduleAdmin(admin.ModelAdmin):
    list_display = ["id", "application", "algorithm", "makespan", "cluster", "created"]
    list_filter = ["algorithm", "fleet"]
    inlines = [AssignmentInline]
