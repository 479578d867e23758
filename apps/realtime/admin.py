"""Admin forms for RT-Kube's resources, validated by the engine's rules (spec 03 3.2: every number positive,
``WCET <= D <= P`` on every node, known nodes, a criticality the platform supports)."""

from django import forms
from django.contrib import admin, messages
from django.core.exceptions import ValidationError

from apps.jobs.services import start_job
from apps.realtime.kinds import RealtimeJob
from continuum.engine.core.errors import InputError

from .kube import has_api
from .models import (
    Monitoring,
    MonitoringReport,
    NodeTaint,
    RealTime,
    RealTimeWcet,
    RTDecision,
    RTEvent,
    RTPlan,
    RTPod,
    RTPolicy,
    engine_container,
)

PARENT_FIELDS = {"criticality", "period", "deadline", "cpu", "memory_mib", "stateless", "name"}


class RealTimeForm(forms.ModelForm):
    class Meta:
        model = RealTime
        fields = ["cluster", "namespace", "name", "criticality", "period", "deadline", "stateless", "cpu", "memory_mib"]

    def clean(self):
        data = super().clean()
        if self.errors:
            return data
        deadline = data.get("deadline")
        # The WCETs are checked with the inline rows; here a stand-in WCET checks the other fields.
        probe = deadline if isinstance(deadline, int | float) and deadline > 0 else 1.0
        try:
            engine_container(
                data.get("name") or "?",
                data.get("criticality") or "",
                data.get("period"),
                deadline,
                [("?", probe)],
                stateless=data.get("stateless", False),
                cpu=data.get("cpu"),
                memory_mib=data.get("memory_mib"),
            )
        except InputError as exc:
            field = exc.field if exc.field in PARENT_FIELDS else None
            raise ValidationError({field: str(exc)} if field else str(exc)) from exc
        return data


class WcetFormSet(forms.BaseInlineFormSet):
    """Checks the rows against the parent's values (``self.instance`` carries the submitted ones)."""

    def clean(self):
        super().clean()
        if any(self.errors):
            return
        parent: RealTime = self.instance
        rows = [f for f in self.forms if f.cleaned_data and not f.cleaned_data.get("DELETE")]
        if not rows:
            raise ValidationError("give the WCET of at least one node")
        pairs = []
        for f in rows:
            node, wcet = f.cleaned_data["node"], f.cleaned_data["wcet"]
            if parent.cluster_id and node.cluster_id != parent.cluster_id:
                f.add_error("node", f"node {node.name!r} is not a node of cluster {parent.cluster.name!r}")
                return
            pairs.append((node.name, wcet))
        try:
            engine_container(
                parent.name,
                parent.criticality,
                parent.period,
                parent.deadline,
                pairs,
                known_nodes=[n.name for n in parent.cluster.nodes.all()] if parent.cluster_id else None,
            )
        except InputError as exc:
            culprit = next((f for f in rows if repr(f.cleaned_data["node"].name) in str(exc)), None)
            if culprit is not None and exc.field in ("wcet", "wcets"):
                culprit.add_error("wcet", str(exc))
            elif exc.field not in PARENT_FIELDS:  # the parent form already said it
                raise ValidationError(str(exc)) from exc


class WcetInline(admin.TabularInline):
    model = RealTimeWcet
    formset = WcetFormSet
    extra = 1
    fields = ["node", "wcet", "position"]

    def get_formset(self, request, obj=None, **kwargs):
        formset = super().get_formset(request, obj, **kwargs)
        if obj is not None:
            formset.form.base_fields["node"].queryset = obj.cluster.nodes.all()
        return formset


@admin.register(RealTime)
class RealTimeAdmin(admin.ModelAdmin):
    form = RealTimeForm
    inlines = [WcetInline]
    list_display = ["name", "namespace", "cluster", "criticality", "period", "deadline", "stateless", "sync_state"]
    list_filter = ["cluster", "criticality", "sync_state"]
    search_fields = ["name"]
    readonly_fields = ["uid", "resource_version", "sync_state", "sync_error", "created", "updated"]

    def get_changeform_initial_data(self, request):
        return {"namespace": "continuum", **super().get_changeform_initial_data(request)}

    def save_model(self, request, obj, form, change):
        obj.dirty = True
        super().save_model(request, obj, form, change)

    def save_related(self, request, form, formsets, change):
        super().save_related(request, form, formsets, change)
        row = form.instance
        if has_api(row.cluster):
            # A job, not a Kubernetes call in this request (it runs at once without a broker).
            job = start_job(RealtimeJob.RT_PUSH, row.cluster.fleet, {"realtimes": [row.pk]}, request.user)
            if job.state == job.State.SUCCEEDED:
                messages.info(request, f"RealTime {row} written to the Kubernetes API of {row.cluster}.")
            elif job.state == job.State.FAILED:
                messages.warning(request, f"RealTime {row} saved here, not in Kubernetes: {job.error}")
            else:
                messages.info(request, f"RealTime {row} saved; job {job.pk} writes it to the Kubernetes API.")


@admin.register(RTPolicy)
class RTPolicyAdmin(admin.ModelAdmin):
    list_display = ["cluster", "threshold_period", "threshold_total", "eviction_policy", "taint_duration_s", "k"]


class MonitoringForm(forms.ModelForm):
    class Meta:
        model = Monitoring
        fields = ["cluster", "name", "node", "container_name", "pod", "missed_period", "missed_total", "received_at"]

    def clean(self):
        data = super().clean()
        node, cluster = data.get("node"), data.get("cluster")
        if node is not None and cluster is not None and node.cluster_id != cluster.pk:
            self.add_error("node", f"node {node.name!r} is not a node of cluster {cluster.name!r}")
        period, total = data.get("missed_period"), data.get("missed_total")
        if period is not None and total is not None and total < period:
            self.add_error("missed_total", f"missedDeadlinesTotal {total} < missedDeadlinesPeriod {period}")
        return data


@admin.register(Monitoring)
class MonitoringAdmin(admin.ModelAdmin):
    form = MonitoringForm
    list_display = ["name", "cluster", "node", "container_name", "missed_period", "missed_total", "received_at"]
    list_filter = ["cluster"]


class ReadOnly(admin.ModelAdmin):
    def has_add_permission(self, request):
        return False

    def has_change_permission(self, request, obj=None):
        return False


@admin.register(MonitoringReport)
class MonitoringReportAdmin(ReadOnly):
    list_display = ["received_at", "cluster", "node", "container_name", "missed_period", "missed_total", "violation"]
    list_filter = ["cluster", "violation", "source"]


@admin.register(RTEvent)
class RTEventAdmin(ReadOnly):
    list_display = ["received_at", "cluster", "kind", "node", "container", "victim", "response_ms"]
    list_filter = ["cluster", "kind"]


@admin.register(NodeTaint)
class NodeTaintAdmin(ReadOnly):
    list_display = ["node", "key", "value", "effect", "created", "expires_at", "lifted_at"]
    list_filter = ["cluster"]


@admin.register(RTPod)
class RTPodAdmin(ReadOnly):
    list_display = ["name", "namespace", "cluster", "node", "criticality", "stateless", "utilization", "deleted_at"]
    list_filter = ["cluster", "criticality"]


@admin.register(RTDecision)
class RTDecisionAdmin(ReadOnly):
    list_display = ["created", "cluster", "namespace", "pod", "outcome", "node", "score"]
    list_filter = ["cluster", "outcome"]


@admin.register(RTPlan)
class RTPlanAdmin(ReadOnly):
    list_display = ["created", "cluster", "kind", "placed", "pending"]
    list_filter = ["cluster", "kind"]
