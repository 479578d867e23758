from django.contrib import admin

from .models import Fleet, FleetToken


class FleetTokenInline(admin.TabularInline):
    model = FleetToken
    extra = 0
    readonly_fields = ["key", "created", "last_used"]


@admin.register(Fleet)
class FleetAdmin(admin.ModelAdmin):
    list_display = ["name", "slug", "created"]
    search_fields = ["name", "slug"]
    prepopulated_fields = {"slug": ["name"]}
    filter_horizontal = ["members"]
    inlines = [FleetTokenInline]


@admin.register(FleetToken)
class FleetTokenAdmin(admin.ModelAdmin):
    list_display = ["fleet", "user", "description", "created", "last_used"]
    list_filter = ["fleet"]
    readonly_fields = ["key", "created", "last_used"]
