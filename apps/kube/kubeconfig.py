"""Validation of a cluster's kubeconfig: inline credentials only, a vetted server address, a bounded size.

A kubeconfig is hostile input. The official client would run ``users[].user.exec`` commands as the server's
user, run ``auth-provider`` plugins, read any server file named by ``tokenFile``, ``client-key``,
``client-certificate`` or ``certificate-authority``, send requests through ``proxy-url`` and call any
address. This module accepts the subset Continuum needs and refuses anything else with a message naming the
field (``users[0].user.exec: not allowed: ...``).

Accepted (everything else, known or unknown, is refused):

- top level: ``apiVersion`` (v1), ``kind`` (Config), ``clusters``, ``users``, ``contexts``,
  ``current-context``, ``preferences`` and ``extensions`` (both ignored);
- ``clusters[].cluster``: ``server`` (https; http only on a loopback address when the policy allows it;
  within the allow-list when there is one), ``certificate-authority-data`` (inline PEM),
  ``tls-server-name``, ``insecure-skip-tls-verify: false``, ``disable-compression``, ``extensions``;
- ``users[].user``: ``token``, ``client-certificate-data`` with ``client-key-data`` (inline PEM),
  ``extensions``. ``username``/``password`` are refused: basic authentication left Kubernetes in 1.19;
- ``contexts[].context``: ``cluster``, ``user``, ``namespace``, ``extensions``.

Pure functions: no Django, no I/O, no DNS. The policy (http on loopback, allowed hosts, size) is an argument;
:func:`apps.kube.gateway.server_policy` reads it from the settings. Every entry is checked, not only the one
the selected context uses, so a refused field cannot hide in an unused user.
"""

from __future__ import annotations

import base64
import binascii
import ipaddress
import re
from dataclasses import dataclass
from typing import Any
from urllib.parse import urlsplit

import yaml

from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import check_yaml_events

#: PyYAML's safe loader, in C when libyaml is there (about 10x faster than the pure-Python one).
SAFE_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
#: Nesting of a kubeconfig's mappings and lists: a real one nests 5 levels (users[].user.exec.env[].name).
KUBECONFIG_MAX_DEPTH = 32
#: Most entries a list (clusters, users, contexts) may have; real kubeconfigs have a handful.
MAX_ENTRIES = 100
MAX_TOKEN_CHARS = 16_384
MAX_NAME_CHARS = 253
#: A bearer token goes into an HTTP header: visible ASCII only (no spaces, no CR/LF header injection).
TOKEN_RE = re.compile(r"^[\x21-\x7e]+$")

TOP_FIELDS = {"apiVersion", "kind", "clusters", "users", "contexts", "current-context", "preferences", "extensions"}
CLUSTER_FIELDS = {
    "server",
    "certificate-authority-data",
    "tls-server-name",
    "insecure-skip-tls-verify",
    "disable-compression",
    "extensions",
}
USER_FIELDS = {"token", "client-certificate-data", "client-key-data", "extensions"}
CONTEXT_FIELDS = {"cluster", "user", "namespace", "extensions"}

#: Known fields refused on purpose, with the reason given to the operator.
REFUSED = {
    "exec": "it would run a command on the Continuum server; give an inline token or client certificate",
    "auth-provider": "auth-provider plugins run code and read files on the server; give an inline token",
    "tokenFile": "it names a file on the Continuum server; give the token inline (token)",
    "client-certificate": "it names a file on the Continuum server; use client-certificate-data",
    "client-key": "it names a file on the Continuum server; use client-key-data",
    "certificate-authority": "it names a file on the Continuum server; use certificate-authority-data",
    "proxy-url": "requests may only go straight to the API server",
    "username": "basic authentication was removed from Kubernetes (1.19); give a token or client certificate",
    "password": "basic authentication was removed from Kubernetes (1.19); give a token or client certificate",
    "as": "impersonation is not supported",
    "as-uid": "impersonation is not supported",
    "as-groups": "impersonation is not supported",
    "as-user-extra": "impersonation is not supported",
}


class KubeconfigError(ValueError):
    """A refused kubeconfig; ``path`` names the field (``users[0].user.exec``), the message starts with it."""

    def __init__(self, path: str, problem: str) -> None:
        super().__init__(f"{path}: {problem}")
        self.path = path
        self.problem = problem


@dataclass(frozen=True)
class ServerPolicy:
    """Where a kubeconfig may point. ``allowed_hosts``: host names (``api.example.org``, ``*.example.org``)
    and IP networks (``10.0.0.0/8``, ``192.0.2.7``); empty allows any host. A host name is compared as
    written (never resolved), so a CIDR entry only admits servers given by IP address."""

    allow_http_loopback: bool = False
    allowed_hosts: tuple[str, ...] = ()
    max_bytes: int = 65_536


@dataclass(frozen=True)
class KubeTarget:
    """What the selected context of a validated kubeconfig says: all a client needs, nothing it could run."""

    context: str
    server: str
    ca_pem: str | None = None
    tls_server_name: str | None = None
    token: str | None = None
    client_cert_pem: bytes | None = None
    client_key_pem: bytes | None = None
    namespace: str | None = None

    def __repr__(self) -> str:  # never print the credentials (logs, tracebacks)
        return f"KubeTarget(context={self.context!r}, server={self.server!r})"


# ---- entry points -----------------------------------------------------------------------------------------
def parse(text: str, policy: ServerPolicy) -> dict[str, Any]:
    """The kubeconfig as a mapping once every entry passed the checks; :class:`KubeconfigError` otherwise."""
    if not isinstance(text, str):
        raise KubeconfigError("kubeconfig", "must be YAML text")
    size = len(text.encode())
    if size > policy.max_bytes:
        raise KubeconfigError("kubeconfig", f"too large: {size} bytes, at most {policy.max_bytes}")
    try:
        # Depth and aliases first, without recursion: the C loader's composer recurses per level and 60 KB
        # of "[" overflowed the C stack, killing the web worker with every request in it (issue 25).
        check_yaml_events(text, "kubeconfig", max_depth=KUBECONFIG_MAX_DEPTH)
        doc = yaml.load(text, Loader=SAFE_LOADER)  # safe: no Python objects
    except InputError as exc:
        raise KubeconfigError("kubeconfig", str(exc)) from exc
    except yaml.YAMLError as exc:
        raise KubeconfigError("kubeconfig", f"not valid YAML ({exc})") from exc
    if not isinstance(doc, dict):
        raise KubeconfigError("kubeconfig", "must be a YAML mapping (apiVersion: v1, kind: Config, ...)")
    _known(doc, TOP_FIELDS, "")
    if doc.get("apiVersion", "v1") != "v1":
        raise KubeconfigError("apiVersion", f"must be v1, not {doc['apiVersion']!r}")
    if doc.get("kind", "Config") != "Config":
        raise KubeconfigError("kind", f"must be Config, not {doc['kind']!r}")
    for key in ("preferences",):
        if key in doc and not isinstance(doc[key], dict | None):
            raise KubeconfigError(key, "must be a mapping")
    clusters = _entries(doc, "clusters", "cluster")
    users = _entries(doc, "users", "user")
    contexts = _entries(doc, "contexts", "context")
    for i, (_, body) in enumerate(clusters):
        _check_cluster(body, f"clusters[{i}].cluster", policy)
    for i, (_, body) in enumerate(users):
        _check_user(body, f"users[{i}].user")
    cluster_names, user_names = {n for n, _ in clusters}, {n for n, _ in users}
    for i, (_, body) in enumerate(contexts):
        where = f"contexts[{i}].context"
        _known(body, CONTEXT_FIELDS, where)
        cluster = body.get("cluster")
        if not isinstance(cluster, str) or cluster not in cluster_names:
            raise KubeconfigError(f"{where}.cluster", f"no cluster named {cluster!r} in clusters")
        user = body.get("user")
        if user not in (None, "") and (not isinstance(user, str) or user not in user_names):
            raise KubeconfigError(f"{where}.user", f"no user named {user!r} in users")
        if body.get("namespace") is not None and not isinstance(body["namespace"], str):
            raise KubeconfigError(f"{where}.namespace", "must be a string")
    current = doc.get("current-context")
    if current not in (None, "") and not isinstance(current, str):
        raise KubeconfigError("current-context", "must be a string")
    return doc


def select(doc: dict[str, Any], context: str = "") -> KubeTarget:
    """The target of ``context`` (else ``current-context``, else the only context) of a :func:`parse`-d doc."""
    contexts = {e["name"]: e.get("context") or {} for e in doc.get("contexts") or []}
    name = context or doc.get("current-context") or ""
    if not name:
        if len(contexts) != 1:
            raise KubeconfigError("current-context", "not set: name the context to use (kube_context)")
        name = next(iter(contexts))
    if name not in contexts:
        where = "kube_context" if context else "current-context"
        raise KubeconfigError(where, f"no context named {name!r} in contexts")
    ctx = contexts[name]
    cluster = next(e["cluster"] for e in doc["clusters"] if e["name"] == ctx["cluster"])
    user = next((e.get("user") or {} for e in doc.get("users") or [] if e["name"] == ctx.get("user")), {})
    ca = cluster.get("certificate-authority-data")
    return KubeTarget(
        context=name,
        server=cluster["server"].rstrip("/"),
        ca_pem=_b64(ca, "").decode() if ca else None,
        tls_server_name=cluster.get("tls-server-name") or None,
        token=user.get("token") or None,
        client_cert_pem=_b64(user["client-certificate-data"], "") if user.get("client-certificate-data") else None,
        client_key_pem=_b64(user["client-key-data"], "") if user.get("client-key-data") else None,
        namespace=ctx.get("namespace") or None,
    )


def validate(text: str, context: str, policy: ServerPolicy) -> KubeTarget:
    """Check ``text`` and return the target of ``context``: what every save and every load goes through."""
    return select(parse(text, policy), context)


# ---- the parts --------------------------------------------------------------------------------------------
def _known(body: dict, allowed: set[str], where: str) -> None:
    for key in body:
        path = f"{where}.{key}" if where else str(key)
        if key in REFUSED:
            raise KubeconfigError(path, f"not allowed: {REFUSED[key]}")
        if key not in allowed:
            raise KubeconfigError(path, f"unknown field, not allowed (allowed: {', '.join(sorted(allowed))})")


def _entries(doc: dict, plural: str, singular: str) -> list[tuple[str, dict]]:
    raw = doc.get(plural)
    if raw is None:
        return []
    if not isinstance(raw, list):
        raise KubeconfigError(plural, "must be a list")
    if len(raw) > MAX_ENTRIES:
        raise KubeconfigError(plural, f"at most {MAX_ENTRIES} entries, got {len(raw)}")
    out, seen = [], set()
    for i, entry in enumerate(raw):
        where = f"{plural}[{i}]"
        if not isinstance(entry, dict):
            raise KubeconfigError(where, "must be a mapping with name and " + singular)
        _known(entry, {"name", singular}, where)
        name = entry.get("name")
        if not isinstance(name, str) or not name or len(name) > MAX_NAME_CHARS:
            raise KubeconfigError(f"{where}.name", f"a non-empty string of at most {MAX_NAME_CHARS} characters")
        if name in seen:
            raise KubeconfigError(f"{where}.name", f"{name!r} is given twice")
        seen.add(name)
        body = entry.get(singular)
        if body is None:
            body = {}
        if not isinstance(body, dict):
            raise KubeconfigError(f"{where}.{singular}", "must be a mapping")
        out.append((name, body))
    return out


def _check_cluster(body: dict, where: str, policy: ServerPolicy) -> None:
    _known(body, CLUSTER_FIELDS, where)
    if body.get("insecure-skip-tls-verify") not in (None, False):
        raise KubeconfigError(
            f"{where}.insecure-skip-tls-verify",
            "not allowed: TLS verification cannot be turned off; give certificate-authority-data",
        )
    if not isinstance(body.get("disable-compression", False), bool):
        raise KubeconfigError(f"{where}.disable-compression", "must be true or false")
    check_server(body.get("server"), f"{where}.server", policy)
    if body.get("certificate-authority-data") is not None:
        _pem(body["certificate-authority-data"], f"{where}.certificate-authority-data", "CERTIFICATE")
    name = body.get("tls-server-name")
    if name is not None and (not isinstance(name, str) or not re.fullmatch(r"[A-Za-z0-9.-]{1,253}", name)):
        raise KubeconfigError(f"{where}.tls-server-name", "must be a host name")


def _check_user(body: dict, where: str) -> None:
    _known(body, USER_FIELDS, where)
    token = body.get("token")
    if token is not None:
        if not isinstance(token, str) or not token:
            raise KubeconfigError(f"{where}.token", "must be a non-empty string")
        if len(token) > MAX_TOKEN_CHARS or not TOKEN_RE.match(token):
            raise KubeconfigError(f"{where}.token", f"must be at most {MAX_TOKEN_CHARS} visible ASCII characters")
    cert, key = body.get("client-certificate-data"), body.get("client-key-data")
    if (cert is None) != (key is None):
        missing = "client-key-data" if key is None else "client-certificate-data"
        raise KubeconfigError(f"{where}.{missing}", "required with the other half of the client certificate")
    if cert is not None:
        _pem(cert, f"{where}.client-certificate-data", "CERTIFICATE")
        _pem(key, f"{where}.client-key-data", "PRIVATE KEY")


def check_server(server: Any, where: str, policy: ServerPolicy) -> str:
    """The API server's URL: https (http only on loopback when allowed), no credentials, within the allow-list."""
    if not isinstance(server, str) or not server:
        raise KubeconfigError(where, "required: the https:// address of the Kubernetes API server")
    if len(server) > 2048 or any(c.isspace() or ord(c) < 0x20 for c in server):
        raise KubeconfigError(where, "not a URL")
    try:
        url = urlsplit(server)
        url.port  # noqa: B018 - raises ValueError on a bad port
    except ValueError as exc:
        raise KubeconfigError(where, f"not a URL ({exc})") from exc
    host = (url.hostname or "").lower()
    if url.scheme.lower() not in ("https", "http") or not host:
        raise KubeconfigError(where, f"must be an https:// URL, not {url.scheme or 'no'} scheme")
    if url.username is not None or url.password is not None:
        raise KubeconfigError(where, "must not carry credentials in the URL")
    if url.query or url.fragment:
        raise KubeconfigError(where, "must not have a query or fragment")
    if url.scheme.lower() == "http":
        if not policy.allow_http_loopback:
            raise KubeconfigError(where, "must use https (plain http would expose the credentials)")
        if not _loopback(host):
            raise KubeconfigError(where, "plain http is only allowed on a loopback address")
    if policy.allowed_hosts and not host_allowed(host, policy.allowed_hosts):
        raise KubeconfigError(where, f"host {host!r} is not in the allowed Kubernetes API hosts")
    return server


def _loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def host_allowed(host: str, allowed: tuple[str, ...] | list[str]) -> bool:
    """Whether ``host`` (a lower-case name or IP literal) matches an entry of the allow-list."""
    try:
        address = ipaddress.ip_address(host)
    except ValueError:
        address = None
    for entry in allowed:
        entry = entry.strip().lower()
        if not entry:
            continue
        if address is not None:
            try:
                if address in ipaddress.ip_network(entry, strict=False):
                    return True
            except ValueError:
                pass
            continue
        if entry.startswith("*."):
            if host.endswith(entry[1:]) and host != entry[2:]:
                return True
        elif host == entry:
            return True
    return False


def _b64(value: Any, where: str) -> bytes:
    if not isinstance(value, str):
        raise KubeconfigError(where, "must be base64 text")
    try:
        return base64.b64decode("".join(value.split()), validate=True)
    except (binascii.Error, ValueError) as exc:
        raise KubeconfigError(where, "not valid base64") from exc


def _pem(value: Any, where: str, label: str) -> None:
    data = _b64(value, where)
    if b"-----BEGIN " not in data or f"{label}-----".encode() not in data:
        raise KubeconfigError(where, f"must be a base64-encoded PEM {label.lower()}")
