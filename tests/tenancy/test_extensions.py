"""Extension points of the lowest app: demo steps contributed by the apps above it, and actions other apps add
to a viewset (the host never imports its extensions)."""

import pytest
from django.core.exceptions import ImproperlyConfigured
from django.core.management import call_command
from django.urls import reverse
from rest_framework import viewsets
from rest_framework.decorators import action

from apps.clusters.demo import demo_cluster
from apps.clusters.models import Cluster
from apps.jobs.models import Job
from apps.scheduling.demo import demo_schedule
from apps.tenancy.api import ExtensibleViewSetMixin
from apps.tenancy.demo import demo_steps, register_demo
from apps.workloads.demo import demo_applications
from apps.workloads.models import Application


def test_demo_steps_run_in_installed_apps_order_and_register_once():
    steps = demo_steps()
    assert [demo_cluster, demo_applications, demo_schedule] == [s for s in steps if s in (
        demo_cluster, demo_applications, demo_schedule)]  # fmt: skip
    register_demo(demo_cluster)
    assert demo_steps() == steps


def test_load_demo_makes_the_cluster_the_applications_and_one_schedule_job(db, tmp_path, settings):
    settings.VAR_DIR = tmp_path
    call_command("load_demo")
    call_command("load_demo")
    assert Cluster.objects.get(fleet__slug="demo").nodes.count() == 4
    assert Application.objects.filter(fleet__slug="demo").count() == 2
    job = Job.objects.get(kind="schedule")
    assert job.arguments["algorithm"] == "heft" and job.arguments["cluster"] == Cluster.objects.get().pk


def test_extension_actions_are_routed_like_the_host_s_own():
    assert reverse("api:application-schedule", args=[1]) == "/api/v1/applications/1/schedule/"
    assert reverse("api:application-compare", args=[1]) == "/api/v1/applications/1/compare/"
    assert reverse("api:schedule-remap", args=[1]) == "/api/v1/schedules/1/remap/"
    assert reverse("api:schedule-push", args=[1]) == "/api/v1/schedules/1/push/"


def test_extra_action_must_be_an_action_with_a_free_name():
    class Host(ExtensibleViewSetMixin, viewsets.GenericViewSet):
        def taken(self, request):
            pass

    def plain(self, request, pk=None):
        pass

    with pytest.raises(ImproperlyConfigured, match="not decorated with @action"):
        Host.extra_action(plain)

    @action(detail=True, methods=["post"])
    def taken(self, request, pk=None):
        pass

    with pytest.raises(ImproperlyConfigured, match="already has an attribute 'taken'"):
        Host.extra_action(taken)

    @action(detail=True, methods=["post"])
    def added(self, request, pk=None):
        pass

    assert Host.extra_action(added) is added and Host.extra_action(added) is added
    assert [a.__name__ for a in Host.get_extra_actions()] == ["added"]
