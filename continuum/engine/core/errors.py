"""Errors raised by the engine for bad input."""

__all__ = ["InputError"]


class InputError(ValueError):
    """Input that the engine rejects; the message names the offending element (task, edge, line...).

    ``field`` is the input field the problem belongs to, so the API can report it as a field error.
    """

    def __init__(self, message: str, field: str | None = None):
        super().__init__(message)
        self.field = field
