from django.contrib import admin

from .models import Cluster, ComputeNode, Link


class ComputeNodeInline(admin.TabularInline):
    model = ComputeNode
    extra = 0
    fields = ["name", "arch", "cpu", "memory_mib", "processor_class", "speed", "rt", "criticality", "status"]


@admin.register(Cluster)
class ClusterAdmin(admin.ModelAdmin):
    list_display = ["name", "fleet", "namespace", "last_synced"]
    list_filter = ["fleet"]
    search_fields = ["name"]
    inlines = [ComputeNodeInline]


@admin.register(ComputeNode)
class ComputeNodeAdmin(admin.ModelAdmin):
    list_display = ["name", "cluster", "arch", "cpu", "memory_mib", "rt", "criticality", "rt_threshold", "status"]
    list_filter = ["cluster", "arch", "status", "rt", "criticality"]
    search_fields = ["name"]


@admin.register(Link)
class LinkAdmin(admin.ModelAdmin):
    list_display = ["cluster", "src", "dst", "bandwidth_mbps", "latency_ms"]
    list_filter = ["cluster"]
