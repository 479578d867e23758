"""Kubernetes credentials across the trust boundary (issue 10): who may set a kubeconfig, what is refused at
save and again at load (legacy rows), encryption at rest, and that a refused kubeconfig never runs a command
nor reads a server file nor calls an arbitrary host."""

import base64
import http.server
import importlib
import threading

import pytest
import yaml
from django.db import connection

from apps.clusters.models import Cluster
from apps.jobs.models import Job

pytestmark = [pytest.mark.kube, pytest.mark.django_db(transaction=True)]


def run(client, url: str) -> dict:
    response = client.post(url, {}, format="json")
    assert response.status_code == 202, response.data
    job = client.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] in ("succeeded", "failed"), job
    return job


def exec_kubeconfig(marker, server: str = "https://127.0.0.1:6443") -> str:
    """What a hostile kubeconfig looks like: loading it with the official client runs the command."""
    return yaml.safe_dump(
        {
            "apiVersion": "v1",
            "kind": "Config",
            "clusters": [{"name": "c", "cluster": {"server": server}}],
            "users": [
                {
                    "name": "u",
                    "user": {
                        "exec": {
                            "apiVersion": "client.authentication.k8s.io/v1beta1",
                            "command": "/bin/sh",
                            "args": ["-c", f"touch {marker}"],
                        }
                    },
                }
            ],
            "contexts": [{"name": "x", "context": {"cluster": "c", "user": "u"}}],
            "current-context": "x",
        }
    )


def token_file_kubeconfig(path, server: str) -> str:
    return yaml.safe_dump(
        {
            "clusters": [{"name": "c", "cluster": {"server": server}}],
            "users": [{"name": "u", "user": {"tokenFile": str(path)}}],
            "contexts": [{"name": "x", "context": {"cluster": "c", "user": "u"}}],
            "current-context": "x",
        }
    )


def store_raw(cluster: Cluster, text: str) -> None:
    """Write the column directly, as a row saved before validation and encryption existed."""
    with connection.cursor() as cursor:
        cursor.execute("UPDATE clusters_cluster SET kubeconfig = %s WHERE id = %s", [text, cluster.pk])


def raw_column(cluster: Cluster) -> str:
    with connection.cursor() as cursor:
        cursor.execute("SELECT kubeconfig FROM clusters_cluster WHERE id = %s", [cluster.pk])
        return cursor.fetchone()[0]


@pytest.fixture
def listener():
    """An HTTP server on 127.0.0.2 that records every request (the SSRF target)."""
    seen: list[dict] = []

    class Handler(http.server.BaseHTTPRequestHandler):
        def do_GET(self):
            seen.append({"path": self.path, "authorization": self.headers.get("Authorization")})
            self.send_response(200)
            self.send_header("Content-Type", "application/json")
            self.end_headers()
            self.wfile.write(b'{"kind": "NodeList", "apiVersion": "v1", "items": []}')

        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.2", 0), Handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.2:{server.server_address[1]}", seen
    server.shutdown()
    server.server_close()


# ---- who may set credentials ------------------------------------------------------------------------------
def test_a_fleet_token_cannot_set_a_kubeconfig(api, fleet, cluster, cluster_doc, kube_server):
    good = kube_server.kubeconfig()
    doc = {**cluster_doc, "name": "robotic", "kubeconfig": good}
    response = api.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 403 and "change_cluster_credentials" in str(response.data["kubeconfig"])
    assert not Cluster.objects.filter(name="robotic").exists()
    response = api.post("/api/v1/clusters/", {"fleet": fleet.slug, "name": "bare", "kubeconfig": good}, format="json")
    assert response.status_code == 403, response.data
    assert not Cluster.objects.filter(name="bare").exists()
    response = api.patch(f"/api/v1/clusters/{cluster.pk}/", {"kubeconfig": good}, format="json")
    assert response.status_code == 403, response.data
    response = api.patch(f"/api/v1/clusters/{cluster.pk}/", {"kube_context": "other"}, format="json")
    assert response.status_code == 403 and "kube_context" in response.data
    cluster.refresh_from_db()
    assert cluster.kubeconfig == "" and cluster.kube_context == ""
    # Everything else stays the robots' to change, and an empty kubeconfig is no change.
    response = api.patch(f"/api/v1/clusters/{cluster.pk}/", {"description": "x", "kubeconfig": ""}, format="json")
    assert response.status_code == 200, response.data


def test_an_operator_needs_the_permission(cluster, operator, kube_admin, kube_server):
    from rest_framework.test import APIClient

    client = APIClient()
    client.force_login(operator)  # a member of the fleet, without clusters.change_cluster_credentials
    good = kube_server.kubeconfig()
    assert client.patch(f"/api/v1/clusters/{cluster.pk}/", {"kubeconfig": good}, format="json").status_code == 403
    response = kube_admin.patch(f"/api/v1/clusters/{cluster.pk}/", {"kubeconfig": good}, format="json")
    assert response.status_code == 200 and response.data["has_kubeconfig"] is True
    assert "kubeconfig" not in response.data  # write-only
    assert "kubeconfig" not in kube_admin.get(f"/api/v1/clusters/{cluster.pk}/").data


# ---- refused at save --------------------------------------------------------------------------------------
def test_an_exec_kubeconfig_is_refused_at_save_and_runs_nothing(kube_admin, cluster, cluster_doc, tmp_path):
    marker = tmp_path / "pwned"
    response = kube_admin.patch(
        f"/api/v1/clusters/{cluster.pk}/", {"kubeconfig": exec_kubeconfig(marker)}, format="json"
    )
    assert response.status_code == 400
    assert response.data["kubeconfig"][0].startswith("users[0].user.exec: not allowed: ")
    doc = {**cluster_doc, "name": "hostile", "kubeconfig": exec_kubeconfig(marker)}
    response = kube_admin.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 400 and "users[0].user.exec" in response.data["kubeconfig"][0]
    assert not Cluster.objects.filter(name="hostile").exists()
    cluster.refresh_from_db()
    assert cluster.kubeconfig == "" and not marker.exists()


def test_token_file_and_plain_http_are_refused_at_save(kube_admin, cluster, tmp_path):
    secret = tmp_path / "secret_key"
    secret.write_text("the-django-secret")
    for server, field in (("http://127.0.0.2:8080", "clusters[0].cluster.server"),
                          ("https://127.0.0.2:8443", "users[0].user.tokenFile")):  # fmt: skip
        body = {"kubeconfig": token_file_kubeconfig(secret, server)}
        response = kube_admin.patch(f"/api/v1/clusters/{cluster.pk}/", body, format="json")
        assert response.status_code == 400 and response.data["kubeconfig"][0].startswith(f"{field}: "), response.data
    cluster.refresh_from_db()
    assert cluster.kubeconfig == ""


def test_http_on_loopback_only_with_the_setting(kube_admin, cluster, settings, listener):
    server, seen = listener
    kubeconfig = yaml.safe_dump(
        {
            "clusters": [{"name": "c", "cluster": {"server": server}}],
            "users": [{"name": "u", "user": {"token": "loopback-token"}}],
            "contexts": [{"name": "x", "context": {"cluster": "c", "user": "u"}}],
            "current-context": "x",
        }
    )
    url = f"/api/v1/clusters/{cluster.pk}/"
    response = kube_admin.patch(url, {"kubeconfig": kubeconfig}, format="json")
    assert response.status_code == 400 and "must use https" in response.data["kubeconfig"][0]
    settings.CONTINUUM_KUBE_ALLOW_HTTP_LOOPBACK = True
    assert kube_admin.patch(url, {"kubeconfig": kubeconfig}, format="json").status_code == 200
    remote = kubeconfig.replace(server, "http://10.1.2.3:8080")
    response = kube_admin.patch(url, {"kubeconfig": remote}, format="json")
    assert response.status_code == 400 and "only allowed on a loopback" in response.data["kubeconfig"][0]
    # The one accepted is used as given: the sync reaches the loopback server with the token.
    job = run(kube_admin, f"/api/v1/clusters/{cluster.pk}/sync/")
    assert job["state"] == "succeeded", job
    assert seen and seen[0]["path"] == "/api/v1/nodes" and seen[0]["authorization"] == "Bearer loopback-token"


def test_the_allow_list_applies_at_save_and_at_load(kube_admin, cluster, settings, kube_server, make_node):
    url = f"/api/v1/clusters/{cluster.pk}/"
    settings.CONTINUUM_KUBE_API_ALLOWED_HOSTS = ["10.0.0.0/8", "k8s.example.org"]
    response = kube_admin.patch(url, {"kubeconfig": kube_server.kubeconfig()}, format="json")
    assert response.status_code == 400 and "'127.0.0.1' is not in the allowed" in response.data["kubeconfig"][0]
    settings.CONTINUUM_KUBE_API_ALLOWED_HOSTS = ["127.0.0.0/8"]
    assert kube_admin.patch(url, {"kubeconfig": kube_server.kubeconfig()}, format="json").status_code == 200
    make_node("allowed-node")
    assert run(kube_admin, f"/api/v1/clusters/{cluster.pk}/sync/")["state"] == "succeeded"
    # Narrowed later: the stored kubeconfig is checked again when it is loaded.
    settings.CONTINUUM_KUBE_API_ALLOWED_HOSTS = ["k8s.example.org"]
    job = run(kube_admin, f"/api/v1/clusters/{cluster.pk}/sync/")
    assert job["state"] == "failed" and "not in the allowed Kubernetes API hosts" in job["error"]


# ---- refused at load: rows saved before the fix --------------------------------------------------------------
def test_a_legacy_exec_row_runs_nothing(api, cluster, tmp_path):
    marker = tmp_path / "pwned"
    store_raw(cluster, exec_kubeconfig(marker))
    job = run(api, f"/api/v1/clusters/{cluster.pk}/sync/")
    assert job["state"] == "failed"
    assert job["error"] == (
        "cluster 'edge': kubeconfig refused: users[0].user.exec: not allowed: it would run a command on the "
        "Continuum server; give an inline token or client certificate"
    )
    # RT-Kube's paths load the same kubeconfig (in a job now, formerly in the web request).
    node = cluster.nodes.first().name
    body = {"cluster": cluster.pk, "name": "cam", "criticality": "A", "period": 10, "deadline": 10,
            "wcets": [{"node": node, "wcet": 2}]}  # fmt: skip
    response = api.post("/api/v1/realtimes/", body, format="json")
    assert response.status_code == 201 and response.data["sync_state"] == "error"
    assert "users[0].user.exec" in response.data["sync_error"]
    push = Job.objects.get(kind="rt_push")
    assert push.state == "failed" and "users[0].user.exec" in push.error
    assert not marker.exists()


def test_a_legacy_token_file_row_reads_no_file_and_calls_no_host(api, cluster, settings, tmp_path, listener):
    server, seen = listener
    secret = tmp_path / "secret_key"
    secret.write_text("the-django-secret")
    settings.CONTINUUM_KUBE_ALLOW_HTTP_LOOPBACK = True  # even then: the tokenFile alone is refused
    store_raw(cluster, token_file_kubeconfig(secret, server))
    job = run(api, f"/api/v1/clusters/{cluster.pk}/sync/")
    assert job["state"] == "failed" and "users[0].user.tokenFile: not allowed" in job["error"]
    settings.CONTINUUM_KUBE_ALLOW_HTTP_LOOPBACK = False
    job = run(api, f"/api/v1/clusters/{cluster.pk}/sync/")
    assert job["state"] == "failed" and "clusters[0].cluster.server: must use https" in job["error"]
    assert seen == []  # nothing reached the host, least of all the file's content


# ---- encryption at rest -----------------------------------------------------------------------------------------
def test_credentials_are_encrypted_at_rest_and_legacy_rows_keep_working(kube_admin, cluster, kube_server, make_node):
    token = kube_server.token
    url = f"/api/v1/clusters/{cluster.pk}/"
    assert kube_admin.patch(url, {"kubeconfig": kube_server.kubeconfig()}, format="json").status_code == 200
    stored = raw_column(cluster)
    ca = base64.b64encode(kube_server.ca_path.read_bytes()).decode()
    assert stored.startswith("fernet:") and token not in stored and ca[:40] not in stored
    assert Cluster.objects.get(pk=cluster.pk).kubeconfig == kube_server.kubeconfig().strip()
    make_node("crypt-node")
    assert run(kube_admin, f"/api/v1/clusters/{cluster.pk}/sync/")["state"] == "succeeded"
    # A row stored in plain text before encryption existed still works ...
    store_raw(cluster, kube_server.kubeconfig())
    assert run(kube_admin, f"/api/v1/clusters/{cluster.pk}/sync/")["state"] == "succeeded"
    # ... and the migration encrypts it.
    migration = importlib.import_module("apps.clusters.migrations.0002_kubeconfig_credentials")

    class Editor:
        pass

    editor = Editor()
    editor.connection = connection
    from django.apps import apps as django_apps

    migration.encrypt_existing(django_apps, editor)
    stored = raw_column(cluster)
    assert stored.startswith("fernet:") and token not in stored
    assert Cluster.objects.get(pk=cluster.pk).kubeconfig == kube_server.kubeconfig()


def test_key_rotation_and_a_lost_key(kube_admin, cluster, settings, kube_server, make_node):
    from cryptography.fernet import Fernet

    old = list(settings.CONTINUUM_CREDENTIALS_KEYS)
    url = f"/api/v1/clusters/{cluster.pk}/"
    assert kube_admin.patch(url, {"kubeconfig": kube_server.kubeconfig()}, format="json").status_code == 200
    new = Fernet.generate_key().decode()
    settings.CONTINUUM_CREDENTIALS_KEYS = [new, *old]  # rotation: the new key first, the old one kept
    assert Cluster.objects.get(pk=cluster.pk).kubeconfig == kube_server.kubeconfig().strip()
    from django.core.management import call_command

    call_command("rotate_credentials", verbosity=0)
    settings.CONTINUUM_CREDENTIALS_KEYS = [new]  # the old key dropped: the row was re-encrypted
    make_node("rotated-node")
    assert run(kube_admin, f"/api/v1/clusters/{cluster.pk}/sync/")["state"] == "succeeded"
    settings.CONTINUUM_CREDENTIALS_KEYS = [Fernet.generate_key().decode()]  # a key that opens nothing
    assert kube_admin.get(url).data["has_kubeconfig"] is True
    job = run(kube_admin, f"/api/v1/clusters/{cluster.pk}/sync/")
    assert job["state"] == "failed" and "cannot be decrypted with CONTINUUM_CREDENTIALS_KEY" in job["error"]
    # Saving other fields keeps the ciphertext as it was (the right key may come back).
    stored = raw_column(cluster)
    assert kube_admin.patch(url, {"description": "still here"}, format="json").status_code == 200
    assert raw_column(cluster) == stored
