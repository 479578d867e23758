from typing import Literal

DagClassEnum = Literal["linear", "tree"]

DAG_CLASS_ENUM_VALUES: set[DagClassEnum] = {
    "linear",
    "tree",
}


def check_dag_class_enum(value: str) -> DagClassEnum:
    if value in DAG_CLASS_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {DAG_CLASS_ENUM_VALUES!r}")
