"""What every Continuum management command shares: file reading, --json output, exit status 2 on bad input."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from django.core.management.base import BaseCommand, CommandError

from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import loads_json


class EngineCommand(BaseCommand):
    """Subclasses implement :meth:`run` returning a JSON-able dict and :meth:`summary` for humans."""

    def add_arguments(self, parser) -> None:
        parser.add_argument("--json", action="store_true", help="print the result as JSON on stdout")

    def handle(self, *args: Any, **options: Any) -> None:
        try:
            result = self.run(**options)
        except InputError as exc:
            raise CommandError(_one_line(str(exc)), returncode=2) from exc
        except OSError as exc:
            raise CommandError(_one_line(f"{exc.filename or ''}: {exc.strerror or exc}"), returncode=2) from exc
        if options["json"]:
            self.stdout.write(json.dumps(result, indent=2))
        else:
            self.stdout.write(self.summary(result))

    def run(self, **options: Any) -> dict:
        raise NotImplementedError

    def summary(self, result: dict) -> str:
        return json.dumps(result, indent=2)

    # ---- helpers ------------------------------------------------------------------------------
    @staticmethod
    def warn(message: str) -> None:
        """Something the input was accepted despite: one line on stderr (stdout stays the result)."""
        sys.stderr.write(f"warning: {_one_line(message)}\n")

    def warn_about(self, graph: Any) -> None:
        """The reader's warnings for a DAG it accepted (``graph.meta["warnings"]``)."""
        for message in graph.meta.get("warnings", []):
            self.warn(message)

    @staticmethod
    def read_text(path: str) -> str:
        p = Path(path)
        if not p.is_file():
            raise InputError(f"{path}: no such file")
        try:
            return p.read_text(encoding="utf-8")
        except UnicodeDecodeError as exc:
            raise InputError(f"{path}: not UTF-8 text (byte {exc.start})") from exc

    def read_json(self, path: str) -> Any:
        try:
            return loads_json(self.read_text(path))
        except InputError as exc:
            raise InputError(f"{path}: {exc}", exc.field) from exc

    def progress_printer(self, label: str, force: bool = False):
        """A progress callback on stderr: one redrawn line on a terminal; with ``force`` and no terminal
        (logs, CI), a line at every tenth of the work."""
        tty = sys.stderr.isatty()
        if not tty and not force:
            return None
        last = [-1]

        def show(done: int, total: int) -> None:
            pct = 100 * done // max(total, 1)
            if tty:
                sys.stderr.write(f"\r{label}: {done}/{total} ({pct}%)")
                if done >= total:
                    sys.stderr.write("\n")
            elif pct // 10 > last[0] or done >= total:
                last[0] = pct // 10
                sys.stderr.write(f"{label}: {done}/{total} ({pct}%)\n")
            sys.stderr.flush()

        return show


def _one_line(message: str) -> str:
    return " ".join(message.split())
