"""Token authentication for robot fleets (``Authorization: Token <key>``).

Keys are looked up by their SHA-256 (:func:`~apps.tenancy.models.hash_token_key`), so the database never holds
one in clear. Bad keys count against the caller's address: past ``CONTINUUM_THROTTLE_BAD_TOKENS`` a client
gets 429 instead of more guesses.
"""

from datetime import timedelta

from django.utils import timezone
from rest_framework import authentication, exceptions

from . import audit, throttling
from .models import FleetToken, hash_token_key

LAST_USED_RESOLUTION = timedelta(minutes=1)


class FleetTokenAuthentication(authentication.TokenAuthentication):
    keyword = "Token"
    model = FleetToken

    def authenticate(self, request):
        self._request = request
        return super().authenticate(request)

    def authenticate_credentials(self, key: str):
        request = getattr(self, "_request", None)
        throttling.check_bad_tokens(request)
        token = FleetToken.objects.select_related("user", "fleet").filter(key_hash=hash_token_key(key)).first()
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
            FleetToken.objects.filter(pk=token.pk).update(last_used=now)
        audit.note_token(token)
        return token.user, token
