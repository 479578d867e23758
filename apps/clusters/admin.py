from django import forms
from django.contrib import admin

from apps.kube.kubeconfig import KubeconfigError, validate

from .models import Cluster, ComputeNode, Link
from .serializers import CREDENTIALS_PERMISSION


class ComputeNodeInline(admin.TabularInline):
    model = ComputeNode
    extra = 0
    fields = ["name", "arch", "cpu", "memory_mib", "processor_class", "speed", "rt", "criticality", "status"]


class ClusterForm(forms.ModelForm):
    """The kubeconfig is write-only: the form never shows the stored one. Empty keeps it; "clear" removes it.
    A new one is validated (apps.kube.kubeconfig) before anything is saved."""

    kubeconfig = forms.CharField(
        required=False,
        strip=False,
        widget=forms.Textarea(attrs={"rows": 8, "autocomplete": "off"}),
        help_text="write-only: paste a kubeconfig with inline credentials to replace the stored one, or leave empty "
        "to keep it (exec, auth-provider, tokenFile, file paths and proxy-url are refused)",
    )
    clear_kubeconfig = forms.BooleanField(required=False, help_text="remove the stored kubeconfig (model-only)")

    class Meta:
        model = Cluster
        fields = "__all__"

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        if "kubeconfig" in self.fields:
            self.initial["kubeconfig"] = ""  # never render the stored credentials

    def clean(self):
        data = super().clean()
        if "kubeconfig" not in self.fields:
            return data  # no permission: the stored credentials stay as they are
        from apps.kube.gateway import server_policy

        text = data.get("kubeconfig") or ""
        if data.get("clear_kubeconfig"):
            data["kubeconfig"] = ""
        elif not text.strip():
            data["kubeconfig"] = self.instance.kubeconfig if self.instance.pk else ""
        context_changed = "kube_context" in self.changed_data
        if (text.strip() or context_changed) and data["kubeconfig"]:
            try:
                validate(data["kubeconfig"], data.get("kube_context") or "", server_policy())
            except KubeconfigError as exc:
                self.add_error("kube_context" if exc.path == "kube_context" else "kubeconfig", str(exc))
        return data


class ClusterFormWithoutCredentials(ClusterForm):
    kubeconfig = None
    clear_kubeconfig = None

    class Meta(ClusterForm.Meta):
        exclude = ["kubeconfig", "kube_context"]


@admin.register(Cluster)
class ClusterAdmin(admin.ModelAdmin):
    form = ClusterForm
    list_display = ["name", "fleet", "namespace", "has_kubeconfig", "last_synced"]
    list_filter = ["fleet"]
    search_fields = ["name"]
    inlines = [ComputeNodeInline]

    @admin.display(boolean=True, description="kubeconfig")
    def has_kubeconfig(self, obj) -> bool:
        return bool(obj.kubeconfig)

    def get_form(self, request, obj=None, **kwargs):
        if not request.user.has_perm(CREDENTIALS_PERMISSION):
            # Without the permission the credentials are neither shown nor settable.
            kwargs["form"] = ClusterFormWithoutCredentials
        return super().get_form(request, obj, **kwargs)


@admin.register(ComputeNode)
class ComputeNodeAdmin(admin.ModelAdmin):
    list_display = ["name", "cluster", "arch", "cpu", "memory_mib", "rt", "criticality", "rt_threshold", "status"]
    list_filter = ["cluster", "arch", "status", "rt", "criticality", "capacity_source"]
    search_fields = ["name"]
    # What Kubernetes reports is node sync's; capacity_source says whether sync keeps cpu/memory/storage.
    readonly_fields = ["reported_cpu", "reported_memory_mib", "reported_storage_mib"]


@admin.register(Link)
class LinkAdmin(admin.ModelAdmin):
    list_display = ["cluster", "src", "dst", "bandwidth_mbps", "latency_ms"]
    list_filter = ["cluster"]
