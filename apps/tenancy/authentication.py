"""Token authentication for robot fleets (``Authorization: Token <key>``)."""

from datetime import timedelta

from django.utils import timezone
from rest_framework import authentication, exceptions

from .models import FleetToken

LAST_USED_RESOLUTION = timedelta(minutes=1)


class FleetTokenAuthentication(authentication.TokenAuthentication):
    keyword = "Token"
    model = FleetToken

    def authenticate_credentials(self, key: str):
        try:
            token = FleetToken.objects.select_related("user", "fleet").get(key=key)
        except FleetToken.DoesNotExist as exc:
            raise exceptions.AuthenticationFailed("invalid token") from exc
        if not token.user.is_active:
            raise exceptions.AuthenticationFailed("user inactive or deleted")
        now = timezone.now()
        # At most one write a minute per token: robots report many times a second.
        if token.last_used is None or now - token.last_used > LAST_USED_RESOLUTION:
            FleetToken.objects.filter(pk=token.pk).update(last_used=now)
        return token.user, token
