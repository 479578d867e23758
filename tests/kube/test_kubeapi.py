"""The test API servers themselves: tests/kubeapi.py's bare-apiserver runner (no test runs on it any more; kept
for benchmarks/rt_monitoring_load.py) reports a server that cannot start as an error, never a skip; and the
session's multi-node cluster answers and reports its start-up time."""

import pytest

from tests.kubeapi import KubeAPIError, KubeAPIServer

pytestmark = pytest.mark.kube


def test_a_server_that_cannot_start_raises_with_its_log(tmp_path):
    broken = tmp_path / "kube-apiserver"
    broken.write_text("#!/bin/sh\necho 'flag provided but not defined' >&2\nexit 3\n")
    broken.chmod(0o755)
    server = KubeAPIServer(broken)
    with pytest.raises(KubeAPIError, match=r"(?s)exited with 3.*flag provided but not defined"):
        server.start(attempts=1)
    assert not server.dir.exists() and not server.procs  # etcd stopped, temporary files gone


def test_server_answers_and_reports_its_start_up_time(kube_server, kube):
    assert kube_server.startup_seconds > 0
    assert kube.list_namespace().items  # default, kube-system, ...
