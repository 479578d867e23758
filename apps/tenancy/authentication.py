"""Token authentication for robot fleets (``Authorization: Token <key>``)."""

from django.utils import timezone
from rest_framework import authentication, exceptions

from .models import FleetToken


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
        FleetToken.objects.filter(pk=token.pk).update(last_used=timezone.now())
        return token.user, token
