"""Numbers the layered generator and the STG reader take stay finite and bounded (found by schemathesis:
``out_degree`` 1.1e308 made the generator raise OverflowError, a server error)."""

import pytest

from continuum.engine.core.errors import InputError
from continuum.engine.device.generators import layered_dag
from continuum.engine.formats import load_dag
from tests.conftest import DATA


@pytest.mark.parametrize(
    ("kwargs", "field", "needle"),
    [
        ({"out_degree": float("inf")}, "out_degree", "out_degree must be a finite number"),
        ({"shape": float("nan")}, "shape", "shape must be a finite number"),
        ({"mean_cost": 1e308}, "mean_cost", "would overflow"),
        ({"ccr": 1e308}, "mean_cost", "would overflow"),
    ],
)
def test_layered_generator_rejects_non_finite_parameters(kwargs, field, needle):
    with pytest.raises(InputError, match=needle) as info:
        layered_dag(30, **kwargs)
    assert info.value.field == field


def test_a_huge_out_degree_is_refused_and_one_above_the_task_count_is_capped_at_it():
    with pytest.raises(InputError, match="out_degree: at most 100"):
        layered_dag(40, seed=3, out_degree=1.1e308)
    above = layered_dag(20, seed=3, out_degree=90)
    dense = layered_dag(20, seed=3, out_degree=20)
    assert above.to_dict() | {"meta": None} == dense.to_dict() | {"meta": None}  # same draws: degree capped at n
    assert layered_dag(40, seed=3).to_dict() == layered_dag(40, seed=3, out_degree=3.0).to_dict()


@pytest.mark.parametrize(
    ("options", "needle"),
    [
        ({"ccr": 1e308}, "ccr must be a finite number >= 0"),
        ({"ccr": -1}, "ccr must be a finite number >= 0"),
        ({"processors": 10**7}, "processors must be an integer in 1..1024"),
    ],
)
def test_stg_options_are_bounded(options, needle):
    with pytest.raises(InputError, match=needle):
        load_dag((DATA / "sample00.stg").read_text(), "stg", options=options)


@pytest.mark.django_db
def test_generate_endpoint_answers_400_for_an_enormous_out_degree(api):
    response = api.post(
        "/api/v1/applications/generate/", {"generator": "layered", "n": 20, "out_degree": 1.1e308}, format="json"
    )
    assert response.status_code == 400 and "out_degree" in response.data
    ok = api.post("/api/v1/applications/generate/", {"generator": "layered", "n": 20, "out_degree": 20}, format="json")
    assert ok.status_code == 201, ok.data
