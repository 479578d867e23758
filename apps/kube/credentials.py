"""Credentials at rest: Fernet encryption of a column, with keys from the environment.

``settings.CONTINUUM_CREDENTIALS_KEYS`` (from ``CONTINUUM_CREDENTIALS_KEY``, comma-separated, newest first,
else a key kept apart from the database, ``settings.credentials_key_file``) feeds a
:class:`~cryptography.fernet.MultiFernet`: values are
encrypted with the first key and decrypted with any of them, so a key is rotated by putting the new one
first and running ``manage.py rotate_credentials``, then dropping the old one.

:class:`EncryptedTextField` is transparent to the code: the attribute holds the plain text, the column holds
``fernet:<token>``. A legacy plain-text value (written before encryption existed) reads as itself and is
encrypted on the next save (migration ``clusters.0002`` does that for every row). A value no key can decrypt
reads as :class:`Undecryptable`: truthy (the cluster still "has a kubeconfig"), saved back unchanged, and
refused by the loader with a message saying why.
"""

from __future__ import annotations

import functools

from cryptography.fernet import Fernet, InvalidToken, MultiFernet
from django.conf import settings
from django.core.exceptions import ImproperlyConfigured
from django.db import models

PREFIX = "fernet:"


class Undecryptable(str):
    """A stored ciphertext no configured key opens (the key changed without keeping the old one)."""

    __slots__ = ()


@functools.lru_cache(maxsize=4)
def _fernet(keys: tuple[str, ...]) -> MultiFernet:
    if not keys:
        raise ImproperlyConfigured("CONTINUUM_CREDENTIALS_KEYS is empty: set CONTINUUM_CREDENTIALS_KEY")
    try:
        return MultiFernet([Fernet(k.encode()) for k in keys])
    except ValueError as exc:
        raise ImproperlyConfigured(
            "CONTINUUM_CREDENTIALS_KEY must be Fernet keys (32 url-safe base64-encoded bytes), comma-separated"
        ) from exc


def fernet() -> MultiFernet:
    return _fernet(tuple(settings.CONTINUUM_CREDENTIALS_KEYS))


def is_encrypted(stored: str) -> bool:
    return stored.startswith(PREFIX)


def encrypt(text: str) -> str:
    """``fernet:<token>`` of ``text`` with the newest key; the empty string stays empty (nothing to hide)."""
    if not text:
        return ""
    return PREFIX + fernet().encrypt(text.encode()).decode()


def decrypt(stored: str) -> str:
    """The plain text of a stored value: decrypted, or a legacy plain value as is; :class:`Undecryptable`
    when no key opens it."""
    if not stored or not is_encrypted(stored):
        return stored
    try:
        return fernet().decrypt(stored[len(PREFIX) :].encode()).decode()
    except (InvalidToken, UnicodeDecodeError):
        return Undecryptable(stored)


def rotate(stored: str) -> str:
    """The stored value re-encrypted with the newest key (legacy plain text gets encrypted)."""
    if not stored:
        return ""
    if not is_encrypted(stored):
        return encrypt(stored)
    return PREFIX + fernet().rotate(stored[len(PREFIX) :].encode()).decode()


class EncryptedTextField(models.TextField):
    """A TextField whose column holds Fernet ciphertext. Lookups other than ``= ''`` make no sense on it."""

    description = "Text encrypted at rest (Fernet)"

    def from_db_value(self, value, expression, connection):
        return value if value is None else decrypt(value)

    def to_python(self, value):
        if isinstance(value, str) and is_encrypted(value) and not isinstance(value, Undecryptable):
            return decrypt(value)
        return super().to_python(value)

    def get_prep_value(self, value):
        value = super().get_prep_value(value)
        if value is None or value == "":
            return value
        if isinstance(value, Undecryptable):
            return str(value)  # keep the ciphertext as it is: a later key (or the old one back) may open it
        return encrypt(value)

    def value_to_string(self, obj):
        # dumpdata/serialization: never write the plain text out.
        value = self.value_from_object(obj)
        return "" if not value else (str(value) if isinstance(value, Undecryptable) else encrypt(value))
