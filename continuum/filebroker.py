"""The quick start's broker: kombu's filesystem transport, made safe for several processes and a full disk.

kombu's own (``filesystem://``) writes a message in place, in the queue directory, and a reader may take the
file before its writer has filled it: the worker read 0 bytes, failed to decode them and died, at every start
since the file stayed there (celery/kombu#1551; issue 25 and 30: twice in an hour, and for good once ``var/``
was full, which leaves such files behind too). Here:

* a message is written to a hidden temporary name and renamed into the queue when complete (``rename`` is
  atomic): a reader never sees a partial file, and a write that fails (ENOSPC) leaves nothing in the queue;
* a reader takes a file by renaming it to a name of its own first, so two readers never get the same message;
* a file that is empty or does not decode (from an older version, a disk that filled up, a hand) is moved to
  ``quarantine/`` beside the queue and logged, and the reader goes on to the next one;
* leftover temporary files of a writer that died are removed after :data:`STALE_S`, and messages taken by a
  reader that died before reading them go back to the queue.

The queue directory must be on one file system (it is: ``var/broker/``). Selected by ``continuumfs://``
(registered below; settings use it when ``CELERY_BROKER_URL`` is not set).
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import logging
import os
import time
import uuid
from pathlib import Path
from typing import Any

from kombu.exceptions import ChannelError
from kombu.transport import TRANSPORT_ALIASES, filesystem, virtual

log = logging.getLogger(__name__)
#: Seconds after which a temporary file (writer gone) is removed and a taken one (reader gone) is put back.
STALE_S = 300.0
PART = ".part"
TAKEN = ".taken"


def _claims_of_dead(name: str) -> bool:
    """True for a file taken (``.<name>.<pid>.taken``) by a process of this host that no longer runs."""
    try:
        pid = int(name[: -len(TAKEN)].rsplit(".", 1)[1])
        os.kill(pid, 0)
    except (ValueError, IndexError):
        return False
    except ProcessLookupError:
        return True
    except PermissionError:
        return False
    return False


class Channel(filesystem.Channel):
    _last_tidy = 0.0

    @property
    def quarantine_folder(self) -> Path:
        return Path(self.transport_options.get("quarantine_folder") or Path(self.data_folder_in).parent / "quarantine")

    def _put(self, queue: str, payload: Any, **kwargs: Any) -> None:
        name = f"{round(time.monotonic() * 1000)}_{uuid.uuid4()}.{queue}.msg"
        final = os.path.join(self.data_folder_out, name)
        part = os.path.join(self.data_folder_out, f".{name}{PART}")
        try:
            with open(part, "wb") as f:
                f.write(json.dumps(payload).encode())
            os.rename(part, final)  # complete, or not there at all
        except OSError as exc:  # ENOSPC, EROFS...: the sender is told, and the queue holds nothing partial
            with contextlib.suppress(OSError):
                os.unlink(part)
            raise ChannelError(f"cannot add a message to {self.data_folder_out}: {exc}") from exc

    def _get(self, queue: str) -> Any:
        self._tidy()
        wanted = f"{queue}.msg"
        folder = self.data_folder_in
        for name in sorted(os.listdir(folder)):
            if name.startswith(".") or name.partition(".")[2] != wanted:
                continue
            taken = os.path.join(folder, f".{name}.{os.getpid()}{TAKEN}")
            try:
                os.rename(os.path.join(folder, name), taken)  # only one reader wins
            except OSError:  # another reader took it
                continue
            data = b""
            try:
                with open(taken, "rb") as f:
                    data = f.read()
                payload = json.loads(data)
                if not isinstance(payload, dict):
                    raise ValueError(f"a message is a JSON object, not {type(payload).__name__}")
            except (OSError, ValueError) as exc:  # UnicodeDecodeError and JSONDecodeError are ValueErrors
                self._quarantine(taken, name, f"{len(data)} bytes: {exc}")
                continue
            os.unlink(taken)
            return payload
        raise virtual.Empty()

    def _quarantine(self, path: str, name: str, why: str) -> None:
        """Move a message file that cannot be delivered out of the queue (kept to look at), and say so."""
        target = self.quarantine_folder
        try:
            target.mkdir(mode=0o700, parents=True, exist_ok=True)
            os.rename(path, target / name)
            where = f"moved to {target}"
        except OSError:
            try:
                os.unlink(path)
                where = "deleted (it could not be moved)"
            except OSError:
                where = "left in place"
        log.warning("broker message file %s skipped (%s): %s", name, why, where)

    def _tidy(self) -> None:
        """Now and then: remove temporary files of dead writers, put back messages taken by dead readers."""
        now = time.time()
        if now - Channel._last_tidy < STALE_S / 10:
            return
        Channel._last_tidy = now
        folder = self.data_folder_in
        for name in os.listdir(folder):
            path = os.path.join(folder, name)
            try:
                old = now - os.stat(path).st_mtime > STALE_S
                if name.startswith(".") and name.endswith(PART) and old:
                    os.unlink(path)
                    log.warning("broker: removed %s, a message its writer never finished", name)
                elif name.startswith(".") and name.endswith(TAKEN) and (old or _claims_of_dead(name)):
                    original = name[1 : -len(TAKEN)].rsplit(".", 1)[0]
                    os.rename(path, os.path.join(folder, original))
                    log.warning("broker: %s put back in the queue (its reader is gone)", original)
            except OSError:
                continue

    def _size(self, queue: str) -> int:
        wanted = f"{queue}.msg"
        names = os.listdir(self.data_folder_in)
        return sum(1 for n in names if not n.startswith(".") and n.partition(".")[2] == wanted)

    def get_table(self, exchange: str) -> list:
        """The exchange's bindings; a file that does not decode (a full disk while it was written) reads as
        none, so the next bind writes it anew, instead of failing every remote control."""
        try:
            return super().get_table(exchange)
        except ValueError as exc:
            log.warning("broker: exchange %s's table does not decode (%s): read as empty", exchange, exc)
            return []

    def _queue_bind(self, exchange: str, routing_key: str, pattern: str, queue: str) -> None:
        table = self.get_table(exchange)
        entry = filesystem.exchange_queue_t(routing_key or "", pattern or "", queue or "")
        if entry in table:
            return
        file = self._exchange_file(exchange)
        self.control_folder.mkdir(exist_ok=True)
        part = file.with_name(f".{file.name}.{uuid.uuid4().hex}{PART}")
        # Read, add, replace under a lock of its own (the table file itself is replaced, so it cannot be the lock).
        with open(file.with_name(f".{file.name}.lock"), "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            table = self.get_table(exchange)
            if entry in table:
                return
            try:
                part.write_text(json.dumps([entry, *table]))
                os.rename(part, file)
            except OSError as exc:
                part.unlink(missing_ok=True)
                raise ChannelError(f"cannot write {file}: {exc}") from exc


class Transport(filesystem.Transport):
    Channel = Channel
    global_state = virtual.BrokerState()
    driver_name = "continuumfs"


TRANSPORT_ALIASES["continuumfs"] = "continuum.filebroker:Transport"
