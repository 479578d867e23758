"""The kubeconfig validator (apps/kube/kubeconfig.py), called directly: pure functions, no database, no API."""

import base64
import copy

import pytest
import yaml

from apps.kube.kubeconfig import KubeconfigError, ServerPolicy, host_allowed, parse, validate

CA = b"-----BEGIN CERTIFICATE-----\nMIIBfake\n-----END CERTIFICATE-----\n"
KEY = b"-----BEGIN EC PRIVATE KEY-----\nMHcfake\n-----END EC PRIVATE KEY-----\n"
B64 = lambda data: base64.b64encode(data).decode()  # noqa: E731
STRICT = ServerPolicy()


def doc(server="https://k8s.example.org:6443", user=None, cluster_extra=None) -> dict:
    return {
        "apiVersion": "v1",
        "kind": "Config",
        "clusters": [
            {"name": "c", "cluster": {"server": server, "certificate-authority-data": B64(CA), **(cluster_extra or {})}}
        ],
        "users": [{"name": "u", "user": user if user is not None else {"token": "abc.def-123"}}],
        "contexts": [{"name": "ctx", "context": {"cluster": "c", "user": "u", "namespace": "robots"}}],
        "current-context": "ctx",
    }


def text(d: dict) -> str:
    return yaml.safe_dump(d)


def refused(d: dict | str, policy: ServerPolicy = STRICT, context: str = "") -> KubeconfigError:
    with pytest.raises(KubeconfigError) as info:
        validate(d if isinstance(d, str) else text(d), context, policy)
    return info.value


def test_inline_token_and_ca_give_the_target():
    target = validate(text(doc()), "", STRICT)
    assert target.server == "https://k8s.example.org:6443" and target.context == "ctx"
    assert target.token == "abc.def-123" and target.ca_pem == CA.decode() and target.namespace == "robots"
    assert target.client_cert_pem is None
    assert "abc.def" not in repr(target)  # credentials never printed


def test_inline_client_certificate():
    target = validate(text(doc(user={"client-certificate-data": B64(CA), "client-key-data": B64(KEY)})), "", STRICT)
    assert target.client_cert_pem == CA and target.client_key_pem == KEY and target.token is None


@pytest.mark.parametrize(
    ("user", "path", "why"),
    [
        ({"exec": {"apiVersion": "client.authentication.k8s.io/v1", "command": "/bin/sh", "args": ["-c", "id"]}},
         "users[0].user.exec", "run a command"),
        ({"auth-provider": {"name": "gcp", "config": {"cmd-path": "/bin/sh"}}}, "users[0].user.auth-provider",
         "plugins"),
        ({"tokenFile": "/etc/passwd"}, "users[0].user.tokenFile", "file"),
        ({"client-certificate": "/a.crt", "client-key": "/a.key"}, "users[0].user.client-certificate", "file"),
        ({"token": "t", "client-key": "/a.key"}, "users[0].user.client-key", "file"),
        ({"username": "admin"}, "users[0].user.username", "basic authentication"),
        ({"token": "t", "as": "system:admin"}, "users[0].user.as", "impersonation"),
        ({"token": "t", "surprise": 1}, "users[0].user.surprise", "unknown field"),
        ({"token": "a b"}, "users[0].user.token", "visible ASCII"),
        ({"token": "abc\r\nX-Evil: 1"}, "users[0].user.token", "visible ASCII"),
        ({"client-certificate-data": B64(CA)}, "users[0].user.client-key-data", "other half"),
        ({"client-certificate-data": B64(CA), "client-key-data": "!!notbase64"}, "users[0].user.client-key-data",
         "base64"),
    ],
)  # fmt: skip
def test_refused_user_fields_are_named(user, path, why):
    exc = refused(doc(user=user))
    assert exc.path == path and str(exc).startswith(f"{path}: ") and why in str(exc)


@pytest.mark.parametrize(
    ("extra", "path", "why"),
    [
        ({"certificate-authority": "/etc/ssl/ca.pem"}, "clusters[0].cluster.certificate-authority", "file"),
        ({"proxy-url": "http://10.0.0.1:3128"}, "clusters[0].cluster.proxy-url", "not allowed"),
        ({"insecure-skip-tls-verify": True}, "clusters[0].cluster.insecure-skip-tls-verify", "TLS verification"),
        ({"certificate-authority-data": B64(b"not a pem")}, "clusters[0].cluster.certificate-authority-data", "PEM"),
    ],
)
def test_refused_cluster_fields_are_named(extra, path, why):
    exc = refused(doc(cluster_extra=extra))
    assert exc.path == path and why in str(exc)


def test_a_refused_field_in_an_unused_user_is_refused_too():
    d = doc()
    d["users"].append({"name": "spare", "user": {"exec": {"command": "/bin/sh"}}})
    assert refused(d).path == "users[1].user.exec"


@pytest.mark.parametrize(
    ("server", "why"),
    [
        ("http://k8s.example.org", "must use https"),
        ("http://127.0.0.2:8080", "must use https"),
        ("ftp://k8s.example.org", "https://"),
        ("ftp://u:hunter2@k8s.example.org", "https://"),
        ("https://admin:pw@k8s.example.org", "credentials in the URL"),
        ("https://k8s.example.org/?x=1", "query"),
        ("https://k8s.example.org:99999", "not a URL"),
        ("https:///nohost", "https://"),
        ("", "required"),
    ],
)
def test_server_must_be_https(server, why):
    exc = refused(doc(server=server))
    assert exc.path == "clusters[0].cluster.server" and why in str(exc)
    assert "hunter2" not in str(exc)  # a password in the URL is never echoed


def test_http_only_on_loopback_and_only_when_allowed():
    loopback = ServerPolicy(allow_http_loopback=True)
    for server in ("http://127.0.0.1:8080", "http://127.0.0.2", "http://localhost:6443", "http://[::1]:80"):
        assert validate(text(doc(server=server)), "", loopback).server == server.rstrip("/")
        assert "must use https" in str(refused(doc(server=server)))
    for server in ("http://10.0.0.1", "http://k8s.example.org", "http://169.254.169.254"):
        assert "only allowed on a loopback" in str(refused(doc(server=server), loopback))


def test_allow_list_of_hosts_and_networks():
    policy = ServerPolicy(allowed_hosts=("k8s.example.org", "*.edge.example.org", "10.20.0.0/16", "192.0.2.7"))
    for server in (
        "https://k8s.example.org",
        "https://a.edge.example.org:6443",
        "https://10.20.3.4",
        "https://192.0.2.7",
    ):
        assert validate(text(doc(server=server)), "", policy).server == server
    for server in ("https://evil.example.org", "https://edge.example.org", "https://10.21.0.1", "https://127.0.0.1",
                   "https://k8s.example.org.evil.net"):  # fmt: skip
        exc = refused(doc(server=server), policy)
        assert exc.path == "clusters[0].cluster.server" and "not in the allowed" in str(exc)
    # A host name is never resolved: a network entry admits IP literals only.
    assert not host_allowed("localhost", ("127.0.0.0/8",))
    assert host_allowed("::1", ("::1/128",))


def test_size_is_bounded():
    d = doc()
    d["preferences"] = {"padding": "x" * 70_000}
    exc = refused(d)
    assert exc.path == "kubeconfig" and "too large" in str(exc)
    assert parse(text(doc()), ServerPolicy(max_bytes=100_000))


def test_too_many_entries():
    d = doc()
    d["users"] = [{"name": f"u{i}", "user": {"token": "t"}} for i in range(101)]
    assert refused(d).path == "users"


@pytest.mark.parametrize(
    ("raw", "path"),
    [
        ("a: [unclosed", "kubeconfig"),
        ("just a string", "kubeconfig"),
        ("fernet:gAAAAAB", "kubeconfig"),
        ("apiVersion: v2\nkind: Config\n", "apiVersion"),
        ("kind: Secret\n", "kind"),
        ("clusters: {}\n", "clusters"),
        ("bogus: 1\n", "bogus"),
    ],
)
def test_malformed_documents(raw, path):
    assert refused(raw).path == path


def test_contexts_must_point_at_known_entries_and_the_selected_context_must_exist():
    d = doc()
    d["contexts"][0]["context"]["user"] = "nobody"
    assert refused(d).path == "contexts[0].context.user"
    d = doc()
    assert refused(d, context="other").path == "kube_context"
    d["current-context"] = "gone"
    assert refused(d).path == "current-context"
    # No current context: the only context is used; with two it must be named.
    d = doc()
    del d["current-context"]
    assert validate(text(d), "", STRICT).context == "ctx"
    d["contexts"].append(copy.deepcopy(d["contexts"][0]) | {"name": "ctx2"})
    assert refused(d).path == "current-context"
    assert validate(text(d), "ctx2", STRICT).context == "ctx2"


def test_the_client_configuration_is_built_from_the_validated_fields_only():
    import os
    import stat
    from pathlib import Path

    from apps.kube.gateway import configuration_for

    target = validate(text(doc(user={"client-certificate-data": B64(CA), "client-key-data": B64(KEY)})), "", STRICT)
    conf = configuration_for(target)
    assert conf.host == "https://k8s.example.org:6443" and conf.verify_ssl is True
    assert conf.ca_cert_data == CA.decode() and conf.ssl_ca_cert is None
    assert "authorization" not in conf.api_key
    # urllib3 loads client certificates from files only: private ones (0600 in a 0700 directory).
    for path, data in ((conf.cert_file, CA), (conf.key_file, KEY)):
        assert stat.S_IMODE(os.stat(path).st_mode) == 0o600 and Path(path).read_bytes() == data
        assert stat.S_IMODE(os.stat(os.path.dirname(path)).st_mode) == 0o700
    token = configuration_for(validate(text(doc()), "", STRICT))
    assert token.api_key == {"authorization": "Bearer abc.def-123"} and token.cert_file is None


@pytest.mark.parametrize("opener", ["[", "{", "- "])
def test_deeply_nested_yaml_is_refused_before_the_c_loader_sees_it(opener):
    """60 KB of "[" overflowed the C stack inside libyaml's composer and killed the process (issue 25): run in
    a child process, so that a crash is this test's failure and not the test run's."""
    import subprocess
    import sys
    from pathlib import Path

    script = (
        "from apps.kube.kubeconfig import KubeconfigError, ServerPolicy, validate\n"
        f"text = {opener!r} * {60_000 // len(opener)}\n"
        "try:\n"
        "    validate(text, '', ServerPolicy())\n"
        "except KubeconfigError as exc:\n"
        "    print('refused:', exc)\n"
    )
    root = Path(__file__).resolve().parents[2]
    done = subprocess.run([sys.executable, "-c", script], cwd=root, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, (done.returncode, done.stderr[-2000:])
    assert "refused:" in done.stdout and "nested too deeply" in done.stdout, done.stdout


def test_a_kubeconfig_nested_within_the_bound_still_parses():
    deep = {"k": 1}
    for _ in range(10):
        deep = {"k": deep}
    d = doc()
    d["preferences"] = {"extensions": [{"name": "x", "extension": deep}]}
    assert validate(text(d), "", STRICT).server == "https://k8s.example.org:6443"
