"""The verification network's transport over Redis (thesis §3.5, Fig. 3.42; spec 03 §9).

Keys (all under one prefix, so several networks and tests can share a Redis server):

    {p}:events            stream of SUV events, in timestamp order: fields v (variable), x (JSON value), t (ms);
                          an entry with field ``end`` closes the stream
    {p}:req:{handler}     stream of requests to one handler (EXEC, MIGRATE, SHUTDOWN and the Fig. 3.43
                          protocol messages MIGRATION_START, T0, HANDOVER)
    {p}:verdicts          stream of verdicts: a violation, or a monitor's final state at shutdown
    {p}:acks              stream of acknowledgements (EXEC done, migration completed)
    {p}:monitors          hash monitor -> JSON {assertion, constants, options}
    {p}:handlers          hash handler -> JSON statistics (the stat handler's report, also its heartbeat)
    {p}:allocation        hash monitor -> handler running it (kept by the coordinator)
    {p}:moving            hash monitor -> JSON {source, target}: migrations in flight (set by the coordinator
                          that sent MIGRATE, cleared by the handler that completes or refuses it), so a newly
                          elected coordinator does not act on a monitor whose hand-over is under way
    {p}:coordinator       the elected coordinator's name, with a time-to-live renewed while it answers
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from typing import Any

import redis


class Bus:
    def __init__(self, url: str = "redis://127.0.0.1:6379/0", prefix: str = "cv"):
        self.redis = redis.Redis.from_url(url, decode_responses=True)
        self.prefix = prefix

    def key(self, *parts: str) -> str:
        return ":".join([self.prefix, *parts])

    # ---- events --------------------------------------------------------------------------------
    def publish_events(self, events: Iterable[tuple[str, Any, float]]) -> None:
        pipe = self.redis.pipeline(transaction=False)
        for n, (var, value, ts) in enumerate(events, start=1):
            pipe.xadd(self.key("events"), {"v": var, "x": json.dumps(value), "t": repr(float(ts))})
            if n % 500 == 0:
                pipe.execute()
        pipe.execute()

    def end_events(self) -> None:
        self.redis.xadd(self.key("events"), {"end": "1"})

    def read_events(self, last_id: str, count: int = 1000, block_ms: int | None = None):
        """[(id, event or None for the end marker)] after ``last_id``."""
        got = self.redis.xread({self.key("events"): last_id}, count=count, block=block_ms)
        out = []
        for _, entries in got or []:
            for entry_id, fields in entries:
                if "end" in fields:
                    out.append((entry_id, None))
                else:
                    out.append((entry_id, (fields["v"], json.loads(fields["x"]), float(fields["t"]))))
        return out

    def last_event_id(self) -> str:
        info = self.redis.xinfo_stream(self.key("events")) if self.redis.exists(self.key("events")) else None
        return info["last-generated-id"] if info else "0-0"

    # ---- requests --------------------------------------------------------------------------------
    def send(self, handler: str, kind: str, **body: Any) -> None:
        self.redis.xadd(self.key("req", handler), {"type": kind, "body": json.dumps(body)})

    def requests(self, handler: str, last_id: str, count: int = 100):
        got = self.redis.xread({self.key("req", handler): last_id}, count=count)
        return [(i, f["type"], json.loads(f["body"])) for _, entries in got or [] for i, f in entries]

    # ---- verdicts and acknowledgements -----------------------------------------------------------
    def verdict(self, monitor: str, handler: str, kind: str, body: Mapping) -> None:
        self.redis.xadd(self.key("verdicts"), {"monitor": monitor, "handler": handler, "kind": kind,
                                               "body": json.dumps(body)})  # fmt: skip

    def verdicts(self) -> list[dict]:
        out = []
        for _, fields in self.redis.xrange(self.key("verdicts")):
            out.append({**fields, "body": json.loads(fields["body"])})
        return out

    def ack(self, kind: str, **body: Any) -> None:
        self.redis.xadd(self.key("acks"), {"type": kind, "body": json.dumps(body)})

    def acks(self) -> list[tuple[str, dict]]:
        return [(f["type"], json.loads(f["body"])) for _, f in self.redis.xrange(self.key("acks"))]

    # ---- registry, statistics, allocation, election ----------------------------------------------
    def register_monitor(self, name: str, assertion: str, **options: Any) -> None:
        self.redis.hset(self.key("monitors"), name, json.dumps({"assertion": assertion, **options}))

    def monitors(self) -> dict[str, dict]:
        return {k: json.loads(v) for k, v in self.redis.hgetall(self.key("monitors")).items()}

    def report(self, handler: str, stats: Mapping) -> None:
        self.redis.hset(self.key("handlers"), handler, json.dumps(stats))

    def handlers(self) -> dict[str, dict]:
        return {k: json.loads(v) for k, v in self.redis.hgetall(self.key("handlers")).items()}

    def allocation(self) -> dict[str, str]:
        return self.redis.hgetall(self.key("allocation"))

    def set_allocation(self, monitor: str, handler: str) -> None:
        self.redis.hset(self.key("allocation"), monitor, handler)

    def start_moving(self, monitor: str, source: str, target: str) -> None:
        self.redis.hset(self.key("moving"), monitor, json.dumps({"source": source, "target": target}))

    def moving(self) -> dict[str, dict]:
        return {k: json.loads(v) for k, v in self.redis.hgetall(self.key("moving")).items()}

    def stop_moving(self, monitor: str) -> None:
        self.redis.hdel(self.key("moving"), monitor)

    def coordinator(self) -> str | None:
        return self.redis.get(self.key("coordinator"))

    def claim_coordinator(self, handler: str, ttl_ms: int) -> bool:
        return bool(self.redis.set(self.key("coordinator"), handler, nx=True, px=ttl_ms))

    def renew_coordinator(self, handler: str, ttl_ms: int) -> bool:
        # only the holder may extend its lease (compare-and-expire, atomically)
        script = (
            "if redis.call('get', KEYS[1]) == ARGV[1] then return redis.call('pexpire', KEYS[1], ARGV[2]) end return 0"
        )
        return bool(self.redis.eval(script, 1, self.key("coordinator"), handler, ttl_ms))

    def clear(self) -> None:
        """Delete every key of this network (tests)."""
        keys = list(self.redis.scan_iter(f"{self.prefix}:*"))
        if keys:
            self.redis.delete(*keys)
