"""No dead ends for a newcomer (issue 30, item 8): a 404 and a 500 are dashboard pages with the navigation and
a way on; the API docs link sends a visitor who is not logged in to the login page and back, not to a bare
401."""

import pytest
from django.test import Client
from django.urls import reverse

pytestmark = pytest.mark.django_db


def test_a_404_is_a_styled_page_with_the_navigation(member):
    response = member.get("/no-such-page/")
    assert response.status_code == 404
    body = response.content.decode()
    assert "css/continuum.css" in body and 'id="mainnav"' in body
    assert "Page not found" in body and "/no-such-page/" in body
    assert f'href="{reverse("dashboard:home")}"' in body


def test_a_404_for_a_visitor_offers_the_login(client):
    body = client.get("/schedules/999999/x/").content.decode()
    assert "Page not found" in body and f'href="{reverse("login")}?next=' in body


def test_a_500_is_a_styled_page_with_the_navigation(member, operator):
    from continuum.urls import server_error

    request = member.get("/").wsgi_request  # a request of the logged-in member
    request.user = operator
    response = server_error(request)
    assert response.status_code == 500
    body = response.content.decode()
    assert "css/continuum.css" in body and 'id="mainnav"' in body and "went wrong" in body


@pytest.mark.parametrize("name", ["api-docs", "api-redoc"])
def test_the_api_docs_send_a_visitor_to_log_in_and_back(operator, name):
    visitor = Client()
    url = reverse(name)
    response = visitor.get(url)
    assert response.status_code == 302
    assert response["Location"] == f"{reverse('login')}?next={url}"
    login = visitor.post(response["Location"], {"username": "operator", "password": "operator-pass-123"})
    assert login.status_code == 302 and login["Location"] == url
    assert visitor.get(url).status_code == 200


def test_the_api_docs_still_answer_a_token(api):
    assert api.get(reverse("api-docs")).status_code == 200
