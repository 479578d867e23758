"""Tenants: fleets (a robot fleet or an operator team) and the API tokens that act for them."""

import hashlib
import hmac
import secrets

from django.conf import settings
from django.db import models
from django.utils import timezone
from django.utils.text import slugify


class Fleet(models.Model):
    name = models.CharField(max_length=100, unique=True)
    slug = models.SlugField(max_length=100, unique=True)
    description = models.TextField(blank=True)
    members = models.ManyToManyField(settings.AUTH_USER_MODEL, related_name="fleets", blank=True)
    created = models.DateTimeField(auto_now_add=True)

    class Meta:
        ordering = ["name"]

    def __str__(self) -> str:
        return self.name

    def save(self, *args, **kwargs) -> None:
        if not self.slug:
            self.slug = slugify(self.name)[:100]
        super().save(*args, **kwargs)


#: Characters of a key kept in clear (``FleetToken.prefix``): enough to tell tokens apart, far too few to guess
#: the rest (the key has 160 bits of entropy).
PREFIX_LENGTH = 8


def new_token_key() -> str:
    """A new random key (40 hex digits, 160 bits, the length the key column of migration 0001 holds); it is
    stored only as its SHA-256. Hex rather than URL-safe base64: a key that starts with "-" reads as an option
    on a command line (``--token KEY``)."""
    return secrets.token_hex(20)


def hash_token_key(key: str) -> str:
    """The stored form of a key. A fast hash is enough: keys are random, not passwords a dictionary could guess."""
    return hashlib.sha256(key.encode()).hexdigest()


class FleetTokenManager(models.Manager):
    def create_token(self, **fields) -> tuple["FleetToken", str]:
        """Create a token and return it with its key in clear, which is never stored and cannot be read again."""
        token = self.create(**fields)
        return token, token.plaintext


class FleetToken(models.Model):
    """A robot fleet's API token: it acts as ``user`` but sees only ``fleet``'s objects.

    Only the key's SHA-256 and its first characters are stored; the key itself exists in ``plaintext`` on the
    instance that created it, once. ``scope`` "robot" reads its fleet and posts reports and events;
    "operator" may do everything the fleet may (see :mod:`apps.tenancy.permissions`).
    """

    class Scope(models.TextChoices):
        ROBOT = "robot", "robot: read the fleet, post reports and events"
        OPERATOR = "operator", "operator: read and change the fleet"

    prefix = models.CharField(
        max_length=PREFIX_LENGTH, editable=False, db_index=True, help_text="first characters of the key"
    )
    key_hash = models.CharField(max_length=64, unique=True, editable=False, help_text="SHA-256 of the key")
    fleet = models.ForeignKey(Fleet, on_delete=models.CASCADE, related_name="tokens")
    user = models.ForeignKey(settings.AUTH_USER_MODEL, on_delete=models.CASCADE, related_name="fleet_tokens")
    scope = models.CharField(max_length=16, choices=Scope.choices, default=Scope.OPERATOR)
    description = models.CharField(max_length=200, blank=True)
    created = models.DateTimeField(auto_now_add=True)
    expires = models.DateTimeField(null=True, blank=True, help_text="empty: never expires")
    last_used = models.DateTimeField(null=True, blank=True)

    objects = FleetTokenManager()

    #: The key in clear, set only on the instance that created the token (not a field: never stored).
    plaintext: str | None = None

    def __str__(self) -> str:
        return f"{self.fleet} token {self.prefix}…"

    def save(self, *args, **kwargs) -> None:
        if not self.key_hash:
            self.set_key(new_token_key())
        super().save(*args, **kwargs)

    def set_key(self, key: str) -> None:
        self.plaintext = key
        self.prefix = key[:PREFIX_LENGTH]
        self.key_hash = hash_token_key(key)

    def matches(self, key: str) -> bool:
        return hmac.compare_digest(self.key_hash, hash_token_key(key))

    @property
    def expired(self) -> bool:
        return self.expires is not None and self.expires <= timezone.now()


class FleetOwned(models.Model):
    """Base for every object that belongs to one fleet; the API scopes querysets by it."""

    fleet = models.ForeignKey(Fleet, on_delete=models.CASCADE, related_name="+")

    class Meta:
        abstract = True
