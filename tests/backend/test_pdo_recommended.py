"""The manuals' recommended mappings, packed for the shipped dictionaries of the three drives."""

from __future__ import annotations

from dataclasses import replace

import pytest

import servodesk_data
from servodesk.od import ObjectDictionaryModel
from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.pdo.recommended import MODES, PROFILES, load_recommendations
from servodesk.pdo.validate import validate
from tests.backend.test_pdo_validate import NODE, context, dictionary, recommendation


def layout(pdos: list[PdoConfig]) -> dict[str, list[str]]:
    """`{"RPDO1": ["6040:00/16", ...]}` for the valid PDOs."""
    return {
        f"{p.kind.upper()}{p.number}": [
            f"{o.index:04X}:{o.subindex:02X}/{o.bits}" for o in p.mapping
        ]
        for p in pdos
        if p.valid
    }


def _entry(o: MappedObject) -> str:
    return f"{o.index:04X}:{o.subindex:02X}/{o.bits}"


def objects(pdos: list[PdoConfig], kind: str) -> set[int]:
    return {o.index for p in pdos if p.kind == kind and p.valid for o in p.mapping}


@pytest.mark.parametrize(
    ("profile", "modes", "expected"),
    [
        # Kinco servo CANopen manual §5.4.5: RPDO1 controlword + target position, TPDO1
        # statusword + position actual internal value
        (
            "kinco",
            ["ip"],
            {"RPDO1": ["6040:00/16", "607A:00/32"], "TPDO1": ["6041:00/16", "6063:00/32"]},
        ),
        # MDi-S1-C CANopen manual §3.4.3 without the optional chapter 6 objects
        (
            "mdi-s1c",
            ["pp"],
            {
                "RPDO1": ["6040:00/16", "607A:00/32", "6060:00/8"],
                "RPDO2": ["6081:00/32", "6083:00/32"],
                "TPDO1": ["6041:00/16", "6064:00/32", "6061:00/8"],
            },
        ),
        # MDi-S1-C CANopen manual §3.8: the interpolation set-point 60C1h:01
        (
            "mdi-s1c",
            ["ip"],
            {"RPDO1": ["6040:00/16", "60C1:01/32"], "TPDO1": ["6041:00/16", "6064:00/32"]},
        ),
        # Kinco servo CANopen manual §5.4.6: controlword / statusword (bit 15 reference found)
        ("kinco", ["hm"], {"RPDO1": ["6040:00/16"], "TPDO1": ["6041:00/16"]}),
        # Nanotec CANopen article example rows lead the profile position mapping
        (
            "cia402",
            ["pp"],
            {
                "RPDO1": ["6040:00/16", "607A:00/32", "6060:00/8"],
                "RPDO2": ["6081:00/32"],
                "TPDO1": ["6041:00/16", "6064:00/32", "6061:00/8"],
            },
        ),
    ],
)
def test_required_objects_only(
    profile: str, modes: list[str], expected: dict[str, list[str]]
) -> None:
    assert layout(recommendation(profile, modes, optional=False)) == expected


def test_mdi_profile_position_and_velocity_is_the_chapter_6_example() -> None:
    # MDi-S1-C CANopen manual chapter 6 step 11: 3 RPDOs, 2 TPDOs, type 255
    pdos = recommendation("mdi-s1c", ["pv", "pp"])
    assert [p.number for p in pdos if p.valid and p.kind == "rpdo"] == [1, 2, 3]
    assert [p.number for p in pdos if p.valid and p.kind == "tpdo"] == [1, 2]
    assert objects(pdos, "rpdo") == {0x6040, 0x6060, 0x607A, 0x6081, 0x6083, 0x6084, 0x60FF}
    assert objects(pdos, "tpdo") == {0x603F, 0x6041, 0x6061, 0x6064, 0x606C}
    assert {p.transmission_type for p in pdos} == {255}


# event-driven TPDOs get ServoDesk's 100 ms event timer (the manuals give none): a standing
# drive still reports its state every 100 ms
@pytest.mark.parametrize(
    ("profile", "modes", "rpdo_type", "tpdo_type", "inhibit", "event_timer"),
    [
        ("mdi-s1c", ["pp"], 255, 255, 100, 100),  # chapter 6 step 11; 10 ms inhibit (§2.5.3 3))
        ("kinco", ["pv"], 255, 254, 100, 100),  # §5.4.4: FEh, inhibit 100 = 10 ms
        ("cia402", ["pt"], 255, 255, 100, 100),  # the drive's own 1800h:03 default
        ("mdi-s1c", ["pp", "ip"], 1, 1, 0, 0),  # interpolation runs on SYNC
        ("kinco", ["ip"], 1, 1, 0, 0),  # §5.4.5
        ("cia402", ["hm", "ip"], 1, 1, 0, 0),
    ],
)
def test_transmission_follows_the_manual(
    profile: str, modes: list[str], rpdo_type: int, tpdo_type: int, inhibit: int, event_timer: int
) -> None:
    used = [p for p in recommendation(profile, modes) if p.valid]
    assert {(p.kind, p.transmission_type) for p in used} == {
        ("rpdo", rpdo_type),
        ("tpdo", tpdo_type),
    }
    assert {p.inhibit_time_100us for p in used if p.kind == "tpdo"} == {inhibit}
    assert {p.event_timer_ms for p in used if p.kind == "tpdo"} == {event_timer}
    assert {p.inhibit_time_100us + p.event_timer_ms for p in used if p.kind == "rpdo"} == {0}


def test_no_event_timer_where_the_drive_has_no_sub_5() -> None:
    od = dictionary("mdi-s1c", NODE)
    objects = dict(od.objects)
    for index in range(0x1800, 0x1804):  # TPDO1–4 communication parameters without sub 5
        subs = {n: sub for n, sub in objects[index].subs.items() if n != 5}
        objects[index] = replace(objects[index], subs=subs)
    pdos = recommendation("mdi-s1c", ["pp"], od=replace(od, objects=objects))
    assert {p.event_timer_ms for p in pdos if p.kind == "tpdo"} == {0}
    assert validate(pdos, context("mdi-s1c", od=replace(od, objects=objects))) == []


@pytest.mark.parametrize("profile", ["mdi-s1c", "kinco", "cia402"])
@pytest.mark.parametrize("modes", [[mode] for mode in MODES] + [list(MODES)])
def test_every_pdo_of_the_drive_is_defined_and_valid(profile: str, modes: list[str]) -> None:
    ctx = context(profile)
    pdos = recommendation(profile, modes)
    assert [(p.kind, p.number) for p in pdos] == [
        *(("rpdo", n) for n in range(1, ctx.rpdo_count + 1)),
        *(("tpdo", n) for n in range(1, ctx.tpdo_count + 1)),
    ]
    first = {p.kind: p.mapping[0] for p in pdos if p.number == 1}
    assert (first["rpdo"].index, first["rpdo"].name) == (0x6040, "Controlword")
    assert (first["tpdo"].index, first["tpdo"].name) == (0x6041, "Statusword")
    for pdo in pdos:
        if pdo.number <= 4:  # the pre-defined connection set
            base = 0x200 if pdo.kind == "rpdo" else 0x180
            assert pdo.cob_id == base + 0x100 * (pdo.number - 1) + NODE
        if not pdo.valid:
            assert pdo.mapping == ()
        assert all(obj.name == ctx.od.get(obj.index, obj.subindex).name for obj in pdo.mapping)  # type: ignore[union-attr]
    assert validate(pdos, ctx) == []
    assert {p.kind for p in pdos if p.valid} == {"rpdo", "tpdo"}


def test_generic_profiles_use_the_cia402_objects_the_dictionary_has() -> None:
    assert recommendation("generic-cia402", ["pp", "pv"]) == recommendation("cia402", ["pp", "pv"])
    # a dictionary without 6081h profile velocity: it is left out, nothing else changes
    od = dictionary("cia402")
    lacking = replace(od, objects={i: o for i, o in od.objects.items() if i != 0x6081})
    pdos = recommendation("generic-cia402", ["pp"], od=lacking)
    assert 0x6081 not in objects(pdos, "rpdo")
    assert objects(pdos, "rpdo") == {0x6040, 0x607A, 0x6060, 0x6083, 0x6084}


def test_no_modes_leaves_every_pdo_invalid() -> None:
    pdos = recommendation("kinco", [])
    assert len(pdos) == 8
    assert not any(p.valid or p.mapping for p in pdos)


def _strip(od: ObjectDictionaryModel, index: int) -> ObjectDictionaryModel:
    return replace(od, objects={i: o for i, o in od.objects.items() if i != index})


@pytest.mark.parametrize(
    ("profile", "modes", "changes", "message"),
    [
        ("mdi-s1c", ["pp", "xx"], {}, "unknown mode(s) 'xx'; known: pp, pv, pt, hm, ip"),
        (
            "acme",
            ["pp"],
            {},
            "unknown profile 'acme'; known: mdi-s1c, kinco, cia402, generic-cia402",
        ),
        (
            "kinco",
            list(MODES),
            {"rpdo_count": 2},
            "the PP, PV, PT, HM, IP objects need 3 RPDOs [(]136 bits[)]"
            " but this drive has 2 usable",
        ),
        (
            "generic-cia301",
            ["pv"],
            {"od": _strip(dictionary("cia402"), 0x6040)},
            "no PDO-mappable 6040h:00: without it no RPDO can drive the PV mode",
        ),
    ],
)
def test_refusals_say_why(
    profile: str, modes: list[str], changes: dict[str, object], message: str
) -> None:
    with pytest.raises(ValueError, match=message.replace("(s)", r"\(s\)")):
        recommendation(profile, modes, **changes)


@pytest.mark.parametrize("profile", PROFILES)
def test_every_profile_has_its_data_file(profile: str) -> None:
    data = load_recommendations(profile)
    assert set(data.modes) == set(MODES)
    assert all(mode.source for mode in data.modes.values())
    assert data.synchronous.tpdo == 1


def test_a_bad_data_file_names_file_and_key(tmp_path: pytest.TempPathFactory) -> None:
    from servodesk.pdo.recommended import _load

    path = servodesk_data.data_dir("kinco") / "recommended_pdos.toml"
    broken = path.read_text(encoding="utf-8").replace('"6063:00"', '"6063"', 1)
    target = tmp_path / "recommended_pdos.toml"  # type: ignore[operator]
    target.write_text(broken, encoding="utf-8")
    with pytest.raises(
        ValueError, match=r"recommended_pdos.toml: modes.pp.tpdo: object reference '6063'"
    ):
        _load(target)
