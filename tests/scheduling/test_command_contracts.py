"""The management commands check their options with the API's request contracts: a bad value is refused
with the API's message (one line, exit status 2)."""

from pathlib import Path

import pytest
from django.core.management import call_command
from django.core.management.base import CommandError

from apps.containers.serializers import ClusterRequestSerializer
from apps.scheduling.serializers import MAX_FRAMES, ScheduleRequestSerializer
from continuum.engine.device.board import board

DATA = Path(__file__).resolve().parents[1] / "data"


def _contract_message(serializer_class, data: dict, field: str) -> str:
    contract = serializer_class(data=data)
    assert not contract.is_valid()
    return str(contract.errors[field][0])


def _refusal(command: str, *args: str) -> str:
    with pytest.raises(CommandError) as info:
        call_command(command, *args, skip_checks=True)
    assert info.value.returncode == 2
    message = str(info.value)
    assert len(message.splitlines()) == 1
    return message


@pytest.mark.parametrize(
    ("argv", "request_data", "field"),
    [
        (["--frames", str(MAX_FRAMES + 1)], {"frames": MAX_FRAMES + 1}, "frames"),
        (["--frames", "0"], {"frames": 0}, "frames"),
        (["--batch", str(MAX_FRAMES + 1), "--frames", "2"], {"batch": MAX_FRAMES + 1, "frames": 2}, "batch"),
        (["--fps", "30", "--period", "2"], {"fps": 30, "period": 2}, "fps"),
        (["--algorithm", "nope"], {"algorithm": "nope"}, "algorithm"),
        (["--frames", "2", "--param", "frames=3"], {"frames": 2, "params": {"frames": 3}}, "frames"),
    ],
)
def test_the_schedule_command_refuses_like_the_api(argv, request_data, field):
    expected = _contract_message(ScheduleRequestSerializer, {"platform": board(1).to_dict(), **request_data}, field)
    message = _refusal("schedule", str(DATA / "fig31.dag.json"), "--gpus", "1", *argv)
    assert expected in message


@pytest.mark.parametrize(
    ("argv", "request_data", "field"),
    [
        (["--containers", "0"], {"containers": 0}, "containers"),
        (["--containers", "2", "--max-share", "1.5"], {"containers": 2, "max_cluster_share": 1.5}, "max_cluster_share"),
        (["--containers", "2", "--max-share", "0"], {"containers": 2, "max_cluster_share": 0}, "max_cluster_share"),
        (["--memory-mib", "20", "--overhead-mib", "29"], {"memory_mib": 20, "overhead_mib": 29}, "memory"),
    ],
)
def test_the_cluster_ros_command_refuses_like_the_api(argv, request_data, field):
    expected = _contract_message(ClusterRequestSerializer, request_data, field)
    message = _refusal("cluster_ros", str(DATA / "irobot_sierra_nevada.json"), *argv)
    assert expected in message


def test_a_list_fields_error_names_the_first_bad_item_not_a_valid_one():
    """DRF reports a list field's errors with an empty entry per valid item; the command's one line names the
    first item that is wrong (an empty first entry used to end in StopIteration)."""
    from apps.tenancy.api import contract_error

    error = contract_error({"nodes": [{}, {"cpu": ["Ensure this value is greater than or equal to 0."]}]})
    assert str(error) == "nodes.cpu: Ensure this value is greater than or equal to 0." and error.field == "cpu"
    assert (
        str(contract_error({"nodes": ["'nodes' must be a non-empty list"]}))
        == "nodes: 'nodes' must be a non-empty list"
    )
