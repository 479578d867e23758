from typing import Literal

NodesListArch = Literal["amd64", "arm64", "riscv64"]

NODES_LIST_ARCH_VALUES: set[NodesListArch] = {
    "amd64",
    "arm64",
    "riscv64",
}


def check_nodes_list_arch(value: str) -> NodesListArch:
    if value in NODES_LIST_ARCH_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {NODES_LIST_ARCH_VALUES!r}")
