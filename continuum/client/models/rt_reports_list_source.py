from typing import Literal

RtReportsListSource = Literal["kube", "rest"]

RT_REPORTS_LIST_SOURCE_VALUES: set[RtReportsListSource] = {
    "kube",
    "rest",
}


def check_rt_reports_list_source(value: str) -> RtReportsListSource:
    if value in RT_REPORTS_LIST_SOURCE_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {RT_REPORTS_LIST_SOURCE_VALUES!r}")
