"""Connecting to a Kubernetes API: the validated client, the timeout and retry of every call, and how a
failure is described.

The one builder of API clients is :func:`api_client`: it takes a kubeconfig's text (already decrypted) and a
context, validates them (:mod:`apps.kube.kubeconfig`: no exec plugin, no file path, a vetted server) and sets
the client's configuration field by field. The app owning the stored cluster passes its kubeconfig in
(``apps.clusters.kube.api_client_for``); nothing here reads another app's rows. API calls happen in jobs,
commands and long-running processes, never inside a web request.
"""

from __future__ import annotations

import atexit
import contextlib
import hashlib
import json
import os
import shutil
import tempfile
import threading
from collections.abc import Callable
from pathlib import Path

import urllib3
from django.conf import settings
from kubernetes import client
from kubernetes.client.exceptions import ApiException

from . import kubeconfig, retry
from .credentials import Undecryptable
from .kubeconfig import KubeconfigError, KubeTarget, ServerPolicy

#: (connect, read) seconds for every API call, so a black-holed API fails the job instead of hanging it.
REQUEST_TIMEOUT = (5, 30)

Progress = Callable[[float, str], None]
ApiClient = client.ApiClient


class KubeError(ValueError):
    """The Kubernetes API cannot be used (no/bad kubeconfig, unreachable, refused): the job fails cleanly."""


#: What an API call may raise when the server is unreachable, refuses us, or stayed failing past the deadline.
API_ERRORS = (ApiException, urllib3.exceptions.HTTPError, OSError, retry.GaveUp)
#: The same, plus an unusable kubeconfig or a body the client refused (both ``ValueError``).
KUBE_ERRORS = (ApiException, OSError, urllib3.exceptions.HTTPError, ValueError)


def call(fn, *args, what: str, server: str = "", idempotent: bool = True, **kwargs):
    """``fn(*args, **kwargs)`` through :func:`apps.kube.retry.call` (transient failures retried with backoff
    until ``CONTINUUM_KUBE_RETRY_DEADLINE_S``), every attempt with :data:`REQUEST_TIMEOUT`."""
    kwargs.setdefault("_request_timeout", REQUEST_TIMEOUT)
    if not server:  # a bound method of a CoreV1Api: name its server in the error
        server = server_of(getattr(getattr(fn, "__self__", None), "api_client", None))
    return retry.call(fn, *args, what=what, idempotent=idempotent, describe=lambda exc: describe(exc, server), **kwargs)


def read_json(fn, *args, **kwargs):
    """``fn(*args, **kwargs)`` of a generated API method, answered as the server's JSON (dicts, camelCase keys)
    instead of model objects: custom objects, Status answers and large pod lists need no deserializing."""
    kwargs.setdefault("_request_timeout", REQUEST_TIMEOUT)
    response = fn(*args, _preload_content=False, **kwargs)  # an error status raises ApiException
    data = response.data  # read it all, so the connection goes back to the pool
    response.release_conn()
    return json.loads(data) if data else None


def by_label(list_fn, namespace: str, label_selector: str, *, what: str, server: str = "") -> dict[str, dict]:
    """The objects a namespaced list call (``list_fn``, e.g. ``CoreV1Api.list_namespaced_pod``) answers for
    ``label_selector``, by name, as the server's JSON: what a push reads before its writes (the pods or
    Deployments already there). Raw JSON, not models: a re-push lists every object it made, and parsing
    thousands of V1Pods costs more CPU than the few fields read from them. Retried like any read."""
    listing = call(read_json, list_fn, namespace, label_selector=label_selector, what=what, server=server)
    return {item["metadata"]["name"]: item for item in (listing or {}).get("items") or []}


def server_of(api_client) -> str:
    return getattr(getattr(api_client, "configuration", None), "host", "") or ""


# -- connecting ---------------------------------------------------------------------------------------------


def server_policy() -> ServerPolicy:
    """Where kubeconfigs may point, from the settings (``CONTINUUM_KUBE_*``)."""
    return ServerPolicy(
        allow_http_loopback=settings.CONTINUUM_KUBE_ALLOW_HTTP_LOOPBACK,
        allowed_hosts=tuple(settings.CONTINUUM_KUBE_API_ALLOWED_HOSTS),
        max_bytes=settings.CONTINUUM_KUBECONFIG_MAX_BYTES,
    )


def target(text: str, context: str = "", *, name: str = "") -> KubeTarget:
    """The validated API target of a kubeconfig (``name``: the cluster's, for the messages). The kubeconfig is
    checked again on every load: rows saved before validation existed (or written to the database directly)
    get no pass."""
    if isinstance(text, Undecryptable):
        raise KubeError(
            f"cluster {name!r}: its kubeconfig cannot be decrypted with CONTINUUM_CREDENTIALS_KEY "
            "(was the key changed without keeping the old one?); set the kubeconfig again"
        )
    if not (text or "").strip():
        raise KubeError(f"cluster {name!r} has no kubeconfig: it is a model-only cluster")
    try:
        return kubeconfig.validate(text, context or "", server_policy())
    except KubeconfigError as exc:
        raise KubeError(f"cluster {name!r}: kubeconfig refused: {exc}") from exc


#: Client certificate files by content digest: urllib3 only loads them from files. Private directory (0700),
#: files 0600, removed at exit.
_CERT_DIR: list[Path] = []
_CERT_LOCK = threading.Lock()


def _private_file(data: bytes, suffix: str) -> str:
    with _CERT_LOCK:
        if not _CERT_DIR:
            _CERT_DIR.append(Path(tempfile.mkdtemp(prefix="continuum-kube-certs-")))
            atexit.register(shutil.rmtree, _CERT_DIR[0], True)
        path = _CERT_DIR[0] / f"{hashlib.sha256(data).hexdigest()}{suffix}"
        if not path.exists():
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
            with os.fdopen(fd, "wb") as out:
                out.write(data)
        return str(path)


def component_token(server: str) -> str | None:
    """The token of this component's own ServiceAccount, when it runs with one for ``server``:
    ``CONTINUUM_KUBE_TOKEN_FILE`` (a projected token, read at each connection since the kubelet rotates it) is
    used for the API ``CONTINUUM_KUBE_TOKEN_SERVER`` names (compared as written) instead of the credentials of
    the cluster's stored kubeconfig, so each component (deploy/rbac.yaml) has only its own verbs there. Set by
    the operator, never by a kubeconfig (those may not name files)."""
    path, own = os.environ.get("CONTINUUM_KUBE_TOKEN_FILE"), os.environ.get("CONTINUUM_KUBE_TOKEN_SERVER", "")
    if not path or not own or own.rstrip("/") != server.rstrip("/"):
        return None
    try:
        return Path(path).read_text().strip() or None
    except OSError as exc:
        raise KubeError(f"CONTINUUM_KUBE_TOKEN_FILE {path!r} cannot be read: {exc.strerror}") from exc


def configuration_for(target: KubeTarget) -> client.Configuration:
    """The client configuration of a validated target, set field by field: no kubeconfig loader, so no exec
    plugin, auth provider or file path can ever come into play. TLS is always verified."""
    configuration = client.Configuration()
    configuration.host = target.server
    configuration.verify_ssl = True
    configuration.ca_cert_data = target.ca_pem  # None: the system's CAs
    configuration.tls_server_name = target.tls_server_name
    own = component_token(target.server)
    if own:  # this process's own ServiceAccount for this API: least privilege, not the stored kubeconfig's user
        configuration.api_key = {"authorization": f"Bearer {own}"}
    elif target.token:
        configuration.api_key = {"authorization": f"Bearer {target.token}"}
    if not own and target.client_cert_pem and target.client_key_pem:
        configuration.cert_file = _private_file(target.client_cert_pem, ".crt")
        configuration.key_file = _private_file(target.client_key_pem, ".key")
    # Retry refused/reset connections briefly; never re-send a request the server may have acted on. HTTP
    # answers (429/503 with Retry-After included) are left to :func:`call`, which knows what is idempotent:
    # urllib3 would otherwise turn a 429 into an exhausted-retries error without waiting.
    # One connection per push worker (apps.kube.parallel): a smaller pool would open and discard extra ones.
    configuration.connection_pool_maxsize = max(
        configuration.connection_pool_maxsize or 1, settings.CONTINUUM_KUBE_PUSH_CONCURRENCY
    )
    configuration.retries = urllib3.Retry(
        total=2, connect=2, read=0, status=0, other=0, backoff_factor=0.2, respect_retry_after_header=False
    )
    return configuration


def api_client(text: str, context: str = "", *, name: str = "", pool: int | None = None) -> client.ApiClient:
    """An API client from a kubeconfig's text and context, validated first (no global state). The one builder
    every caller uses (schedule pushes, container pushes, RT-Kube, the node watcher, node sync). ``pool``: the
    connections kept per server when more threads share the client than a push has workers (a smaller pool
    opens and discards a TLS connection per extra request)."""
    configuration = configuration_for(target(text, context, name=name))
    if pool:
        configuration.connection_pool_maxsize = max(configuration.connection_pool_maxsize, pool)
    return client.ApiClient(configuration)


def describe(exc: BaseException, server: str = "") -> str:
    """One line saying why a call failed: the API's own message, or why the server could not be reached."""
    if isinstance(exc, retry.GaveUp):
        return str(exc)  # already names the call and describes its last cause
    if isinstance(exc, ApiException):
        message = exc.reason or ""
        with contextlib.suppress(ValueError, AttributeError):  # not a Status document: keep the reason
            message = json.loads(exc.body or "{}").get("message") or message
        return f"Kubernetes API answered {exc.status}: {message}"
    if isinstance(exc, urllib3.exceptions.MaxRetryError) and exc.reason is not None:
        exc = exc.reason
    reason = str(exc)
    # urllib3 prefixes the connection object's repr; the tail is the useful part.
    if "): " in reason:
        reason = reason.rsplit("): ", 1)[-1]
    where = f" at {server}" if server else ""
    return f"Kubernetes API unreachable{where}: {reason}"


def problem(exc: BaseException) -> str:
    """One line saying why a call failed (any of :data:`KUBE_ERRORS`)."""
    if isinstance(exc, ApiException | OSError | urllib3.exceptions.HTTPError):
        return describe(exc)
    return str(exc)


def status_of(exc: BaseException) -> int | None:
    """The HTTP status of an API error answer (``None``: not an answer)."""
    return exc.status if isinstance(exc, ApiException) else None
