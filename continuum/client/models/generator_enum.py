from typing import Literal

GeneratorEnum = Literal["layered", "thesis"]

GENERATOR_ENUM_VALUES: set[GeneratorEnum] = {
    "layered",
    "thesis",
}


def check_generator_enum(value: str) -> GeneratorEnum:
    if value in GENERATOR_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {GENERATOR_ENUM_VALUES!r}")
