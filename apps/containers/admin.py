from django.contrib import admin

from .models import Clustering, ContainerDeployment, Placement, RosGraph


@admin.register(RosGraph)
class RosGraphAdmin(admin.ModelAdmin):
    list_display = ["name", "fleet", "source_format", "node_count", "topic_count", "created"]
    list_filter = ["fleet", "source_format"]
    search_fields = ["name", "description"]
    readonly_fields = ["node_count", "topic_count", "created", "updated"]


@admin.register(Clustering)
class ClusteringAdmin(admin.ModelAdmin):
    list_display = [
        "rosgraph",
        "fleet",
        "container_count",
        "requested_containers",
        "inter_container_bandwidth",
        "disk_before_mib",
        "disk_after_mib",
        "created",
    ]
    list_filter = ["fleet"]
    search_fields = ["rosgraph__name"]
    raw_id_fields = ["rosgraph", "job"]


class ContainerDeploymentInline(admin.TabularInline):
    model = ContainerDeployment
    extra = 0
    fields = ["container", "node", "deployment", "namespace", "state", "message"]
    readonly_fields = fields


@admin.register(Placement)
class PlacementAdmin(admin.ModelAdmin):
    list_display = [
        "pk",
        "fleet",
        "policy",
        "cluster",
        "placed_count",
        "pending_count",
        "inter_node_bandwidth",
        "created",
    ]
    list_filter = ["fleet", "policy"]
    raw_id_fields = ["clustering", "rosgraph", "cluster", "job"]
    inlines = [ContainerDeploymentInline]


@admin.register(ContainerDeployment)
class ContainerDeploymentAdmin(admin.ModelAdmin):
    list_display = ["container", "placement", "node", "deployment", "state", "updated"]
    list_filter = ["state"]
    search_fields = ["container", "deployment"]
