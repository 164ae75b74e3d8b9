"""What PDO validation finds wrong, as plain data: the foundation that both the PDO package
(`servodesk.pdo.validate`, which finds problems) and the error model (`servodesk.errors`'s
`PdoInvalidError`, which carries them) build on, so the errors import nothing above them.
The API schema's `PdoProblem` (servodesk.models.pdo) mirrors `Problem` field for field."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

PdoKind = Literal["rpdo", "tpdo"]


@dataclass(frozen=True, slots=True)
class Problem:
    """One reason a configuration cannot be applied, in words, with the object it concerns."""

    kind: PdoKind
    number: int
    message: str
    index: int | None = None
    subindex: int | None = None
