"""A process keeps the robot tokens it looked up for a moment (issue 15: reports many times a second), and a
revocation still takes effect on the next request: deleting or saving a token, its user or its fleet bumps the
generation in the shared cache and empties what the process kept (apps/tenancy/authentication.py)."""

import pytest
from django.core.cache import cache
from django.db import connection
from django.test.utils import CaptureQueriesContext

from apps.tenancy import authentication
from apps.tenancy.models import FleetToken

from .test_tokens import client_for

pytestmark = pytest.mark.django_db


@pytest.fixture
def robot(fleet, django_user_model):
    user = django_user_model.objects.create_user("cache-robot")
    token, key = FleetToken.objects.create_token(fleet=fleet, user=user, scope=FleetToken.Scope.ROBOT)
    return token, client_for(key)


def token_queries(client) -> tuple[int, list[str]]:
    with CaptureQueriesContext(connection) as queries:
        status = client.get("/api/v1/rt-reports/").status_code
    return status, [q["sql"] for q in queries if 'FROM "tenancy_fleettoken"' in q["sql"]]


def test_a_robot_token_is_looked_up_once_then_kept(robot):
    _, client = robot
    status, looked = token_queries(client)
    assert status == 200 and len(looked) == 1
    status, looked = token_queries(client)
    assert status == 200 and looked == []


@pytest.mark.parametrize("revoke", ["delete token", "deactivate user", "delete user", "delete fleet", "expire"])
def test_a_revocation_is_honoured_on_the_next_request(robot, revoke):
    token, client = robot
    assert token_queries(client)[0] == 200 and token_queries(client)[1] == []  # kept
    if revoke == "delete token":
        token.delete()
    elif revoke == "deactivate user":
        token.user.is_active = False
        token.user.save()
    elif revoke == "delete user":
        token.user.delete()
    elif revoke == "delete fleet":
        token.fleet.delete()
    else:
        from django.utils import timezone

        token.expires = timezone.now()
        token.save()
    assert client.get("/api/v1/rt-reports/").status_code == 401


def test_another_process_revoking_bumps_the_shared_generation(robot):
    """What another process's revocation leaves here: this process's entries untouched, the generation in the
    shared cache moved. The kept token is not used again: the row is read (and is gone)."""
    token, client = robot
    assert token_queries(client)[1] != [] and token_queries(client)[1] == []
    FleetToken.objects.filter(pk=token.pk)._raw_delete(connection.alias)  # as another process would: no signal here
    assert client.get("/api/v1/rt-reports/").status_code == 200  # not told: kept until the generation moves
    cache.set(authentication.GENERATION_KEY, cache.get(authentication.GENERATION_KEY, 0) + 1)  # its bump
    assert client.get("/api/v1/rt-reports/").status_code == 401


def test_operator_tokens_are_never_kept_and_a_zero_ttl_keeps_nothing(fleet_token, robot, settings):
    client = client_for(fleet_token.plaintext)
    assert token_queries(client)[1] != [] and token_queries(client)[1] != []
    settings.CONTINUUM_ROBOT_TOKEN_CACHE_S = 0
    _, robot_client = robot
    assert token_queries(robot_client)[1] != [] and token_queries(robot_client)[1] != []
