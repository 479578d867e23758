"""Debian's ROS 1 for the tests: a real ``roscore`` on a free loopback port and rospy nodes (rospy_node.py) run
by /usr/bin/python3, where Debian installs rospy (``scripts/services.sh``'s ``ensure_ros1`` installs it).

Every process is started in a session of its own and stopped by its process group id, so that roscore's
children (rosmaster, rosout) go with it and nothing else on the machine is touched.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import signal
import socket
import subprocess
import time
import xmlrpc.client
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

ROS_PYTHON = "/usr/bin/python3"
NODE = Path(__file__).with_name("rospy_node.py")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def require_ros1() -> None:
    missing = [b for b in ("roscore", "rosbag") if shutil.which(b) is None]
    probe = subprocess.run([ROS_PYTHON, "-c", "import rospy, std_msgs.msg"], capture_output=True)
    if missing or probe.returncode:
        raise RuntimeError("Debian's ROS 1 is missing: run `source scripts/services.sh && ensure_ros1` "
                           f"(missing: {missing or 'rospy'})")  # fmt: skip


@dataclass
class Ros1:
    uri: str
    env: dict[str, str]
    home: Path
    procs: list[subprocess.Popen] = field(default_factory=list)

    def spawn(self, argv: list[str], **kw: Any) -> subprocess.Popen:
        proc = subprocess.Popen(argv, env=self.env, start_new_session=True, **kw)
        self.procs.append(proc)
        return proc

    def node(self, name: str, publish: list[dict] | None = None, subscribe: list[str] | None = None,
             timeout: float = 60, **extra: Any) -> subprocess.Popen:  # fmt: skip
        """A rospy node; returns once it printed ``ready`` (its publishers and subscribers are registered)."""
        spec = {"name": name, "publish": publish or [], "subscribe": subscribe or [], **extra}
        log = (self.home / f"{name}.log").open("w")
        proc = self.spawn([ROS_PYTHON, str(NODE), json.dumps(spec)], stdout=subprocess.PIPE, stderr=log, text=True)
        assert proc.stdout is not None
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            line = proc.stdout.readline()
            if line.strip() == "ready":
                return proc
            if not line and proc.poll() is not None:
                break
        raise RuntimeError(f"node {name} did not start: {(self.home / f'{name}.log').read_text()[-2000:]}")

    def master(self) -> xmlrpc.client.ServerProxy:
        return xmlrpc.client.ServerProxy(self.uri)

    def stop(self, proc: subprocess.Popen) -> None:
        if proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGINT)  # roslaunch shuts its children down on SIGINT
            try:
                proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(proc.pid, signal.SIGKILL)
                proc.wait(timeout=15)


@contextmanager
def roscore(home: Path, timeout: float = 90) -> Iterator[Ros1]:
    """A real roscore (rosmaster + rosout) on a free port; yields once the master answers getSystemState."""
    require_ros1()
    port = free_port()
    uri = f"http://127.0.0.1:{port}/"
    home.mkdir(parents=True, exist_ok=True)
    env = {**os.environ, "ROS_MASTER_URI": uri, "ROS_IP": "127.0.0.1", "ROS_HOME": str(home),
           "ROS_LOG_DIR": str(home / "log"), "PYTHONUNBUFFERED": "1"}  # fmt: skip
    env.pop("ROS_HOSTNAME", None)
    ros = Ros1(uri, env, home)
    core = ros.spawn(["roscore", "-p", str(port)], stdout=(home / "roscore.log").open("w"), stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + timeout
        while True:
            try:
                code, _, _ = ros.master().getSystemState("/test")
                if code == 1 and _rosout_up(ros):
                    break
            except OSError:
                pass
            if core.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"roscore did not start: {(home / 'roscore.log').read_text()[-2000:]}")
            time.sleep(0.2)
        yield ros
    finally:
        for proc in reversed(ros.procs):
            ros.stop(proc)


def _rosout_up(ros: Ros1) -> bool:
    _, _, state = ros.master().getSystemState("/test")
    return any(topic == "/rosout" for topic, _ in state[1])  # rosout subscribes to /rosout once it is up
