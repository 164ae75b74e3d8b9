"""What the decoder knows about each node: its profile (from the identity seen in the log or the
DCF), the dictionary that names its objects, and the PDO mappings of a DCF."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from servodesk.od import ObjectDictionaryModel, OdSub, load_od
from servodesk.pdo.decode import PdoDecoder
from servodesk.pdo.read import KINDS, PDO_SPAN, RawPdo, Slot, to_config
from servodesk.profiles import ProfileDictionaries, ProfileMatch, load_known, match
from servodesk.sdo import codec
from servodesk_data import PROFILE_NAMES, DriveData, EmcyFormat

DEVICE_TYPE = (0x1000, 0)  # Device type
VENDOR_ID = (0x1018, 1)  # Identity object: Vendor-ID
PRODUCT_CODE = (0x1018, 2)  # Identity object: Product code
_CIA402_DEVICE_TYPE = 0x00020192  # what an unknown node is assumed to be: a CiA 402 drive


@dataclass(frozen=True, slots=True)
class PdoChannel:
    node: int
    label: str  # "TPDO1"
    decoder: PdoDecoder


@dataclass
class NodeProfile:
    """One node's profile as far as the log tells it."""

    node: int
    profile: ProfileMatch
    model: ObjectDictionaryModel
    device_type: int | None = None
    vendor_id: int | None = None
    product_code: int | None = None
    named: bool = False  # the user named its drive for this decode

    @property
    def data(self) -> DriveData | None:
        """Fault table and quirks; None for a generic profile."""
        return self.profile.data

    @property
    def label(self) -> str:
        return self.profile.label


class DecodeContext:
    """Profiles of the nodes seen so far; a node's profile changes when its identity appears."""

    def __init__(
        self,
        *,
        dcf: Path | None = None,
        known: Sequence[DriveData] | None = None,
        profiles: Mapping[int, str] | None = None,
    ):
        self._known = tuple(known) if known is not None else load_known()
        self._dictionaries = ProfileDictionaries()
        self._generic = match(_CIA402_DEVICE_TYPE, None, None, known=self._known)
        self._generic_model = self._dictionaries.model(self._generic, 1)
        self.nodes: dict[int, NodeProfile] = {}
        self.pdos: dict[int, PdoChannel] = {}  # COB-ID -> mapping
        self.bitrate: int | None = None
        self._alarm: tuple[ProfileMatch | None] | None = None  # alarm_profile(), once
        if dcf is not None:
            self._load_dcf(dcf)
        for node, name in sorted((profiles or {}).items()):
            self._name_profile(node, name)

    def alarm_profile(self) -> ProfileMatch | None:
        """The one known drive whose EMCY is a 2-byte alarm number (the MDi-S1-C); None when
        none or several are (a 2-byte EMCY then names no drive)."""
        if self._alarm is None:
            found = [d for d in self._known if d.quirks.emcy_format is EmcyFormat.ALARM_NUMBER]
            self._alarm = (self._match(found[0]) if len(found) == 1 else None,)
        return self._alarm[0]

    def _match(self, data: DriveData) -> ProfileMatch:
        identity = data.identity
        return match(identity.device_type, identity.vendor_id, identity.product_code,
                     known=self._known)  # fmt: skip

    def _name_profile(self, node: int, name: str) -> None:
        """The user's word for a node's drive: its fault table and quirks from the start (a
        DCF of the node keeps naming its objects)."""
        data = next((d for d in self._known if d.profile == name), None)
        if data is None:
            raise ValueError(f"unknown drive profile {name!r}; known: {self.profile_names()}")
        found = self._match(data)
        info = self.node(node)
        if info.profile.name != found.name:
            info.profile = found
            if info.model is self._generic_model:
                info.model = self._dictionaries.model(found, node)
        info.named = True

    def profile_names(self) -> str:
        return ", ".join(d.profile for d in self._known)

    def node(self, node: int) -> NodeProfile:
        found = self.nodes.get(node)
        if found is None:
            found = self.nodes[node] = NodeProfile(node, self._generic, self._generic_model)
        return found

    def sub(self, node: int, index: int, subindex: int) -> OdSub | None:
        return self.node(node).model.get(index, subindex)

    def name(self, node: int, index: int, subindex: int) -> str | None:
        model = self.node(node).model
        sub = model.get(index, subindex)
        return None if sub is None else codec.entry_name(model, sub)

    def identity_value(self, node: int, index: int, subindex: int, value: int) -> str | None:
        """Record an identity object read from `node`; the new profile's label when the node
        now matches another profile."""
        info = self.node(node)
        key = (index, subindex)
        if key == DEVICE_TYPE:
            info.device_type = value
        elif key == VENDOR_ID:
            info.vendor_id = value
        elif key == PRODUCT_CODE:
            info.product_code = value
        else:
            return None
        found = match(info.device_type, info.vendor_id, info.product_code, known=self._known)
        # only a shipped drive profile replaces the generic CiA 402 names (a generic CiA 301
        # match would name fewer objects)
        if found.data is None or found.name == info.profile.name:
            return None
        info.profile = found
        info.model = self._dictionaries.model(found, node)
        return found.label

    # ------------------------------------------------------------------ DCF

    def _load_dcf(self, path: Path) -> None:
        """Node id, identity, bitrate and PDO mappings of a DCF (CiA 306)."""
        model = load_od(path)
        node = model.device.node_id or model.node_id
        if node:
            model = load_od(path, node_id=node)  # resolve $NODEID values for this node
        self.bitrate = model.device.baud_rate
        if not node:
            return
        info = self.node(node)
        for key in (DEVICE_TYPE, VENDOR_ID, PRODUCT_CODE):
            value = _value(model.get(*key))
            if value is not None:
                self.identity_value(node, key[0], key[1], value)
        info.model = model  # the DCF names this node's objects best
        for kind, base in KINDS:
            for comm in range(base, base + PDO_SPAN):
                if comm not in model.objects:
                    continue
                slot = Slot(kind, comm - base + 1)
                values = {
                    (index, sub.subindex): v
                    for index in (slot.comm, slot.mapping)
                    for sub in (
                        model.objects[index].subs.values() if index in model.objects else ()
                    )
                    if (v := _value(sub)) is not None
                }
                config = to_config(RawPdo(slot, values), model)
                if config.valid and config.mapping:
                    decoder = PdoDecoder(config.mapping, model)
                    self.pdos[config.cob_id] = PdoChannel(node, slot.label, decoder)


def parse_profiles(
    text: str | Sequence[str] | None, names: Sequence[str] = PROFILE_NAMES
) -> dict[int, str]:
    """ "1=mdi-s1c, 2=kinco" (or one item per string) -> {1: "mdi-s1c", 2: "kinco"}; a
    ValueError in words for anything else, or for a profile not in `names`."""
    items = [text] if isinstance(text, str) else list(text or ())
    found: dict[int, str] = {}
    for part in (p.strip() for item in items for p in item.split(",")):
        if not part:
            continue
        node, sep, name = part.partition("=")
        try:
            number = int(node.strip(), 0)
        except ValueError:
            number = 0
        if not sep or not 1 <= number <= 127 or not name.strip():
            raise ValueError(f"{part!r}: name a drive as NODE=PROFILE, e.g. 1=mdi-s1c")
        if name.strip() not in names:
            raise ValueError(f"{name.strip()!r}: no such drive profile; known: {', '.join(names)}")
        found[number] = name.strip()
    return found


def _value(sub: OdSub | None) -> int | None:
    if sub is None:
        return None
    value = sub.value if sub.value is not None else sub.default
    return value if isinstance(value, int) else None
