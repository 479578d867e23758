"""The cluster admin's kubeconfig: write-only, validated before saving, only for holders of
clusters.change_cluster_credentials."""

import base64

import pytest
import yaml

from apps.clusters.models import Cluster

pytestmark = pytest.mark.django_db

CA = base64.b64encode(b"-----BEGIN CERTIFICATE-----\nMIIBfake\n-----END CERTIFICATE-----\n").decode()


def kubeconfig(user: dict, server: str = "https://k8s.example.org:6443") -> str:
    return yaml.safe_dump(
        {
            "clusters": [{"name": "c", "cluster": {"server": server, "certificate-authority-data": CA}}],
            "users": [{"name": "u", "user": user}],
            "contexts": [{"name": "x", "context": {"cluster": "c", "user": "u"}}],
            "current-context": "x",
        }
    )


GOOD = kubeconfig({"token": "admin-secret-token"})


@pytest.fixture
def bare(fleet):
    return Cluster.objects.create(fleet=fleet, name="bare")


def form(cluster: Cluster, **fields) -> dict:
    data = {
        "fleet": cluster.fleet_id,
        "name": cluster.name,
        "description": "",
        "kube_context": "",
        "namespace": "continuum",
        "default_latency_ms": "0",
        "nodes-TOTAL_FORMS": "0",
        "nodes-INITIAL_FORMS": "0",
        "nodes-MIN_NUM_FORMS": "0",
        "nodes-MAX_NUM_FORMS": "1000",
    }
    data.update(fields)
    return data


def change(client, cluster: Cluster, **fields):
    return client.post(f"/admin/clusters/cluster/{cluster.pk}/change/", form(cluster, **fields))


@pytest.fixture
def root(client, django_user_model):
    client.force_login(django_user_model.objects.create_superuser("root", "root@example.com", "root-pass-123"))
    return client


def test_the_admin_validates_and_never_shows_the_kubeconfig(root, bare, tmp_path):
    marker = tmp_path / "pwned"
    hostile = kubeconfig({"exec": {"command": "/bin/sh", "args": ["-c", f"touch {marker}"]}})
    response = change(root, bare, kubeconfig=hostile)
    assert response.status_code == 200  # the form again, with the error
    assert "users[0].user.exec: not allowed" in " ".join(response.context["adminform"].form.errors["kubeconfig"])
    bare.refresh_from_db()
    assert bare.kubeconfig == "" and not marker.exists()

    assert change(root, bare, kubeconfig=GOOD).status_code == 302
    bare.refresh_from_db()
    assert bare.kubeconfig == GOOD
    page = root.get(f"/admin/clusters/cluster/{bare.pk}/change/").content.decode()
    assert "admin-secret-token" not in page and "write-only" in page
    # Empty keeps the stored one; a context it does not have is refused; "clear" removes it.
    assert change(root, bare, description="kept").status_code == 302
    bare.refresh_from_db()
    assert bare.kubeconfig == GOOD and bare.description == "kept"
    response = change(root, bare, kube_context="elsewhere")
    assert "no context named 'elsewhere'" in " ".join(response.context["adminform"].form.errors["kube_context"])
    assert change(root, bare, clear_kubeconfig="on").status_code == 302
    bare.refresh_from_db()
    assert bare.kubeconfig == ""


def test_without_the_permission_the_admin_has_no_credential_fields(client, django_user_model, bare):
    from django.contrib.auth.models import Permission

    staff = django_user_model.objects.create_user("staff", password="staff-pass-123", is_staff=True)
    staff.user_permissions.add(*Permission.objects.filter(codename__in=["view_cluster", "change_cluster"]))
    client.force_login(staff)
    response = client.get(f"/admin/clusters/cluster/{bare.pk}/change/")
    fields = response.context["adminform"].form.fields
    assert "kubeconfig" not in fields and "kube_context" not in fields and "clear_kubeconfig" not in fields
    data = form(bare, description="by staff", kubeconfig=GOOD)
    del data["kube_context"]
    assert client.post(f"/admin/clusters/cluster/{bare.pk}/change/", data).status_code == 302
    bare.refresh_from_db()
    assert bare.description == "by staff" and bare.kubeconfig == ""
