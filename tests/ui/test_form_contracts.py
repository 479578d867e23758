"""One request contract per action: the dashboard's forms are validated by the API's request serializers and
take their job arguments from them, so the page and the API accept the same requests, refuse the same bad
input with the same message and start the same job."""

import html

import pytest
from django import forms
from django.urls import reverse

from apps.jobs.models import Job
from apps.scheduling.forms import CompareForm, ScheduleForm
from apps.scheduling.serializers import MAX_FRAMES, CompareRequestSerializer
from apps.ui.forms import contract_field
from apps.workloads.models import Application
from continuum.engine.device.board import board
from tests.conftest import make_application

pytestmark = pytest.mark.django_db

BOARD_FORM = {"target": "platform", "cpus": 1, "gpus": 1, "shared_memory": "on"}
BOARD = board(1, 1).to_dict()


@pytest.fixture
def fig31(fleet):
    return make_application(fleet, "fig31.dag.json")


def _compare_page(member, app, data):
    return member.post(
        reverse("scheduling:application-compare", args=[app.pk]), {f"compare-{k}": v for k, v in data.items()}
    )


def _api_errors(api, app, action, data) -> dict:
    response = api.post(f"/api/v1/applications/{app.pk}/{action}/", data, format="json")
    assert response.status_code == 400, response.content
    return response.json()


def test_the_compare_form_takes_comm_mode_and_starts_the_same_job_as_the_api(member, api, fig31):
    request = {"algorithms": ["heft", "xeft"], "rank_mode": "mean", "comm_mode": "pairs", "frames": 2}
    response = _compare_page(member, fig31, {**request, **BOARD_FORM})
    assert response.status_code == 302
    page_job = Job.objects.get(kind="compare")
    assert page_job.state == "succeeded", page_job.error
    assert page_job.arguments["comm_mode"] == "pairs"

    response = api.post(f"/api/v1/applications/{fig31.pk}/compare/", {**request, "platform": BOARD}, format="json")
    assert response.status_code == 202, response.content
    api_job = Job.objects.exclude(pk=page_job.pk).get(kind="compare")
    assert api_job.arguments == page_job.arguments


def test_the_compare_form_offers_the_contracts_comm_modes_with_its_default():
    form = CompareForm(application=Application(fleet_id=0))
    field = CompareRequestSerializer().fields["comm_mode"]
    assert [value for value, _ in form.fields["comm_mode"].choices] == list(field.choices)
    assert form.fields["comm_mode"].initial == field.default == "impl"


@pytest.mark.parametrize(
    ("data", "field"),
    [
        ({"frames": 0}, "frames"),
        ({"frames": MAX_FRAMES + 1}, "frames"),  # the API's own wording: "frames: at most N"
        ({"batch": MAX_FRAMES + 1}, "batch"),
        ({"frames": 2, "fps": 30, "period": 5}, "fps"),
        ({"fps": 0}, "fps"),
    ],
)
@pytest.mark.parametrize("action", ["schedule", "compare"])
def test_the_page_and_the_api_refuse_bad_frame_options_with_the_same_message(member, api, fig31, action, data, field):
    api_message = _api_errors(api, fig31, action, {"platform": BOARD, **data})[field][0]
    if action == "compare":
        response = _compare_page(member, fig31, {"algorithms": ["heft"], "rank_mode": "max", **BOARD_FORM, **data})
    else:
        url = reverse("scheduling:application-schedule", args=[fig31.pk])
        response = member.post(url, {"algorithm": "heft", **BOARD_FORM, **data})
    assert response.status_code == 400
    assert api_message in html.unescape(response.content.decode())
    assert not Job.objects.exists()


def test_a_frame_option_given_twice_is_refused_alike(member, api, fig31):
    api_message = _api_errors(api, fig31, "schedule", {"platform": BOARD, "frames": 2, "params": {"frames": 3}})
    url = reverse("scheduling:application-schedule", args=[fig31.pk])
    response = member.post(url, {"algorithm": "heft", **BOARD_FORM, "frames": 2, "params": '{"frames": 3}'})
    assert response.status_code == 400
    assert api_message["frames"][0] in html.unescape(response.content.decode())


def test_the_schedule_form_and_the_api_start_the_same_job(member, api, fig31):
    url = reverse("scheduling:application-schedule", args=[fig31.pk])
    response = member.post(url, {"algorithm": "xeft", **BOARD_FORM, "frames": 3, "period": 10})
    assert response.status_code == 302
    page_job = Job.objects.get(kind="schedule")
    request = {"algorithm": "xeft", "platform": BOARD, "frames": 3, "period": 10}
    assert api.post(f"/api/v1/applications/{fig31.pk}/schedule/", request, format="json").status_code == 202
    api_job = Job.objects.exclude(pk=page_job.pk).get(kind="schedule")
    assert api_job.arguments == page_job.arguments


def test_a_cluster_of_another_fleet_is_not_offered_to_the_form(member, fig31, fleets):
    from apps.clusters.models import Cluster

    foreign = Cluster.objects.create(fleet=fleets[1], name="theirs")
    response = member.post(
        reverse("scheduling:application-schedule", args=[fig31.pk]),
        {"algorithm": "heft", "target": "cluster", "cluster": foreign.pk},
    )
    assert response.status_code == 400 and not Job.objects.exists()


@pytest.mark.parametrize(
    "data",
    [
        {"generator": "layered", "n": 1},
        {"generator": "thesis", "ccr": 1},
        {"generator": "layered", "dag_class": "tree"},
    ],
)
def test_the_generate_form_and_the_api_refuse_alike(member, api, data):
    response = api.post("/api/v1/applications/generate/", {"seed": 0, **data}, format="json")
    assert response.status_code == 400
    page = member.post(reverse("workloads:application-generate"), {"seed": 0, **data})
    assert page.status_code == 400
    for messages in response.json().values():
        assert messages[0] in html.unescape(page.content.decode())
    assert Application.objects.count() == 0


@pytest.mark.parametrize(
    "data",
    [
        {"cpu_usage": 3, "gpu_usage": 3, "miss_rate_l1": 2},
        {"gpu_usage": 3},
        {"cpu_usage": 3, "gpu_usage": 3, "kernel_time": 10},
        {"cpu_usage": 3, "gpu_usage": 3, "cpu_workers": 0, "gpu_workers": 0},
    ],
)
def test_the_advice_form_and_the_api_refuse_alike(member, api, data):
    request = {"current_model": "SC", "cpu_workers": 1, "gpu_workers": 1, **data}
    response = api.post("/api/v1/devices/jetson-tx2/advise/", request, format="json")
    assert response.status_code == 400
    page = member.post(reverse("devices:device", args=["jetson-tx2"]), request)
    assert page.status_code == 400
    for messages in response.json().values():
        assert messages[0] in html.unescape(page.content.decode())


def test_a_contract_field_cannot_offer_what_the_api_refuses():
    with pytest.raises(ValueError, match="the form offers 'nope', which the API refuses"):
        contract_field(CompareRequestSerializer, "rank_mode", choices=[("max", "max"), ("nope", "nope")])
    field = contract_field(CompareRequestSerializer, "algorithms", widget=forms.CheckboxSelectMultiple)
    assert isinstance(field, forms.MultipleChoiceField)


def test_the_schedule_form_needs_the_request_to_see_clusters(fig31, fleet):
    """Without the caller's request the contract sees no cluster at all (fail closed)."""
    from apps.clusters.models import Cluster

    cluster = Cluster.objects.create(fleet=fleet, name="ours")
    form = ScheduleForm({"algorithm": "heft", "target": "cluster", "cluster": cluster.pk}, application=fig31)
    assert not form.is_valid() and "cluster" in form.errors
