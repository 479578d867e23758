from typing import Literal

NodesListCriticality = Literal["A", "B", "C", "D"]

NODES_LIST_CRITICALITY_VALUES: set[NodesListCriticality] = {
    "A",
    "B",
    "C",
    "D",
}


def check_nodes_list_criticality(value: str) -> NodesListCriticality:
    if value in NODES_LIST_CRITICALITY_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {NODES_LIST_CRITICALITY_VALUES!r}")
