"""A real kube-apiserver + etcd on loopback, for the Kubernetes gateway tests.

There is no kubelet, scheduler or controller-manager: nodes are plain objects the tests create, pods stay
Pending once bound. See ``/work/shared/notes/real-services.md`` (kube-apiserver section) for the facts the
flags below rest on. The binary comes from ``scripts/build-kube-apiserver.sh`` (built once, then cached).
"""

from __future__ import annotations

import atexit
import base64
import os
import secrets
import shutil
import signal
import socket
import ssl
import subprocess
import tempfile
import time
import urllib.error
import urllib.request
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
BUILD_SCRIPT = ROOT / "scripts" / "build-kube-apiserver.sh"
#: Seconds the build may take on a cold cache (the notes measured 3.5-6.6 min on 2 cores).
BUILD_TIMEOUT = 30 * 60
READY_TIMEOUT = 120


class KubeAPIError(RuntimeError):
    """The API server could not be built or started (the fixture turns this into a test failure)."""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def build_kube_apiserver() -> Path:
    """Path of the cached kube-apiserver binary, building it first when the cache is cold."""
    try:
        done = subprocess.run(
            ["bash", str(BUILD_SCRIPT)], capture_output=True, text=True, timeout=BUILD_TIMEOUT, check=False
        )
    except subprocess.TimeoutExpired as exc:
        raise KubeAPIError(f"{BUILD_SCRIPT.name} did not finish in {BUILD_TIMEOUT} s") from exc
    lines = done.stdout.strip().splitlines()
    if done.returncode != 0 or not lines or not os.access(lines[-1], os.X_OK):
        raise KubeAPIError(f"{BUILD_SCRIPT.name} failed (exit {done.returncode}):\n{done.stderr[-3000:]}")
    return Path(lines[-1])


def kubeconfig_text(server: str, token: str, ca_pem: bytes, context: str = "continuum-test") -> str:
    """A self-contained kubeconfig (CA and token inline), as a cluster row stores it."""
    doc = {
        "apiVersion": "v1",
        "kind": "Config",
        "clusters": [
            {
                "name": context,
                "cluster": {"server": server, "certificate-authority-data": base64.b64encode(ca_pem).decode()},
            }
        ],
        "users": [{"name": f"{context}-admin", "user": {"token": token}}],
        "contexts": [{"name": context, "context": {"cluster": context, "user": f"{context}-admin"}}],
        "current-context": context,
    }
    return yaml.safe_dump(doc, sort_keys=False)


class KubeAPIServer:
    """etcd + kube-apiserver in a temporary directory, on free loopback ports."""

    def __init__(self, binary: Path, etcd: str | None = None, extra_args: list[str] | None = None) -> None:
        self.binary = binary
        self.extra_args = list(extra_args or [])
        self.etcd = etcd or shutil.which("etcd") or "/usr/bin/etcd"
        self.token = secrets.token_hex(24)
        self.dir = Path(tempfile.mkdtemp(prefix="continuum-kube-"))
        self.procs: list[subprocess.Popen] = []
        self.port = 0
        self.startup_seconds = 0.0

    @property
    def server(self) -> str:
        return f"https://127.0.0.1:{self.port}"

    @property
    def ca_path(self) -> Path:
        return self.dir / "certs" / "apiserver.crt"

    def kubeconfig(self, context: str = "continuum-test") -> str:
        return kubeconfig_text(self.server, self.token, self.ca_path.read_bytes(), context)

    # -- start-up ---------------------------------------------------------------------------------------

    def start(self, attempts: int = 3) -> KubeAPIServer:
        began = time.monotonic()
        # A safety net if the session ends without its fixture tear-down (stop() is idempotent).
        atexit.register(self.stop)
        self._write_credentials()
        last: Exception | None = None
        # Free ports are picked before the servers bind them; a port taken in between fails the start,
        # so try again with fresh ports (and a fresh etcd data dir).
        for _ in range(attempts):
            try:
                self._start_once()
                self.startup_seconds = time.monotonic() - began
                return self
            except KubeAPIError as exc:
                last = exc
                self._stop_processes()
        self.stop()
        raise KubeAPIError(f"kube-apiserver did not start after {attempts} attempts: {last}")

    def _write_credentials(self) -> None:
        (self.dir / "tokens.csv").write_text(f"{self.token},continuum-admin,continuum-admin,system:masters\n")
        key = self.dir / "sa.key"
        done = subprocess.run(["openssl", "genrsa", "-out", str(key), "2048"], capture_output=True, check=False)
        if done.returncode != 0:
            raise KubeAPIError(f"openssl genrsa failed: {done.stderr.decode()[-500:]}")

    def _start_once(self) -> None:
        client, peer, self.port = free_port(), free_port(), free_port()
        data = Path(tempfile.mkdtemp(prefix="etcd-", dir=self.dir))
        shutil.rmtree(self.dir / "certs", ignore_errors=True)
        etcd = self._spawn(
            "etcd",
            [
                self.etcd,
                f"--data-dir={data}",
                "--name=default",
                f"--listen-client-urls=http://127.0.0.1:{client}",
                f"--advertise-client-urls=http://127.0.0.1:{client}",
                f"--listen-peer-urls=http://127.0.0.1:{peer}",
                f"--initial-advertise-peer-urls=http://127.0.0.1:{peer}",
                f"--initial-cluster=default=http://127.0.0.1:{peer}",
            ],
        )
        self._wait_for_port(client, etcd, "etcd", 30)
        api = self._spawn(
            "kube-apiserver",
            [
                str(self.binary),
                f"--etcd-servers=http://127.0.0.1:{client}",
                "--bind-address=127.0.0.1",
                "--advertise-address=127.0.0.1",
                f"--secure-port={self.port}",
                f"--cert-dir={self.dir / 'certs'}",
                f"--token-auth-file={self.dir / 'tokens.csv'}",
                # RBAC as a real cluster has it (issue 28): the tests' admin token is in system:masters, and each
                # component's ServiceAccount gets only deploy/rbac.yaml's verbs.
                "--authorization-mode=Node,RBAC",
                "--service-account-issuer=https://kubernetes.default.svc",
                f"--service-account-key-file={self.dir / 'sa.key'}",
                f"--service-account-signing-key-file={self.dir / 'sa.key'}",
                "--disable-admission-plugins=ServiceAccount",
                "--endpoint-reconciler-type=none",
                "--enable-priority-and-fairness=false",
                "--service-cluster-ip-range=10.96.0.0/16",
                *self.extra_args,
            ],
        )
        self._wait_ready(api)

    def _spawn(self, name: str, argv: list[str]) -> subprocess.Popen:
        log = open(self.dir / f"{name}.log", "ab")  # noqa: SIM115 - closed with the process in stop()
        try:
            proc = subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        except OSError as exc:
            log.close()
            raise KubeAPIError(f"cannot run {argv[0]}: {exc}") from exc
        proc.log = log  # type: ignore[attr-defined]
        proc.name = name  # type: ignore[attr-defined]
        self.procs.append(proc)
        return proc

    def _log_tail(self, name: str, chars: int = 3000) -> str:
        path = self.dir / f"{name}.log"
        return path.read_text(errors="replace")[-chars:] if path.exists() else ""

    def _wait_for_port(self, port: int, proc: subprocess.Popen, name: str, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if proc.poll() is not None:
                raise KubeAPIError(f"{name} exited with {proc.returncode}:\n{self._log_tail(name)}")
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", port)) == 0:
                    return
            time.sleep(0.1)
        raise KubeAPIError(f"{name} did not listen on {port} within {timeout} s:\n{self._log_tail(name)}")

    def _wait_ready(self, proc: subprocess.Popen) -> None:
        deadline = time.monotonic() + READY_TIMEOUT
        last = "no answer"
        while time.monotonic() < deadline:
            if proc.poll() is not None:
                raise KubeAPIError(f"kube-apiserver exited with {proc.returncode}:\n{self._log_tail('kube-apiserver')}")
            if self.ca_path.exists():
                request = urllib.request.Request(
                    f"{self.server}/readyz", headers={"Authorization": f"Bearer {self.token}"}
                )
                try:
                    context = ssl.create_default_context(cafile=str(self.ca_path))
                    with urllib.request.urlopen(request, context=context, timeout=5) as response:
                        if response.status == 200:
                            return
                except (urllib.error.URLError, OSError, ssl.SSLError) as exc:
                    last = str(exc)
            time.sleep(0.2)
        raise KubeAPIError(
            f"kube-apiserver not ready within {READY_TIMEOUT} s ({last}):\n{self._log_tail('kube-apiserver')}"
        )

    # -- tear-down --------------------------------------------------------------------------------------

    def _stop_processes(self) -> None:
        # The API server first, so it does not log etcd errors while shutting down.
        for proc in reversed(self.procs):
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)
                try:
                    proc.wait(15)
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, signal.SIGKILL)
                    proc.wait(5)
            proc.log.close()  # type: ignore[attr-defined]
        self.procs.clear()

    def stop(self) -> None:
        self._stop_processes()
        shutil.rmtree(self.dir, ignore_errors=True)
