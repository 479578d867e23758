"""Tenants: fleets (a robot fleet or an operator team) and the API tokens that act for them."""

import secrets

from django.conf import settings
from django.db import models
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


def new_token_key() -> str:
    return secrets.token_hex(20)


class FleetToken(models.Model):
    """A robot fleet's API token: it acts as ``user`` but sees only ``fleet``'s objects."""

    key = models.CharField(max_length=40, unique=True, default=new_token_key)
    fleet = models.ForeignKey(Fleet, on_delete=models.CASCADE, related_name="tokens")
    user = models.ForeignKey(settings.AUTH_USER_MODEL, on_delete=models.CASCADE, related_name="fleet_tokens")
    description = models.CharField(max_length=200, blank=True)
    created = models.DateTimeField(auto_now_add=True)
    last_used = models.DateTimeField(null=True, blank=True)

    def __str__(self) -> str:
        return f"{self.fleet} token {self.key[:6]}…"


class FleetOwned(models.Model):
    """Base for every object that belongs to one fleet; the API scopes querysets by it."""

    fleet = models.ForeignKey(Fleet, on_delete=models.CASCADE, related_name="+")

    class Meta:
        abstract = True
