"""Which fleets a request may see: the one behind a fleet token, else the user's memberships."""

from django.db.models import QuerySet

from .models import Fleet, FleetToken


def visible_fleets(request) -> QuerySet[Fleet]:
    if isinstance(getattr(request, "auth", None), FleetToken):
        return Fleet.objects.filter(pk=request.auth.fleet_id)
    user = request.user
    if not user.is_authenticated:
        return Fleet.objects.none()
    if user.is_superuser:
        return Fleet.objects.all()
    return Fleet.objects.filter(members=user)
