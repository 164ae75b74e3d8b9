"""What every API schema module builds on: the value type, strict JSON integers and the base of
request bodies (every module of servodesk.models)."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, BeforeValidator, ConfigDict

Value = int | float | str | None


def _not_text(value: object) -> object:
    if isinstance(value, str | bool):
        raise ValueError("a number, not text or true/false")
    return value


def _not_bool(value: object) -> object:
    if isinstance(value, bool):
        raise ValueError("true/false is not a value here: send a number or text")
    return value


# A value written to a drive: a number or text, never true/false (true would write 1).
NOT_BOOL = BeforeValidator(_not_bool)

# A JSON integer: 12 and 12.0 (JSON Schema's integer), never "12" or 12.5.
JsonInt = Annotated[int, BeforeValidator(_not_text)]
# Bounds for JsonInt in an alias: Annotated[Annotated[int, Field(ge=…)], NOT_TEXT]. Given as
# JsonInt's own metadata instead, pydantic leaves them out of the JSON schema ("ge" instead
# of "minimum"), and the schema would promise what the API refuses.
NOT_TEXT = BeforeValidator(_not_text)


class RequestBody(BaseModel):
    """What clients send: no silent coercion ("12" is not 12, "true" is not true: JsonInt and
    StrictBool fields) and no unknown fields (a misspelt "comfirm" must not be ignored)."""

    model_config = ConfigDict(extra="forbid")
