"""Token authentication for robot fleets (``Authorization: Token <key>``).

Keys are looked up by their SHA-256 (:func:`~apps.tenancy.models.hash_token_key`), so the database never holds
one in clear. Bad keys count against the caller's address: past ``CONTINUUM_THROTTLE_BAD_TOKENS`` a client
gets 429 instead of more guesses.

Robot tokens post reports many times a second (RT-Kube's monitoring endpoint, issue 15): a process keeps a
robot token it found for ``CONTINUUM_ROBOT_TOKEN_CACHE_S`` seconds (2; 0: never), so most reports cost no token
query. Revocation is honoured as follows. Deleting a token, its user or its fleet, or saving any of them
(an expiry moved, a user deactivated), bumps a generation number in the shared cache (``CACHES["default"]``,
Redis when ``CONTINUUM_CACHE_URL`` is set, as in docker-compose.yml) and empties this process's entries; every
request compares its entry's generation with the shared one, so with a shared cache a revoked token is refused
by the very next request in every process. Without one (the quick start's per-process memory cache) other
processes refuse it at most ``CONTINUUM_ROBOT_TOKEN_CACHE_S`` seconds later, which also bounds a change made
without signals (``QuerySet.update``). Expiry and the user's active flag are checked on every request, as
before. Operator tokens are never kept.
"""

import threading
import time
from datetime import timedelta

from django.conf import settings
from django.contrib.auth import get_user_model
from django.core.cache import cache
from django.db.models.signals import post_delete, post_save
from django.utils import timezone
from rest_framework import authentication, exceptions

from . import audit, throttling
from .models import Fleet, FleetToken, hash_token_key

LAST_USED_RESOLUTION = timedelta(minutes=1)
#: The shared cache's key of the token generation (see the module docstring).
GENERATION_KEY = "continuum:token-generation"
#: Entries a process keeps at most (emptied when full: keys are random, there is no locality to keep).
MAX_ENTRIES = 10_000
_kept: dict[str, tuple[float, object, FleetToken]] = {}  # key hash -> (monotonic time, generation, token)
_lock = threading.Lock()


def _generation() -> object:
    """The shared generation; with the cache down a new object each time, which matches no kept entry: every
    request then looks its token up in the database (never a revoked one kept past its revocation)."""
    try:
        return cache.get(GENERATION_KEY, 0)
    except Exception as exc:  # any failure of the cache's backend
        throttling.cache_down(exc)
        return object()


def revoke_kept(**_) -> None:
    """A token, user or fleet changed or was deleted: no process may go on using what it kept."""
    with _lock:
        _kept.clear()
    try:
        try:
            cache.incr(GENERATION_KEY)
        except ValueError:  # not set yet (or evicted): any new value differs from what entries were kept with
            cache.set(GENERATION_KEY, time.time_ns(), timeout=None)
    except Exception as exc:  # the cache is down: other processes' entries expire by their age
        throttling.cache_down(exc)


for _model in (FleetToken, Fleet, get_user_model()):
    post_save.connect(revoke_kept, sender=_model, dispatch_uid=f"token-cache-save-{_model.__name__}")
    post_delete.connect(revoke_kept, sender=_model, dispatch_uid=f"token-cache-delete-{_model.__name__}")


def _kept_token(key_hash: str) -> FleetToken | None:
    ttl = settings.CONTINUUM_ROBOT_TOKEN_CACHE_S
    entry = _kept.get(key_hash) if ttl > 0 else None
    if entry is None:
        return None
    at, generation, token = entry
    if time.monotonic() - at > ttl or generation != _generation():
        _kept.pop(key_hash, None)
        return None
    return token


def _keep(key_hash: str, token: FleetToken, generation: object) -> None:
    if settings.CONTINUUM_ROBOT_TOKEN_CACHE_S <= 0 or token.scope != FleetToken.Scope.ROBOT:
        return
    with _lock:
        if len(_kept) >= MAX_ENTRIES:
            _kept.clear()
        _kept[key_hash] = (time.monotonic(), generation, token)


class FleetTokenAuthentication(authentication.TokenAuthentication):
    keyword = "Token"
    model = FleetToken

    def authenticate(self, request):
        self._request = request
        return super().authenticate(request)

    def authenticate_credentials(self, key: str):
        request = getattr(self, "_request", None)
        throttling.check_bad_tokens(request)
        key_hash = hash_token_key(key)
        token = _kept_token(key_hash)
        if token is None:
            generation = _generation()  # read before the row: a revocation in between is not missed
            token = FleetToken.objects.select_related("user", "fleet").filter(key_hash=key_hash).first()
            if token is not None:
                _keep(key_hash, token, generation)
        if token is None or not token.matches(key):
            throttling.record_bad_token(request)
            raise exceptions.AuthenticationFailed("invalid token")
        if token.expired:
            raise exceptions.AuthenticationFailed("token expired")
        if not token.user.is_active:
            raise exceptions.AuthenticationFailed("user inactive or deleted")
        now = timezone.now()
        # At most one write a minute per token: robots report many times a second.
        if token.last_used is None or now - token.last_used > LAST_USED_RESOLUTION:
            FleetToken.objects.filter(pk=token.pk).update(last_used=now)  # no signal: the kept token stays
            token.last_used = now
        audit.note_token(token)
        return token.user, token
