"""The shared UI kit (apps/ui): the panel registry, and the layering it allows: the kit imports no domain
app, and a host page never imports the app that extends it."""

import ast
from pathlib import Path

from apps.ui import panels

ROOT = Path(__file__).resolve().parents[2]


def imported_apps(folder: str, pattern: str = "*.py") -> set[str]:
    """The ``apps.<name>`` packages the Python files under ``folder`` (matching ``pattern``) import."""
    found = set()
    for path in (ROOT / folder).rglob(pattern):
        for node in ast.walk(ast.parse(path.read_text())):
            names = []
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            found.update(".".join(n.split(".")[:2]) for n in names if n.startswith("apps."))
    return found


def test_the_kit_imports_no_domain_app():
    assert imported_apps("apps/ui") <= {"apps.ui", "apps.tenancy"}


def test_host_pages_never_import_their_extensions():
    assert "apps.heft4k" not in imported_apps("apps/scheduling", "views.py")
    assert not imported_apps("apps/workloads", "views.py") & {"apps.scheduling", "apps.heft4k"}


def test_panels_render_in_order_and_skip_the_ones_with_nothing_to_show():
    host = "tests.host"
    try:
        panels.register_panel(host, "late", lambda obj, **kw: {"who": "late", **kw}, templates={"main": "b.html"})
        panels.register_panel(host, "early", lambda obj, **kw: {"who": obj}, templates={"side": "a.html"}, order=1)
        panels.register_panel(host, "silent", lambda obj, **kw: None)
        shown = panels.render_panels(host, "thing", extra=1)
        assert [p.name for p in shown] == ["early", "late"]
        assert shown[0].context == {"who": "thing"} and shown[0].templates == {"side": "a.html"}
        assert shown[1].context == {"who": "late", "extra": 1}
        # Registering again replaces (a re-import is harmless); unregistering removes.
        panels.register_panel(host, "late", lambda obj, **kw: {"who": "again"})
        assert [p.context["who"] for p in panels.render_panels(host, "thing")] == ["thing", "again"]
        panels.unregister_panel(host, "late")
        assert [p.name for p in panels.render_panels(host, "thing")] == ["early"]
    finally:
        for name in ("late", "early", "silent"):
            panels.unregister_panel(host, name)


def test_the_domain_apps_register_their_panels_on_the_pages_they_extend():
    assert [p.name for p in panels.panels_for("workloads.application")] == ["scheduling", "heft4k"]
    assert [p.name for p in panels.panels_for("scheduling.schedule")] == ["heft4k"]


def test_result_pages_are_registered_by_the_apps_that_own_them():
    from django.urls import reverse

    from apps.ui.links import result_page

    # A remap names its new schedule too: the remap page wins; a job's own page comes before a comparison.
    assert result_page({"remap": 3, "schedule": 4}) == reverse("heft4k:remap", args=[3])
    assert result_page({"schedule": 4, "page": "/ros/x/"}) == reverse("scheduling:schedule", args=[4])
    assert result_page({"comparison": 5, "page": "/ros/x/"}) == "/ros/x/"
    assert result_page({"comparison": 5, "page": "http://elsewhere/"}) == reverse("scheduling:comparison", args=[5])
    assert result_page({"schedule": "4"}) is None and result_page({}) is None
