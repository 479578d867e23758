"""The node agent inside a container (issue 32): SCHED_DEADLINE from a runc container's namespaces and cgroup.

What a pod on a real node does, without the kubelet: ``buildah run`` (runc, its own PID/mount/UTS/IPC namespaces
and cgroup) of an image built here from ``continuum/base:bookworm`` with Debian's python3 (python3-minimal lacks
json), the agent mounted read-only. Measured: with ``CAP_SYS_NICE`` added the kernel admits the deadline task
inside the container (its cpuset is the whole root domain) and the overruns are counted; without it
sched_setattr is EPERM (exit 77). The tracer's SCHED_FIFO is refused there (the container's cpu cgroup has no
``cpu.rt_runtime_us``: RT group scheduling), so it traces at SCHED_OTHER and says so. Needs root and buildah
(CI runs as root).
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

from apps.containers import imagebuild
from continuum.engine.containers.image_inheritance import plan_images

ROOT = Path(__file__).resolve().parents[2]
HOG = "import time\nt = time.monotonic()\nwhile time.monotonic() - t < 1.0: pass\n"


@pytest.fixture(scope="module")
def python_image():
    if os.geteuid() != 0:
        pytest.fail("needs root (buildah's storage; CI runs as root)")
    try:
        imagebuild.image_layers(imagebuild.BASE_IMAGE)
    except imagebuild.BuildError:
        # Missing buildah or base image: the script installs buildah and debootstrap, and builds the base.
        subprocess.run(["bash", str(ROOT / "scripts" / "build-images.sh"), "base"], check=True, timeout=1800)
    plan = plan_images({"agent": ["python3"]}, distro_image=imagebuild.BASE_IMAGE, platforms=("amd64",),
                       repository="continuum-built")  # fmt: skip
    built = imagebuild.build(plan, lambda pct, msg: None)
    yield built["images"][-1]["reference"]
    imagebuild.remove(im["reference"] for im in built["images"])


def in_container(image: str, *agent_args: str, caps: tuple[str, ...] = ()) -> subprocess.CompletedProcess:
    container = subprocess.run(["buildah", "from", "--pull-never", image], capture_output=True, text=True,
                               check=True).stdout.strip().splitlines()[-1]  # fmt: skip
    try:
        argv = ["buildah", "run", *(a for c in caps for a in ("--cap-add", c)),
                "-v", f"{ROOT / 'continuum' / 'agent'}:/opt/agent/continuum/agent:ro",
                "-v", f"{ROOT / 'continuum' / '__init__.py'}:/opt/agent/continuum/__init__.py:ro",
                "--env", "PYTHONPATH=/opt/agent", container,
                "--", "python3", "-m", "continuum.agent", *agent_args]  # fmt: skip
        return subprocess.run(argv, capture_output=True, text=True, timeout=600)
    finally:
        subprocess.run(["buildah", "rm", container], capture_output=True, timeout=120)


def test_sched_deadline_inside_a_container_with_cap_sys_nice(python_image):
    proc = in_container(python_image, "run", "--runtime-ms", "2", "--deadline-ms", "10", "--period-ms", "10",
                        "--warmup-ms", "0", "--json", "--", "python3", "-c", HOG, caps=("CAP_SYS_NICE",))  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout.splitlines()[-1])
    assert out["overruns"] > 0 and not out["kernel_rejected"] and out["exit_code"] == 0
    assert out["command_uid"] == 65534 and out["agent_capabilities"] == ["CAP_KILL", "CAP_SYS_NICE"]
    assert out["tracer_policy"] in ("other", "fifo:1")
    # The node's admission read from inside the container: the same kernel, the same root domain.
    proc = in_container(python_image, "admission", caps=("CAP_SYS_NICE",))
    assert proc.returncode == 0, proc.stderr
    assert 0 < json.loads(proc.stdout.splitlines()[-1])["capacity"] <= len(os.sched_getaffinity(0))


def test_without_cap_sys_nice_the_kernel_says_eperm(python_image):
    proc = in_container(python_image, "run", "--runtime-ms", "2", "--deadline-ms", "10", "--period-ms", "10", "--",
                        "true")  # fmt: skip
    assert proc.returncode == 77 and "EPERM" in proc.stderr and "CAP_SYS_NICE" in proc.stderr
