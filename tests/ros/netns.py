"""Hosts for the tests: Linux network namespaces joined to this one by veth pairs (needs root; the tests run as
root, as the real-node tests do), and a TCP relay in this namespace so that a process in a host reaches a
server that listens on this machine's loopback (Redis) at the host's gateway address.

Each host gets its own 10.N.i.0/24 (N random per test): the host is .2, this namespace .1. Everything made is
removed at the end (deleting a namespace deletes its end of the veth pair, and with it the pair).
"""

from __future__ import annotations

import contextlib
import random
import socket
import subprocess
import threading
import uuid
from collections.abc import Iterator
from dataclasses import dataclass


def sh(*argv: str) -> None:
    subprocess.run(argv, check=True, capture_output=True, text=True)


@dataclass
class Host:
    name: str  # the namespace
    address: str  # the host's address
    gateway: str  # this namespace's address on the host's link

    def argv(self, *cmd: str) -> list[str]:
        return ["ip", "netns", "exec", self.name, *cmd]


class Relay:
    """Accepts on ``listen`` and pipes every connection to ``target`` (both (host, port))."""

    def __init__(self, listen: tuple[str, int], target: tuple[str, int]):
        self.server = socket.create_server(listen)
        self.target = target
        self.port = self.server.getsockname()[1]
        self.closed = False
        threading.Thread(target=self._accept, daemon=True).start()

    def _accept(self) -> None:
        while not self.closed:
            try:
                client, _ = self.server.accept()
            except OSError:
                return
            upstream = socket.create_connection(self.target)
            for a, b in ((client, upstream), (upstream, client)):
                threading.Thread(target=self._pipe, args=(a, b), daemon=True).start()

    @staticmethod
    def _pipe(a: socket.socket, b: socket.socket) -> None:
        with contextlib.suppress(OSError):
            while data := a.recv(1 << 16):
                b.sendall(data)
        with contextlib.suppress(OSError):
            b.shutdown(socket.SHUT_WR)

    def close(self) -> None:
        self.closed = True
        self.server.close()


@contextlib.contextmanager
def hosts(count: int) -> Iterator[list[Host]]:
    tag = uuid.uuid4().hex[:6]
    net = random.randrange(100, 250)
    made: list[Host] = []
    try:
        for i in range(1, count + 1):
            ns, outer, inner = f"cvh{tag}{i}", f"cvv{tag}{i}", f"cvp{tag}{i}"
            host = Host(ns, f"10.{net}.{i}.2", f"10.{net}.{i}.1")
            sh("ip", "netns", "add", ns)
            made.append(host)
            sh("ip", "link", "add", outer, "type", "veth", "peer", "name", inner)
            sh("ip", "link", "set", inner, "netns", ns)
            sh("ip", "addr", "add", f"{host.gateway}/24", "dev", outer)
            sh("ip", "link", "set", outer, "up")
            sh(*host.argv("ip", "addr", "add", f"{host.address}/24", "dev", inner))
            sh(*host.argv("ip", "link", "set", inner, "up"))
            sh(*host.argv("ip", "link", "set", "lo", "up"))
            sh(*host.argv("ip", "route", "add", "default", "via", host.gateway))
        yield made
    finally:
        for host in made:
            subprocess.run(["ip", "netns", "del", host.name], capture_output=True)
