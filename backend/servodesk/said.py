"""Words said by id that travel as plain text: a `str`, the English every caller already
formats into messages, audit entries and events, that also knows its message id and
parameters (the page's `server` catalogue, docs/api.md "Texts in the user's language").

A text that names one of these (a jog's stop reason inside "jog stopped (…)", who uses a CAN id
inside a PDO problem) carries it as parameters: its English as `<name>`, its id as `<name>_id`
and its parameters as `<name>_<param>`, so the page says the inner text in its language too."""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import ClassVar, Self

Params = dict[str, str | int]


class SaidText(str):
    """English words with their message id; a subclass names its templates (`TEXTS`)."""

    TEXTS: ClassVar[Mapping[str, str]] = MappingProxyType({})
    message_id: str
    params: Params

    def __new__(cls, message_id: str, **params: str | int) -> Self:
        made = super().__new__(cls, cls.TEXTS[message_id].format(**params))
        made.message_id = message_id
        made.params = params
        return made


def said(text: str | None) -> tuple[str | None, Params]:
    """The message id and parameters of `text`; (None, {}) for words without an id."""
    if isinstance(text, SaidText):
        return text.message_id, dict(text.params)
    return None, {}


def kept(name: str, text: str | None, message_id: str | None, params: Params) -> Params:
    """A text kept as its words, id and parameters (a stored JogInfo's stop reason) as the
    parameters `name`, `name_id`, `name_*` of a text that names it."""
    named: Params = {name: str(text)}
    if message_id is not None:
        named[f"{name}_id"] = message_id
        named.update({f"{name}_{param}": value for param, value in params.items()})
    return named


def nested(name: str, text: str) -> Params:
    """`text` as the parameters `name`, `name_id`, `name_*` of a text that names it."""
    return kept(name, text, *said(text))
