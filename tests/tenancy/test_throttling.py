"""Rate limits on API tokens, on bad keys and on logins, with low rates set for the test."""

import pytest
from django.core.cache import cache
from rest_framework.test import APIClient

from ..realtime.test_api import report


@pytest.fixture
def rates(settings):
    def set_rates(**rates):
        base = {"user": None, "reports": None, "anon": None}
        settings.REST_FRAMEWORK = {**settings.REST_FRAMEWORK, "DEFAULT_THROTTLE_RATES": {**base, **rates}}
        cache.clear()  # what fixtures did before does not count

    return set_rates


def test_token_requests_beyond_the_rate_get_429_and_other_tokens_are_not_slowed(api, other_api, rates):
    rates(user="3/min")
    assert [api.get("/api/v1/clusters/").status_code for _ in range(4)] == [200, 200, 200, 429]
    response = api.get("/api/v1/clusters/")
    assert response.status_code == 429 and "Retry-After" in response.headers
    assert other_api.get("/api/v1/clusters/").status_code == 200


def test_reports_have_their_own_budget(api, cluster, rates):
    rates(user="2/min", reports="3/min")
    body = {"cluster": cluster.pk, "reports": [report()]}
    codes = [api.post("/api/v1/rt-reports/", body, format="json").status_code for _ in range(4)]
    assert codes == [201, 201, 201, 429]
    # The general budget was not spent by the reports.
    assert [api.get("/api/v1/clusters/").status_code for _ in range(3)] == [200, 200, 429]


def test_session_users_are_throttled_per_user(client, operator, rates):
    rates(user="2/min")
    client.force_login(operator)
    assert [client.get("/api/v1/clusters/").status_code for _ in range(3)] == [200, 200, 429]


def test_guessing_keys_is_cut_off_per_address(fleet_token, settings):
    settings.CONTINUUM_THROTTLE_BAD_TOKENS = "3/min"
    guesser = APIClient()
    codes = []
    for i in range(4):
        guesser.credentials(HTTP_AUTHORIZATION=f"Token guess{i:035d}")
        codes.append(guesser.get("/api/v1/clusters/").status_code)
    assert codes == [401, 401, 401, 429]
    # Even the right key is refused from that address until the window ends: no more tries to learn from.
    guesser.credentials(HTTP_AUTHORIZATION=f"Token {fleet_token.plaintext}")
    assert guesser.get("/api/v1/clusters/").status_code == 429
    elsewhere = APIClient(REMOTE_ADDR="10.0.0.7")
    elsewhere.credentials(HTTP_AUTHORIZATION=f"Token {fleet_token.plaintext}")
    assert elsewhere.get("/api/v1/clusters/").status_code == 200


def test_dashboard_login_is_refused_after_repeated_failures(client, operator, settings):
    settings.CONTINUUM_LOGIN_FAILURES = 2
    for _ in range(2):
        response = client.post("/login/", {"username": "operator", "password": "wrong"})
        assert response.status_code == 200 and "_auth_user_id" not in client.session
    # The right password no longer helps from this address until the window has passed.
    response = client.post("/login/", {"username": "operator", "password": "operator-pass-123"})
    assert response.status_code == 429 and "too many failed logins" in response.content.decode()
    assert "_auth_user_id" not in client.session
    # Another address, or another user name, is not locked out.
    other = type(client)(REMOTE_ADDR="10.0.0.9")
    response = other.post("/login/", {"username": "operator", "password": "operator-pass-123"})
    assert response.status_code == 302 and "_auth_user_id" in other.session


def test_successful_login_clears_the_failures(client, operator, settings):
    settings.CONTINUUM_LOGIN_FAILURES = 2
    client.post("/login/", {"username": "operator", "password": "wrong"})
    assert client.post("/login/", {"username": "operator", "password": "operator-pass-123"}).status_code == 302
    client.logout()
    client.post("/login/", {"username": "operator", "password": "wrong"})
    assert client.post("/login/", {"username": "operator", "password": "operator-pass-123"}).status_code == 302


def test_admin_login_is_throttled_too(client, django_user_model, settings):
    settings.CONTINUUM_LOGIN_FAILURES = 1
    django_user_model.objects.create_superuser("root", password="root-pass-123456")
    client.post("/admin/login/", {"username": "root", "password": "nope"})
    response = client.post("/admin/login/?next=/admin/", {"username": "root", "password": "root-pass-123456"})
    assert response.status_code == 200 and "too many failed logins" in response.content.decode()
    assert "_auth_user_id" not in client.session


# ---- the client's address (issue 25: X-Forwarded-For was believed) ----------------------------------------
def test_a_forged_forwarded_for_neither_spends_a_robots_budget_nor_escapes_its_own(api, fleet_token, settings):
    settings.CONTINUUM_THROTTLE_BAD_TOKENS = "3/min"
    robot = APIClient(REMOTE_ADDR="192.0.2.10")
    robot.credentials(HTTP_AUTHORIZATION=f"Token {fleet_token.plaintext}")
    attacker = APIClient(REMOTE_ADDR="203.0.113.66")
    codes = []
    for i in range(5):  # a new forged address per request, then the robot's
        attacker.credentials(HTTP_AUTHORIZATION=f"Token guess{i:035d}")
        forged = f"198.51.100.{i}" if i < 4 else "192.0.2.10"
        codes.append(attacker.get("/api/v1/clusters/", HTTP_X_FORWARDED_FOR=forged).status_code)
    assert codes == [401, 401, 401, 429, 429]  # counted against the attacker's own connection
    assert robot.get("/api/v1/clusters/").status_code == 200


def test_a_forged_forwarded_for_does_not_reset_the_login_limit(client, operator, settings):
    settings.CONTINUUM_LOGIN_FAILURES = 2
    for i in range(2):
        client.post("/login/", {"username": "operator", "password": "wrong"}, HTTP_X_FORWARDED_FOR=f"10.1.1.{i}")
    response = client.post(
        "/login/", {"username": "operator", "password": "operator-pass-123"}, HTTP_X_FORWARDED_FOR="10.1.1.99"
    )
    assert response.status_code == 429 and "_auth_user_id" not in client.session


def test_behind_trusted_proxies_the_address_they_appended_counts(fleet_token, settings):
    settings.CONTINUUM_THROTTLE_BAD_TOKENS = "2/min"
    settings.CONTINUUM_NUM_PROXIES = 1
    via_proxy = APIClient(REMOTE_ADDR="127.0.0.1")
    for i in range(2):  # the caller writes the first entries, the proxy appends the address it saw
        via_proxy.credentials(HTTP_AUTHORIZATION=f"Token guess{i:035d}")
        via_proxy.get("/api/v1/clusters/", HTTP_X_FORWARDED_FOR=f"10.0.0.{i}, 198.51.100.1")
    via_proxy.credentials(HTTP_AUTHORIZATION=f"Token {fleet_token.plaintext}")
    assert via_proxy.get("/api/v1/clusters/", HTTP_X_FORWARDED_FOR="198.51.100.1").status_code == 429
    assert via_proxy.get("/api/v1/clusters/", HTTP_X_FORWARDED_FOR="198.51.100.2").status_code == 200
    # A request that skipped the proxy (no header): the connection's address, not the header's.
    assert via_proxy.get("/api/v1/clusters/").status_code == 200


# ---- the cache down (issue 25: every API request answered 500 while Redis was down) -----------------------
@pytest.fixture
def cache_down(settings):
    import socket

    with socket.socket() as s:  # a port nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    settings.CACHES = {
        "default": {"BACKEND": "django.core.cache.backends.redis.RedisCache", "LOCATION": f"redis://127.0.0.1:{port}/0"}
    }
    yield
    settings.CACHES = {"default": {"BACKEND": "django.core.cache.backends.locmem.LocMemCache"}}


def test_with_the_cache_down_the_limits_fail_open_with_a_log_line(api, client, operator, settings, cache_down,
                                                                  caplog, monkeypatch):  # fmt: skip
    from apps.tenancy import throttling

    rates = {"user": "1/min", "reports": None, "anon": "1/min"}
    settings.REST_FRAMEWORK = {**settings.REST_FRAMEWORK, "DEFAULT_THROTTLE_RATES": rates}
    settings.CONTINUUM_THROTTLE_BAD_TOKENS = "1/min"
    monkeypatch.setattr(throttling, "_last_logged", 0.0)
    assert [api.get("/api/v1/clusters/").status_code for _ in range(3)] == [200, 200, 200]
    assert "rate limits off: the cache is unreachable" in caplog.text
    bad = APIClient()
    bad.credentials(HTTP_AUTHORIZATION="Token " + "g" * 40)
    assert bad.get("/api/v1/clusters/").status_code == 401
    assert APIClient().get("/api/v1/clusters/").status_code in (401, 403)
    response = client.post("/login/", {"username": "operator", "password": "operator-pass-123"})
    assert response.status_code == 302
