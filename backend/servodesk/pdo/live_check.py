"""The live check after an apply: per node, a capture of its valid PDOs' COB-IDs (live.py) and
the decoders that turn each COB-ID's last frame into named values (decode.py), read on demand.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import canopen

from servodesk.models.base import Value
from servodesk.models.pdo import LiveCheck, LivePdo, LiveValue
from servodesk.od import ObjectDictionaryModel
from servodesk.pdo.decode import Decoded, PdoDecoder, value_text
from servodesk.pdo.display import display_text
from servodesk.pdo.drive_use import drive_page_use
from servodesk.pdo.live import PdoCapture
from servodesk.pdo.model import PdoConfig


@dataclass
class _Check:
    capture: PdoCapture
    pdos: dict[int, tuple[PdoConfig, PdoDecoder]]  # COB-ID -> the PDO and its decoder
    drive_page: str | None  # what the Drive page does with the node's RPDOs


class LiveChecks:
    def __init__(self) -> None:
        self._checks: dict[int, _Check] = {}

    def start(
        self,
        node: int,
        network: canopen.Network,
        pdos: Sequence[PdoConfig],
        od: ObjectDictionaryModel,
    ) -> LiveCheck:
        """Capture every valid PDO of `node` (TPDOs it sends, RPDOs others send to it); a
        running check of the node starts over with these mappings."""
        self.stop(node)
        chosen: dict[int, tuple[PdoConfig, PdoDecoder]] = {}
        for pdo in sorted(pdos, key=lambda p: (p.kind != "tpdo", p.number)):
            if pdo.valid and pdo.cob_id not in chosen:
                chosen[pdo.cob_id] = (pdo, PdoDecoder(pdo.mapping, od))
        capture = PdoCapture(network, chosen)
        capture.start()
        self._checks[node] = _Check(capture, chosen, drive_page_use(pdos))
        return self.status(node)

    def stop(self, node: int) -> LiveCheck:
        check = self._checks.pop(node, None)
        if check is not None:
            check.capture.stop()
        return LiveCheck(node=node, active=False, pdos=[])

    def stop_all(self, keep: Callable[[canopen.Network], bool] = lambda _n: False) -> None:
        """Stop every capture whose network is not to be kept (bus reconnected or closed)."""
        for node, check in list(self._checks.items()):
            if not keep(check.capture.network):
                self.stop(node)

    def active(self, node: int) -> bool:
        return node in self._checks

    def status(self, node: int) -> LiveCheck:
        check = self._checks.get(node)
        if check is None:
            return LiveCheck(node=node, active=False, pdos=[])
        rows: list[LivePdo] = []
        for cob in check.capture.cob_ids:
            pdo, decoder = check.pdos[cob]
            stats = check.capture.stats(cob)
            data = stats.last_data
            rows.append(
                LivePdo(
                    cob_id=cob,
                    kind=pdo.kind,
                    number=pdo.number,
                    frames=stats.frames,
                    rate_hz=None if stats.rate_hz is None else round(stats.rate_hz, 2),
                    age_ms=None if stats.age_s is None else round(stats.age_s * 1000),
                    values=[] if data is None else [_value(d) for d in decoder.decode(data)],
                )
            )
        return LiveCheck(
            node=node,
            active=True,
            since=check.capture.started_wall,
            pdos=rows,
            drive_page=check.drive_page,
        )


def _value(decoded: Decoded) -> LiveValue:
    return LiveValue(
        index=decoded.index,
        subindex=decoded.subindex,
        name=decoded.name,
        value=_api_value(decoded.value),
        raw=decoded.raw_bytes.hex(" ").upper(),
        unit=decoded.unit or "",
        text=value_text(decoded.index, decoded.subindex, decoded.value),
        display=display_text(
            decoded.index,
            decoded.subindex,
            decoded.name,
            decoded.value,
            decoded.bits,
            decoded.unit or "",
        ),
    )


def _api_value(value: object) -> Value:
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, int | float | str):
        return value
    if isinstance(value, bytes | bytearray):
        return value.hex(" ").upper()
    return None if value is None else str(value)
