"""The demo's applications (``load_demo``): a Montage workflow (WfFormat) and Topcuoglu's example DAG."""

from apps.tenancy.demo import DATA, Demo
from continuum.engine.formats import load_dag

from .models import Application


def demo_applications(demo: Demo) -> None:
    """Create the two demo applications unless they exist; ``demo.objects["applications"]`` (in that order)."""
    result = []
    for name, fmt in [("montage-chameleon-2mass-005d-001.json", None), ("topcuoglu.dag.json", None)]:
        graph = load_dag((DATA / name).read_text(), fmt)
        app = Application.objects.filter(fleet=demo.fleet, name=graph.name).first()
        if app is None:
            app = Application(
                fleet=demo.fleet, name=graph.name, source_format=graph.meta.get("source_format", "continuum")
            )
            app.set_graph(graph)
            app.save()
        result.append(app)
    demo.objects["applications"] = result
