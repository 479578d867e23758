"""The deployment's configuration (issue 25): `check --deploy` clean in production settings, HSTS and Secure
cookies over HTTPS, a Content-Security-Policy on every page, `testserver` not a default host, the image
non-root, compose publishing on loopback, and the quick start's credentials key apart from its database."""

from __future__ import annotations

import json
import os
import secrets
import stat
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]


def clean_environment() -> dict[str, str]:
    """This environment without what configures Continuum or Django (other test modules set some, e.g. the
    browser tests' DJANGO_ALLOW_ASYNC_UNSAFE, which `check --deploy` rightly refuses)."""
    prefixes = ("CONTINUUM_", "ALLOWED_HOSTS", "SECRET_KEY", "DJANGO_", "DEBUG")
    return {k: v for k, v in os.environ.items() if not k.startswith(prefixes)}


def settings_in_child(env: dict[str, str], *names: str, tmp_path: Path) -> dict:
    """Settings as a fresh process reads them from ``env`` (settings are read once, at start-up)."""
    code = (
        "import json, os, django; os.environ.setdefault('DJANGO_SETTINGS_MODULE', 'continuum.settings'); "
        "django.setup(); from django.conf import settings; "
        f"print(json.dumps({{n: getattr(settings, n, None) for n in {list(names)!r}}}, default=str))"
    )
    base = clean_environment()
    base |= {"CONTINUUM_VAR_DIR": str(tmp_path / "var"), "XDG_CONFIG_HOME": str(tmp_path / "config")}
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, env=base | env, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


PRODUCTION = {
    "DEBUG": "0",
    "SECRET_KEY": secrets.token_urlsafe(50),
    "ALLOWED_HOSTS": "continuum.example.org",
    "CONTINUUM_HTTPS": "1",
    "CONTINUUM_NUM_PROXIES": "1",
}


def test_check_deploy_is_clean_in_the_production_settings(tmp_path):
    env = clean_environment()
    env |= PRODUCTION | {"CONTINUUM_VAR_DIR": str(tmp_path / "var"), "XDG_CONFIG_HOME": str(tmp_path / "config")}
    done = subprocess.run(
        [sys.executable, "manage.py", "check", "--deploy", "--fail-level", "WARNING"],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    assert "no issues" in done.stdout


def test_https_turns_on_hsts_secure_cookies_and_the_redirect(tmp_path):
    names = ("SECURE_HSTS_SECONDS", "SESSION_COOKIE_SECURE", "CSRF_COOKIE_SECURE", "SECURE_SSL_REDIRECT",
             "SECURE_PROXY_SSL_HEADER", "ALLOWED_HOSTS")  # fmt: skip
    on = settings_in_child(PRODUCTION, *names, tmp_path=tmp_path)
    assert on["SECURE_HSTS_SECONDS"] >= 31536000 and on["SESSION_COOKIE_SECURE"] and on["CSRF_COOKIE_SECURE"]
    assert on["SECURE_SSL_REDIRECT"] and on["SECURE_PROXY_SSL_HEADER"] == ["HTTP_X_FORWARDED_PROTO", "https"]
    off = settings_in_child({}, *names, tmp_path=tmp_path)  # the quick start: plain http on loopback
    assert off["SECURE_HSTS_SECONDS"] == 0 and not off["SESSION_COOKIE_SECURE"] and not off["SECURE_SSL_REDIRECT"]
    assert off["SECURE_PROXY_SSL_HEADER"] is None  # X-Forwarded-Proto is a caller's header without a proxy
    assert "testserver" not in off["ALLOWED_HOSTS"]


@pytest.mark.django_db
def test_over_https_the_answer_carries_hsts_and_secure_cookies(client, settings):
    settings.SECURE_HSTS_SECONDS = 31536000
    settings.SESSION_COOKIE_SECURE = settings.CSRF_COOKIE_SECURE = True
    response = client.get("/login/", secure=True)
    assert response.status_code == 200
    assert response.headers["Strict-Transport-Security"].startswith("max-age=31536000")
    assert response.cookies["csrftoken"]["secure"] is True


@pytest.mark.django_db
@pytest.mark.parametrize("path", ["/login/", "/api/v1/clusters/", "/static/css/continuum.css"])
def test_every_answer_has_a_content_security_policy_without_inline_script(client, path):
    response = client.get(path)
    policy = response.headers["Content-Security-Policy"]
    directives = dict(d.strip().split(" ", 1) for d in policy.split(";"))
    assert directives["script-src"] == "'self' 'unsafe-eval'"  # no 'unsafe-inline' (eval: Plotly's WebGL)
    assert directives["style-src"] == "'self'" and directives["object-src"] == "'none'"
    assert directives["frame-ancestors"] == "'none'"


def test_no_page_template_has_an_inline_script_or_style_element():
    templates = [*ROOT.glob("templates/**/*.html"), *ROOT.glob("apps/*/templates/**/*.html")]
    assert templates
    for path in templates:
        text = path.read_text()
        for tag in ("<script", "<style"):
            for chunk in text.split(tag)[1:]:
                opening = chunk.split(">", 1)[0]
                assert tag == "<script" and ("src=" in opening or 'type="application/json"' in opening), (
                    f"{path.relative_to(ROOT)}: inline {tag}>: the Content-Security-Policy refuses it"
                )


def test_compose_publishes_gunicorn_on_loopback_only_and_the_image_is_not_root():
    compose = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
    for name, service in compose["services"].items():
        for port in service.get("ports", []):
            assert str(port).startswith("127.0.0.1:"), f"{name} publishes {port} on every address"
    lines = [line.split() for line in (ROOT / "Dockerfile").read_text().splitlines() if line.strip()]
    users = [words[1] for words in lines if words[0] == "USER"]
    cmd_at = max(i for i, words in enumerate(lines) if words[0] == "CMD")
    assert users and users[-1] not in ("root", "0") and lines.index(["USER", users[-1]]) < cmd_at


def test_the_quick_starts_credentials_key_lives_apart_from_its_database(tmp_path):
    var = tmp_path / "var"
    var.mkdir(mode=0o700)
    (var / "credentials_key").write_text("b" * 43 + "=\n")  # what an older version kept beside the database
    keys = settings_in_child({}, "CONTINUUM_CREDENTIALS_KEYS", tmp_path=tmp_path)["CONTINUUM_CREDENTIALS_KEYS"]
    assert keys == ["b" * 43 + "="]  # the same key: kubeconfigs stored with it still decrypt
    assert not (var / "credentials_key").exists()  # moved out of var/
    moved = list((tmp_path / "config" / "continuum" / "keys").glob("*.key"))
    assert len(moved) == 1 and moved[0].read_text().strip() == keys[0]
    assert stat.S_IMODE(moved[0].stat().st_mode) == 0o600
    assert stat.S_IMODE(moved[0].parent.stat().st_mode) == 0o700
    # Read again (web and worker share it), and another var/ gets a key of its own.
    again = settings_in_child({}, "CONTINUUM_CREDENTIALS_KEYS", tmp_path=tmp_path)["CONTINUUM_CREDENTIALS_KEYS"]
    assert again == keys
    other = settings_in_child(
        {"CONTINUUM_VAR_DIR": str(tmp_path / "var2")}, "CONTINUUM_CREDENTIALS_KEYS", tmp_path=tmp_path
    )["CONTINUUM_CREDENTIALS_KEYS"]
    assert other != keys and not list((tmp_path / "var2").glob("credentials_key*"))
