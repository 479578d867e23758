from typing import Literal

ArchEnum = Literal["amd64", "arm64", "riscv64"]

ARCH_ENUM_VALUES: set[ArchEnum] = {
    "amd64",
    "arm64",
    "riscv64",
}


def check_arch_enum(value: str) -> ArchEnum:
    if value in ARCH_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {ARCH_ENUM_VALUES!r}")
