"""``python manage.py register_cluster --kubeconfig FILE --cluster-file FILE [--name N] [--fleet SLUG] [--json]``:
store a running Kubernetes cluster in Continuum and read its nodes now (what ``./scripts/cluster up --register``
runs, so the demo's local cluster is live on the dashboard).

The cluster file (``continuum.cluster/v1``, JSON or YAML) gives the nodes, links and Continuum's own attributes
(class, speed, RT threshold...), read exactly as ``POST /api/v1/clusters/import/`` reads it; the kubeconfig is
validated as every stored kubeconfig is (:mod:`apps.kube.kubeconfig`, the ``CONTINUUM_KUBE_*`` settings). Then
the nodes are synced from the API (:func:`apps.clusters.kube.sync_nodes`): labels, taints, Ready, and the
capacity Kubernetes reports, stored beside the file's (``reported_cpu``...: a kubemark hollow node reports 1 CPU
and 3840 MiB whatever the file says); the file's capacity stays the planning input.

Idempotent: registering again (after ``scripts/cluster down`` and ``up``, which makes a new kubeconfig) updates the
stored cluster's kubeconfig, nodes and links instead of failing. Exit status 2 with one line on stderr for bad
input (a missing or unreadable file, a refused kubeconfig, an unknown fleet); 1 when the API cannot be reached.
Only someone with a shell on the server runs it: it is not subject to the API's credentials permission.
"""

from __future__ import annotations

import uuid
from pathlib import Path
from typing import Any

from django.core.management.base import CommandError
from django.db import transaction

from apps.clusters import kube
from apps.clusters.models import Cluster, ComputeNode, Link
from apps.clusters.serializers import ClusterImportSerializer
from apps.kube.gateway import KubeError, server_policy
from apps.kube.kubeconfig import KubeconfigError, validate
from apps.tenancy.api import contract_error
from apps.tenancy.models import Fleet
from continuum.commands import EngineCommand
from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import load_yaml_all

#: The demo fleet (``load_demo``), the default when --fleet is not given.
DEFAULT_FLEET = "demo"
MAX_FILE_BYTES = 1 << 20


def _read(path: str, what: str) -> str:
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{what} {path}: no such file", what)
    if p.stat().st_size > MAX_FILE_BYTES:
        raise InputError(f"{what} {path}: larger than {MAX_FILE_BYTES} bytes", what)
    try:
        return p.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"{what} {path}: not UTF-8 text (byte {exc.start})", what) from exc


class _Document(ClusterImportSerializer):
    """The import API's document, with the fleet given by the operator at the shell (no request)."""

    fleet = None  # not a field: context["fleet"]

    def validate(self, attrs):
        return super().validate({**attrs, "fleet": self.context["fleet"]})


class Command(EngineCommand):
    help = "Store a running Kubernetes cluster (kubeconfig + cluster file) in Continuum and sync its nodes."

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("--kubeconfig", default="", help="the cluster's kubeconfig file (required)")
        parser.add_argument("--cluster-file", required=True, help="continuum.cluster/v1 file (JSON or YAML)")
        parser.add_argument("--name", default="", help="cluster name (default: the file's name, else its stem)")
        parser.add_argument("--fleet", default=DEFAULT_FLEET, help=f"fleet slug (default: {DEFAULT_FLEET})")
        parser.add_argument("--context", default="", help="kubeconfig context (default: its current-context)")
        parser.add_argument("--namespace", default="continuum", help="namespace Continuum pushes to")
        parser.add_argument("--no-sync", action="store_true", help="store only; do not read the nodes now")
        parser.add_argument(
            "--check-only",
            action="store_true",
            help="check the cluster file and the fleet only (before a cluster is started); no kubeconfig",
        )

    def run(self, **options: Any) -> dict:
        kubeconfig = ""
        if not options["check_only"]:
            if not options["kubeconfig"]:
                raise InputError("--kubeconfig FILE is required", "kubeconfig")
            kubeconfig = _read(options["kubeconfig"], "kubeconfig")
            try:
                validate(kubeconfig, options["context"], server_policy())
            except KubeconfigError as exc:
                raise InputError(f"kubeconfig {options['kubeconfig']}: {exc}", "kubeconfig") from exc
        docs = load_yaml_all(_read(options["cluster_file"], "cluster file"), "cluster file")  # JSON is YAML
        if len(docs) != 1 or not isinstance(docs[0], dict):
            raise InputError(f"{options['cluster_file']}: one continuum.cluster/v1 object expected", "cluster file")
        doc = docs[0]
        name = options["name"] or (doc.get("name") if isinstance(doc.get("name"), str) else "")
        name = name or Path(options["cluster_file"]).stem
        fleet = Fleet.objects.filter(slug=options["fleet"]).first()
        if fleet is None:
            hint = " (run ./scripts/start or `python manage.py load_demo` first)" if options["fleet"] == "demo" else ""
            raise InputError(f"fleet {options['fleet']!r} does not exist{hint}", "fleet")
        nodes, links = self._validated(doc, fleet, options["cluster_file"])
        if len(name) > 100:
            raise InputError(f"cluster name {name[:20]!r}...: at most 100 characters", "name")
        if options["check_only"]:
            return {"name": name, "fleet": fleet.slug, "nodes": len(nodes), "check_only": True}
        with transaction.atomic():
            cluster, created = Cluster.objects.select_for_update().get_or_create(
                fleet=fleet,
                name=name,
                defaults={"description": f"registered from {Path(options['cluster_file']).name}"},
            )
            cluster.kubeconfig = kubeconfig
            cluster.kube_context = options["context"]
            cluster.namespace = options["namespace"]
            cluster.save()
            rows = {}
            for raw in nodes:
                # The file declares the planning capacity: node sync keeps it (and stores what Kubernetes reports).
                fields = {k: v for k, v in raw.items() if k != "name"}
                fields["capacity_source"] = ComputeNode.Capacity.DECLARED
                rows[raw["name"]], _ = ComputeNode.objects.update_or_create(
                    cluster=cluster, name=raw["name"], defaults=fields
                )
            for link in links:
                Link.objects.update_or_create(
                    cluster=cluster,
                    src=rows[link["src"]],
                    dst=rows[link["dst"]],
                    defaults={"bandwidth_mbps": link["bandwidth_mbps"], "latency_ms": link["latency_ms"]},
                )
        result: dict[str, Any] = {"cluster": cluster.pk, "name": cluster.name, "fleet": fleet.slug,
                                  "cluster_created": created, "synced": False}  # fmt: skip
        if not options["no_sync"]:
            try:
                result.update(kube.sync_nodes(cluster))
            except KubeError as exc:
                raise CommandError(f"stored cluster {cluster.pk}, but: {exc}", returncode=1) from exc
            result["synced"] = True
        result["ready"] = list(
            cluster.nodes.filter(status=ComputeNode.Status.READY).order_by("name").values_list("name", flat=True)
        )
        result["not_ready"] = list(
            cluster.nodes.exclude(status=ComputeNode.Status.READY).order_by("name").values_list("name", flat=True)
        )
        return result

    @staticmethod
    def _validated(doc: dict, fleet: Fleet, path: str) -> tuple[list[dict], list[dict]]:
        """The document's nodes and links as the import API validates them (the engine's one parser). The
        name is a placeholder: registering again updates the cluster instead of refusing its name."""
        data = {k: v for k, v in doc.items() if k in ("format", "nodes", "links")}
        serializer = _Document(data={**data, "name": f"register-{uuid.uuid4().hex}"}, context={"fleet": fleet})
        if not serializer.is_valid():
            raise InputError(f"{path}: {contract_error(serializer.errors)}", "cluster file")
        return serializer.validated_data["nodes"], serializer.validated_data["links"]

    def summary(self, result: dict) -> str:
        if result.get("check_only"):
            return f"cluster file OK: {result['nodes']} nodes for cluster {result['name']!r} of fleet {result['fleet']}"
        verb = "created" if result["cluster_created"] else "updated"
        lines = [f"cluster {result['name']!r} (id {result['cluster']}, fleet {result['fleet']}) {verb}"]
        if result["synced"]:
            lines.append(
                f"{result['nodes']} nodes in the API: {len(result['ready'])} Ready"
                + (f", not Ready: {', '.join(result['not_ready'])}" if result["not_ready"] else "")
            )
        return "\n".join(lines)
