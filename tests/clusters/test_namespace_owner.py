"""Issue 25: two fleets registering the same Kubernetes API would share a namespace, hence pods and live state;
a cluster's namespace of one API belongs to one fleet."""

from __future__ import annotations

import pytest
from django.contrib.auth.models import Permission
from rest_framework.test import APIClient

from tests.kubeapi import kubeconfig_text

pytestmark = pytest.mark.django_db
CA = b"-----BEGIN CERTIFICATE-----\nMIIB\n-----END CERTIFICATE-----\n"


def operator_of(fleet, django_user_model, name):
    user = django_user_model.objects.create_user(name)
    fleet.members.add(user)
    user.user_permissions.add(Permission.objects.get(codename="change_cluster_credentials"))
    client = APIClient()
    client.force_login(user)
    return client


def register(client, fleet, cluster_doc, server, namespace, name="edge"):
    body = {**cluster_doc, "name": name, "fleet": fleet.slug if hasattr(fleet, "slug") else fleet.pk,
            "kubeconfig": kubeconfig_text(server, "t0ken", CA), "namespace": namespace}  # fmt: skip
    return client.post("/api/v1/clusters/import/", body, format="json")


def test_another_fleet_cannot_take_a_namespace_of_the_same_api(fleets, django_user_model, cluster_doc):
    first, second = fleets[0], fleets[1]
    a, b = operator_of(first, django_user_model, "a"), operator_of(second, django_user_model, "b")
    assert register(a, first, cluster_doc, "https://10.1.2.3:6443", "robots").status_code == 201
    taken = register(b, second, cluster_doc, "https://10.1.2.3:6443", "robots")
    assert taken.status_code == 400 and "another fleet" in str(taken.data["namespace"])
    # Another namespace of that API, or the same namespace of another API, is the second fleet's to use.
    assert register(b, second, cluster_doc, "https://10.1.2.3:6443", "robots-b").status_code == 201
    assert register(b, second, cluster_doc, "https://10.9.9.9:6443", "robots", name="other").status_code == 201
    # Nor can it move a cluster it has into the first fleet's namespace.
    own = b.get("/api/v1/clusters/").data["results"][0]["id"]
    moved = b.patch(f"/api/v1/clusters/{own}/", {"namespace": "robots"}, format="json")
    assert moved.status_code == 400 and "namespace" in moved.data
