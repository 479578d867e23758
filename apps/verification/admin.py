from django.contrib import admin

from .models import AllocationRun, Assertion, Handler, MigrationEvent, Monitor, MonitorVerdict, Violation


@admin.register(Assertion)
class AssertionAdmin(admin.ModelAdmin):
    list_display = ["name", "fleet", "text", "created"]
    list_filter = ["fleet"]
    search_fields = ["name", "text"]
    readonly_fields = ["skeleton", "placeholders", "variables"]


@admin.register(Monitor)
class MonitorAdmin(admin.ModelAdmin):
    list_display = ["name", "assertion", "cluster", "node", "tolerant", "verdict", "events", "violation_count"]
    list_filter = ["fleet", "cluster", "verdict", "tolerant"]
    search_fields = ["name"]
    readonly_fields = ["verdict", "events", "violation_count", "active_instances", "cpu"]


@admin.register(Handler)
class HandlerAdmin(admin.ModelAdmin):
    list_display = [
        "node",
        "cluster",
        "threshold",
        "delay_ms",
        "free_cpu",
        "verification_cpu",
        "is_coordinator",
        "last_seen",
    ]
    list_filter = ["cluster", "is_coordinator"]


@admin.register(Violation)
class ViolationAdmin(admin.ModelAdmin):
    list_display = ["monitor", "time_ms", "instance_start_ms", "handler", "created"]
    list_filter = ["handler"]
    readonly_fields = [f.name for f in Violation._meta.fields]


@admin.register(MonitorVerdict)
class MonitorVerdictAdmin(admin.ModelAdmin):
    list_display = ["monitor", "verdict", "handler", "created"]
    readonly_fields = [f.name for f in MonitorVerdict._meta.fields]


class MigrationInline(admin.TabularInline):
    model = MigrationEvent
    extra = 0
    readonly_fields = ["monitor_name", "source", "target", "t", "events_moved"]
    fields = readonly_fields


@admin.register(AllocationRun)
class AllocationRunAdmin(admin.ModelAdmin):
    list_display = [
        "id",
        "fleet",
        "source",
        "scenario",
        "t",
        "status",
        "n_monitors",
        "n_nodes",
        "objective",
        "solve_time_ms",
        "created",
    ]
    list_filter = ["fleet", "source", "status", "scenario"]
    readonly_fields = [f.name for f in AllocationRun._meta.fields]
    inlines = [MigrationInline]


@admin.register(MigrationEvent)
class MigrationEventAdmin(admin.ModelAdmin):
    list_display = ["monitor_name", "source", "target", "t", "events_moved", "run"]
    list_filter = ["source", "target"]
    readonly_fields = [f.name for f in MigrationEvent._meta.fields]
