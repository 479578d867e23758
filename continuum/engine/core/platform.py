"""Platforms: the processors a DAG is scheduled on and the network between them.

This is the ``continuum.platform/v1`` contract. Moving an edge's data between two different processors
takes ``latency + data / bandwidth``; on the same processor it takes 0; a bandwidth of ``None`` means
transfers are free. Links are undirected. When ``route`` is set (cluster platforms), a pair of processors
without a direct link is routed over the links, as the thesis does with OSPF (3.3.2), by one of two rules
(``routing``):

- ``"latency"`` (default): the path with the least total latency (ties: the larger bottleneck bandwidth);
  the transfer takes the summed latency plus ``data / bottleneck bandwidth`` (cut-through). A direct
  link always wins.
- ``"ospf"``: the path with the least OSPF cost, the sum of ``1 / bandwidth`` over its hops (ties: less
  latency); the transfer takes the summed latency plus ``data * sum(1 / bandwidth)``, i.e. it is stored
  and forwarded at every hop (spec 02 section 6.1, our reading). A direct link is one candidate path.

Pairs that no path joins use the platform defaults. A processor with ``cores > 1`` is a multi-core
computing node (a Kubernetes node, thesis 3.3.2): it runs up to ``cores`` tasks at once and transfers
between its cores are free.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.core import limits
from continuum.engine.core.dag import Task, TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.unique import duplicates

__all__ = ["CLASSES", "FORMAT", "ROUTINGS", "Link", "Platform", "Processor"]

FORMAT = "continuum.platform/v1"
ROUTINGS = ("latency", "ospf")
#: The processor classes the product's platforms use (model platforms, boards, cluster nodes); any other key
#: of a task's cost names one processor.
CLASSES = ("cpu", "gpu")


@dataclass(frozen=True)
class Processor:
    id: str
    cls: str = "cpu"
    #: Speed factor for class costs: a class cost ``c`` takes ``c / speed`` here (related machines).
    #: A cost given for this processor's id is taken as measured, unscaled.
    speed: float = 1.0
    #: Number of CPUs that can run tasks at the same time (a cluster node); 1 for a single processor.
    cores: int = 1


@dataclass(frozen=True)
class Link:
    src: str
    dst: str
    bandwidth: float | None
    latency: float = 0.0


@dataclass
class Platform:
    processors: list[Processor]
    bandwidth: float | None = 1.0
    latency: float = 0.0
    links: list[Link] = field(default_factory=list)
    route: bool = False
    #: How routed pairs are joined when ``route`` is set: ``"latency"`` or ``"ospf"`` (module docstring).
    routing: str = "latency"

    def __post_init__(self) -> None:
        if not self.processors:
            raise InputError("a platform needs at least one processor", "processors")
        ids = [p.id for p in self.processors]
        dup = duplicates(ids)
        if dup:
            raise InputError(f"duplicate processor id {sorted(dup)[0]!r}", "processors")
        lim = limits.get()
        for p in self.processors:
            if not (p.speed > 0 and math.isfinite(p.speed)):
                raise InputError(f"processor {p.id!r} has invalid speed {p.speed!r}", "processors")
            if not lim.min_rate <= p.speed <= 1 / lim.min_rate:  # a cost is divided by it: keep sums finite
                raise InputError(
                    f"processor {p.id!r}: speed must be from {lim.min_rate:g} to {1 / lim.min_rate:g}, not {p.speed!r}",
                    "processors",
                )
            if isinstance(p.cores, bool) or not isinstance(p.cores, int) or p.cores < 1:
                raise InputError(f"processor {p.id!r} has invalid cores {p.cores!r} (a positive integer)", "processors")
            if p.cores > limits.get().cores:
                raise InputError(f"processor {p.id!r}: cores: at most {limits.get().cores}", "processors")
        if self.routing not in ROUTINGS:
            raise InputError(f"unknown routing {self.routing!r} (choose from {', '.join(ROUTINGS)})", "routing")
        _check_bandwidth(self.bandwidth, "platform")
        _check_latency(self.latency, "platform")
        known = set(ids)
        for link in self.links:
            for end in (link.src, link.dst):
                if end not in known:
                    raise InputError(f"link {link.src}-{link.dst} refers to unknown processor {end!r}", "links")
            _check_bandwidth(link.bandwidth, f"link {link.src}-{link.dst}")
            _check_latency(link.latency, f"link {link.src}-{link.dst}")
        self.index = {p.id: i for i, p in enumerate(self.processors)}
        self._matrices: tuple[list[list[float]], list[list[float]]] | None = None

    # ---- construction -------------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Platform:
        if not isinstance(data, Mapping):
            raise InputError("a platform document must be a JSON object")
        fmt = data.get("format", FORMAT)
        if fmt != FORMAT:
            raise InputError(f"unsupported format {fmt!r}, expected {FORMAT!r}", "format")
        procs = []
        if not isinstance(data.get("processors") or [], list) or not isinstance(data.get("links") or [], list):
            raise InputError("'processors' and 'links' must be lists", "processors")
        limits.check("processors", len(data.get("processors") or []))
        for i, raw in enumerate(data.get("processors") or []):
            if not isinstance(raw, Mapping) or not raw.get("id"):
                raise InputError(f"processors[{i}] needs an 'id'", "processors")
            cores = raw.get("cores", 1)
            if isinstance(cores, float) and cores.is_integer() and abs(cores) < 2**31:
                cores = int(cores)
            speed = _number(raw.get("speed", 1.0), f"processors[{i}].speed", "processors")
            procs.append(Processor(str(raw["id"]), str(raw.get("class", "cpu")), speed, cores))
        links = []
        for i, raw in enumerate(data.get("links") or []):
            if not isinstance(raw, Mapping) or "src" not in raw or "dst" not in raw:
                raise InputError(f"links[{i}] needs 'src' and 'dst'", "links")
            latency = _number(raw.get("latency", 0.0), f"links[{i}].latency", "links")
            links.append(Link(str(raw["src"]), str(raw["dst"]), raw.get("bandwidth"), latency))
        return cls(
            procs,
            bandwidth=data.get("bandwidth", 1.0),
            latency=_number(data.get("latency", 0.0), "latency", "latency"),
            links=links,
            route=bool(data.get("route", False)),
            routing=str(data.get("routing", "latency")),
        )

    @classmethod
    def homogeneous(cls, cpus: int = 1, gpus: int = 0, **kwargs: Any) -> Platform:
        """``cpus`` processors of class ``cpu`` and ``gpus`` of class ``gpu`` (the ``--cpus/--gpus`` flags)."""
        if cpus < 0 or gpus < 0 or cpus + gpus == 0:
            raise InputError("need at least one processor (--cpus/--gpus)", "processors")
        limits.check("processors", cpus + gpus)
        procs = [Processor(f"cpu{i}", "cpu") for i in range(cpus)]
        procs += [Processor(f"gpu{i}", "gpu") for i in range(gpus)]
        return cls(procs, **kwargs)

    @classmethod
    def named_by(cls, costs: Iterable[Mapping[str, Any]]) -> Platform | None:
        """The processors a DAG's cost table names, or ``None`` when its costs are per class only.

        ``costs`` is each task's cost map: ``task.cost`` of a :class:`TaskGraph`, or the ``cost`` of the stored
        ``continuum.dag/v1`` tasks (a page need not parse a large DAG to ask). A DAG may give its costs as the
        matrix W of Topcuoglu et al. (2002): one column per processor (``{"p0": 14, "p1": 16, "p2": 9}``), not
        per class (``cpu``, ``gpu``). Such a DAG runs only on those processors, so its own platform is them,
        joined by the paper's network: unit bandwidth and no latency (a transfer costs its data, the edge
        weights of the paper's Fig. 2).
        """
        names: set[str] = set()
        for cost in costs:
            names.update(key for key in cost if key not in CLASSES)
        if not names:
            return None
        limits.check("processors", len(names))
        ordered = sorted(names, key=lambda n: (len(n), n))  # p2 before p10
        return cls([Processor(name, "cpu") for name in ordered], bandwidth=1.0, latency=0.0)

    def to_dict(self) -> dict[str, Any]:
        doc = {
            "format": FORMAT,
            "processors": [
                {"id": p.id, "class": p.cls, "speed": p.speed} | ({"cores": p.cores} if p.cores != 1 else {})
                for p in self.processors
            ],
            "bandwidth": self.bandwidth,
            "latency": self.latency,
            "links": [
                {"src": lk.src, "dst": lk.dst, "bandwidth": lk.bandwidth, "latency": lk.latency} for lk in self.links
            ],
            "route": self.route,
        }
        if self.route:
            doc["routing"] = self.routing
        return doc

    def without(self, ids: Iterable[str]) -> Platform:
        """This platform minus the processors ``ids`` and their links (nodes gone offline, Algorithm 2)."""
        gone = set(ids)
        unknown = sorted(gone - set(self.index))
        if unknown:
            raise InputError(f"unknown processor {unknown[0]!r}", "processors")
        procs = [p for p in self.processors if p.id not in gone]
        if not procs:
            raise InputError("no processor is left", "processors")
        links = [lk for lk in self.links if lk.src not in gone and lk.dst not in gone]
        return Platform(procs, self.bandwidth, self.latency, links, self.route, self.routing)

    # ---- costs --------------------------------------------------------------------------------
    def cost(self, task: Task, proc: Processor) -> float | None:
        """Execution time of ``task`` on ``proc``; ``None`` when ``proc`` cannot run it."""
        c = task.cost.get(proc.id)
        if c is not None:
            return c
        c = task.cost.get(proc.cls)
        return None if c is None else c / proc.speed

    def cost_table(self, dag: TaskGraph) -> dict[str, list[tuple[int, float]]]:
        """Per task, the (processor index, time) pairs it can run on; rejects tasks nothing can run."""
        table: dict[str, list[tuple[int, float]]] = {}
        for task in dag.tasks.values():
            row = []
            for i, proc in enumerate(self.processors):
                c = self.cost(task, proc)
                if c is not None:
                    row.append((i, c))
            if not row:
                keys = ", ".join(sorted(task.cost))
                raise InputError(f"task {task.id!r} cannot run on any processor (its costs name {keys})", "tasks")
            table[task.id] = row
        return table

    def comm_matrices(self) -> tuple[list[list[float]], list[list[float]]]:
        """(latency, 1/bandwidth) between every pair of processors, 0 on the diagonal."""
        if self._matrices is None:
            self._matrices = self._build_matrices()
        return self._matrices

    def comm_time(self, src: str, dst: str, data: float) -> float:
        lat, inv = self.comm_matrices()
        i, j = self.index[src], self.index[dst]
        return lat[i][j] + data * inv[i][j]

    def mean_comm(self) -> tuple[float, float]:
        """Mean latency and mean 1/bandwidth over ordered pairs of distinct processors.

        Transfer time is linear in the data size, so ``mean_lat + data * mean_inv`` is exactly the mean
        transfer time over those pairs: the average communication cost c-bar of HEFT (Eq. 2.1).
        """
        n = len(self.processors)
        if n < 2:
            return 0.0, 0.0
        lat, inv = self.comm_matrices()
        pairs = n * (n - 1)
        return sum(map(sum, lat)) / pairs, sum(map(sum, inv)) / pairs

    def _build_matrices(self) -> tuple[list[list[float]], list[list[float]]]:
        n = len(self.processors)
        d_lat = self.latency if self.bandwidth is not None else 0.0
        d_inv = 0.0 if self.bandwidth is None else 1.0 / self.bandwidth
        lat = [[0.0 if i == j else d_lat for j in range(n)] for i in range(n)]
        inv = [[0.0 if i == j else d_inv for j in range(n)] for i in range(n)]
        if self.route and self.links:
            self._fill_routes(lat, inv)
            if self.routing == "ospf":  # the routes already weigh every direct link
                return lat, inv
        for link in self.links:  # a direct link always wins
            i, j = self.index[link.src], self.index[link.dst]
            if i == j:
                continue
            li, iv = (0.0, 0.0) if link.bandwidth is None else (link.latency, 1.0 / link.bandwidth)
            lat[i][j] = lat[j][i] = li
            inv[i][j] = inv[j][i] = iv
        return lat, inv

    def _fill_routes(self, lat: list[list[float]], inv: list[list[float]]) -> None:
        """All-pairs routes by Floyd-Warshall on numpy arrays (fast enough to re-route after a failure)."""
        import numpy as np

        n = len(self.processors)
        primary = np.full((n, n), np.inf)  # what the route minimises
        second = np.full((n, n), np.inf)  # the tie-break (latency mode: minus the bottleneck bandwidth)
        r_lat = np.zeros((n, n))
        r_inv = np.zeros((n, n))
        np.fill_diagonal(primary, 0.0)
        np.fill_diagonal(second, 0.0 if self.routing == "ospf" else -np.inf)
        for link in self.links:
            i, j = self.index[link.src], self.index[link.dst]
            if i == j:
                continue
            li, iv = (0.0, 0.0) if link.bandwidth is None else (link.latency, 1.0 / link.bandwidth)
            p, q = (iv, li) if self.routing == "ospf" else (li, -(math.inf if iv == 0 else 1.0 / iv))
            if (p, q) < (primary[i, j], second[i, j]):
                for a, b in ((i, j), (j, i)):
                    primary[a, b], second[a, b], r_lat[a, b], r_inv[a, b] = p, q, li, iv
        tol = 1e-12
        with np.errstate(invalid="ignore"):  # inf - inf between unreachable pairs compares as False
            primary, second, r_lat, r_inv = _floyd_warshall(primary, second, r_lat, r_inv, self.routing, tol)
        reach = np.isfinite(primary)
        for i in range(n):
            for j in range(n):
                if i != j and reach[i, j]:
                    lat[i][j] = float(r_lat[i, j])
                    inv[i][j] = float(r_inv[i, j])


def _floyd_warshall(primary, second, r_lat, r_inv, routing: str, tol: float):
    """Lexicographic (primary, second) all-pairs shortest paths, carrying each route's latency and 1/bw."""
    import numpy as np

    for k in range(len(primary)):
        p_new = primary[:, k, None] + primary[None, k, :]
        if routing == "ospf":
            q_new = second[:, k, None] + second[None, k, :]
        else:  # bottleneck: the smaller bandwidth, i.e. the larger minus-bandwidth
            q_new = np.maximum(second[:, k, None], second[None, k, :])
        better = (p_new < primary - tol * np.maximum(1.0, primary)) | (
            (np.abs(p_new - primary) <= tol * np.maximum(1.0, primary)) & (q_new < second - tol)
        )
        better &= np.isfinite(p_new)
        if not better.any():
            continue
        primary = np.where(better, p_new, primary)
        second = np.where(better, q_new, second)
        r_lat = np.where(better, r_lat[:, k, None] + r_lat[None, k, :], r_lat)
        if routing == "ospf":
            r_inv = np.where(better, r_inv[:, k, None] + r_inv[None, k, :], r_inv)
        else:
            r_inv = np.where(better, np.maximum(r_inv[:, k, None], r_inv[None, k, :]), r_inv)
    return primary, second, r_lat, r_inv


def _check_bandwidth(bw: Any, where: str) -> None:
    if bw is None:
        return
    if isinstance(bw, bool) or not isinstance(bw, (int, float)) or not (bw > 0 and math.isfinite(bw)):
        raise InputError(f"{where} has invalid bandwidth {bw!r} (a positive number or null)", "bandwidth")
    if bw < limits.get().min_rate:  # data sizes are divided by it: keep sums finite
        raise InputError(f"{where}: bandwidth must be at least {limits.get().min_rate:g}, not {bw!r}", "bandwidth")


def _check_latency(latency: Any, where: str) -> None:
    most = limits.get().magnitude
    if isinstance(latency, (int, float)) and not isinstance(latency, bool) and latency > most:
        raise InputError(f"{where}: latency: at most {most:g} (got {latency!r})", "latency")


def _number(value: Any, what: str, field: str) -> float:
    """A finite number from a document, or an InputError naming it (never a TypeError)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{what} must be a finite number, not {value!r:.60}", field)
    return float(value)
