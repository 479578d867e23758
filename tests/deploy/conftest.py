"""A kube-apiserver under ``--authorization-mode=Node,RBAC`` with deploy/'s namespaces, CRDs and RBAC applied,
and an audit log of every Binding and Lease write (who bound which pod, and how often).

A bare API server (no kubelet, scheduler or controller-manager): enough for what these tests need, the
authorizer, the Lease and the Binding API (a bound pod stays Pending). Fails, never skips, when it cannot start.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
import yaml

from tests.kubeapi import KubeAPIError, KubeAPIServer, build_kube_apiserver

ROOT = Path(__file__).resolve().parents[2]
DEPLOY = ROOT / "deploy"
AUDIT_POLICY = {
    "apiVersion": "audit.k8s.io/v1",
    "kind": "Policy",
    "omitStages": ["RequestReceived"],
    "rules": [
        {"level": "Metadata", "verbs": ["create"], "resources": [{"group": "", "resources": ["pods/binding"]}]},
        {"level": "None"},
    ],
}


class RBACServer:
    def __init__(self, api: KubeAPIServer, audit: Path) -> None:
        self.api, self.audit = api, audit
        self.kubeconfig_path = api.dir / "admin.kubeconfig"
        self.kubeconfig_path.write_text(api.kubeconfig())

    @property
    def server(self) -> str:
        return self.api.server

    def kubectl(self, *args: str, token: str | None = None, input: str | None = None, check: bool = True):
        argv = ["kubectl", f"--kubeconfig={self.kubeconfig_path}", *args]
        if token is not None:
            argv.insert(2, f"--token={token}")
        done = subprocess.run(argv, capture_output=True, text=True, input=input, timeout=120, check=False)
        if check and done.returncode != 0:
            raise AssertionError(f"kubectl {' '.join(args)} failed ({done.returncode}): {done.stderr[-2000:]}")
        return done

    def token(self, account: str, namespace: str = "continuum-system", seconds: int = 3600) -> str:
        """A TokenRequest token of a ServiceAccount (what a pod of that account gets projected)."""
        done = self.kubectl("create", "token", account, "-n", namespace, f"--duration={seconds}s")
        return done.stdout.strip()

    def token_file(self, account: str) -> Path:
        path = self.api.dir / f"{account}.token"
        path.write_text(self.token(account))
        path.chmod(0o600)
        return path

    def kubeconfig_as(self, token: str) -> str:
        doc = yaml.safe_load(self.api.kubeconfig())
        doc["users"][0]["user"] = {"token": token}
        return yaml.safe_dump(doc)

    def bindings(self) -> list[dict]:
        """Every Binding the server answered (audit events at ResponseComplete): pod, code, user."""
        out = []
        for line in self.audit.read_text().splitlines() if self.audit.exists() else []:
            event = json.loads(line)
            if event.get("stage") != "ResponseComplete":
                continue
            ref = event.get("objectRef") or {}
            if ref.get("subresource") == "binding":
                out.append({"pod": f"{ref.get('namespace')}/{ref.get('name')}",
                            "code": (event.get("responseStatus") or {}).get("code"),
                            "user": (event.get("user") or {}).get("username")})  # fmt: skip
        return out


@pytest.fixture(scope="session")
def rbac_api(tmp_path_factory):
    policy = tmp_path_factory.mktemp("audit") / "policy.yaml"
    policy.write_text(yaml.safe_dump(AUDIT_POLICY))
    audit = policy.parent / "audit.log"
    try:
        binary = build_kube_apiserver()
        api = KubeAPIServer(binary, extra_args=[f"--audit-policy-file={policy}", f"--audit-log-path={audit}",
                                                 "--audit-log-format=json"]).start()  # fmt: skip
    except KubeAPIError as exc:
        pytest.fail(f"the test API server did not start: {exc}")
    server = RBACServer(api, audit)
    try:
        for name in ("namespaces.yaml", "crds.yaml", "rbac.yaml"):
            server.kubectl("apply", "-f", str(DEPLOY / name))
        yield server
    finally:
        api.stop()
