"""Login throttling for the dashboard and the admin: after ``CONTINUUM_LOGIN_FAILURES`` failed attempts for
one user name from one address within ``CONTINUUM_LOGIN_WINDOW_S`` seconds, the form refuses further
attempts (without checking the password) until the window has passed. Counted in the Django cache, so
gunicorn workers share the count when the cache is Redis; a successful login clears it."""

from __future__ import annotations

import hashlib

from django import forms
from django.conf import settings
from django.contrib.admin.forms import AdminAuthenticationForm
from django.contrib.auth.forms import AuthenticationForm
from django.contrib.auth.views import LoginView

from .clientaddr import client_address
from .throttling import cached, count, forget

LOCKED = "too many failed logins for this user from your address; try again in a few minutes"


def _key(request, username: str) -> str:
    ip = client_address(request) if request is not None else "-"
    digest = hashlib.sha256(f"{ip}\0{username.casefold()}".encode()).hexdigest()[:32]
    return f"login_failures_{digest}"


class ThrottledLoginMixin:
    def clean(self):
        username = self.data.get("username", "") or ""
        key = _key(self.request, username)
        if cached(key) >= settings.CONTINUUM_LOGIN_FAILURES:
            raise forms.ValidationError(LOCKED, code="throttled")
        try:
            cleaned = super().clean()
        except forms.ValidationError:
            count(key, settings.CONTINUUM_LOGIN_WINDOW_S)  # the window opens with the first failure
            raise
        forget(key)
        return cleaned


class ThrottledAuthenticationForm(ThrottledLoginMixin, AuthenticationForm):
    pass


class ThrottledAdminAuthenticationForm(ThrottledLoginMixin, AdminAuthenticationForm):
    pass


class ThrottledLoginView(LoginView):
    """The dashboard's login page; a refused (throttled) attempt answers 429 with the form and its error."""

    authentication_form = ThrottledAuthenticationForm

    def form_invalid(self, form):
        response = super().form_invalid(form)
        if any(e.code == "throttled" for e in form.non_field_errors().as_data()):
            response.status_code = 429
        return response
