"""A parameter set made for another device is refused before anything is written, unless the
user confirms it; the compare view carries the identity check and keeps status values apart.
The bitrate dialog gets only what each drive supports."""

from __future__ import annotations

import re
from typing import Any

import pytest
from fastapi.testclient import TestClient


def value(client: TestClient, node: int, index: str) -> Any:
    return client.get(f"/api/nodes/{node}/sdo/{index}/0").json()["value"]


def saved_set(client: TestClient, node: int, profile_velocity: int) -> bytes:
    """A DCF saved from `node` with 6081h set to `profile_velocity`, the node left as it was."""
    before = value(client, node, "6081")
    client.put(f"/api/nodes/{node}/sdo/6081/0", json={"value": profile_velocity})
    text: str = client.get(f"/api/nodes/{node}/dcf").text
    client.put(f"/api/nodes/{node}/sdo/6081/0", json={"value": before})
    return text.encode()


def load(client: TestClient, node: int, data: bytes, **form: str) -> Any:
    return client.post(f"/api/nodes/{node}/dcf", files={"file": ("set.dcf", data)}, data=form)


def test_a_set_from_an_mdi_is_refused_on_the_cia402_node(client: TestClient) -> None:
    mdi_set = saved_set(client, 1, 4321)
    before = value(client, 3, "6081")
    refused = load(client, 3, mdi_set)
    assert refused.status_code == 428
    body = refused.json()
    assert body["error"] == "identity_mismatch"
    assert body["message"].startswith("set.dcf is for vendor 0x00445653")
    assert "node 3 is vendor 0x0000026C" in body["message"]
    assert body["message"].endswith("nothing was written. Load it anyway with confirm")
    assert value(client, 3, "6081") == before  # nothing written

    confirmed = load(client, 3, mdi_set, confirm="true")
    assert confirmed.status_code == 200, confirmed.text
    assert confirmed.json()["identity"]["matches"] is False
    assert value(client, 3, "6081") == 4321


def test_a_foreign_vendor_is_refused(client: TestClient) -> None:
    own = saved_set(client, 3, 777).decode()
    foreign = own.replace("VendorNumber=0x0000026C", "VendorNumber=0x00BADBAD")
    foreign = foreign.replace("ParameterValue=0x26C", "ParameterValue=0xBADBAD")
    assert "BADBAD" in foreign
    before = value(client, 3, "6081")
    refused = load(client, 3, foreign.encode())
    assert refused.status_code == 428
    assert "vendor 0x00BADBAD" in refused.json()["message"]
    assert value(client, 3, "6081") == before


def test_the_same_device_loads_without_a_question(client: TestClient) -> None:
    own = saved_set(client, 3, 555)
    loaded = load(client, 3, own)
    assert loaded.status_code == 200, loaded.text
    assert loaded.json()["identity"]["matches"] is True
    assert value(client, 3, "6081") == 555


def without_sections(dcf: str, names: set[str]) -> str:
    """`dcf` without the named [sections] (a hand-edited file)."""
    kept = re.split(r"(?m)^(?=\[)", dcf)
    return "".join(part for part in kept if part.split("]")[0].lstrip("[") not in names)


def with_value(dcf: str, section: str, value: str) -> str:
    """`dcf` with the ParameterValue of [section] set to `value`."""
    head, _, rest = dcf.partition(f"[{section}]")
    body, bracket, tail = rest.partition("\n[")
    body = re.sub(r"(?m)^ParameterValue=.*$", f"ParameterValue={value}", body)
    assert f"ParameterValue={value}" in body
    return f"{head}[{section}]{body}{bracket}{tail}"


def test_a_set_without_identity_is_confirmed_like_a_mismatch(client: TestClient) -> None:
    mdi_set = saved_set(client, 1, 4321).decode()
    stripped = without_sections(mdi_set, {"1000", "1018sub1", "1018sub2", "1018sub3", "1018sub4"})
    stripped = re.sub(r"(?m)^(VendorNumber|ProductNumber)=.*\n", "", stripped)
    assert "[1018sub1]" not in stripped
    assert "VendorNumber" not in stripped
    before = value(client, 3, "6081")
    preview = client.post("/api/nodes/3/compare", files={"file": ("bare.dcf", stripped)}).json()
    assert preview["identity"]["checked"] is False
    assert preview["identity"]["matches"] is False
    assert preview["confirm"] == [preview["identity"]["message"]]
    refused = load(client, 3, stripped.encode())
    assert refused.status_code == 428
    assert refused.json()["error"] == "identity_mismatch"
    assert refused.json()["message"].startswith("set.dcf names no device")
    assert "node 3 (vendor 0x0000026C" in refused.json()["message"]
    assert value(client, 3, "6081") == before  # nothing written
    assert load(client, 3, stripped.encode(), confirm="true").status_code == 200
    assert value(client, 3, "6081") == 4321


def test_a_set_with_a_1_ms_heartbeat_needs_confirm(client: TestClient) -> None:
    fast = with_value(saved_set(client, 3, 888).decode(), "1017", "0x1")
    before, velocity = value(client, 3, "1017"), value(client, 3, "6081")
    assert velocity != 888
    preview = client.post("/api/nodes/3/compare", files={"file": ("fast.dcf", fast)}).json()
    assert preview["identity"]["matches"] is True
    assert preview["confirm"] == [
        "fast.dcf sets a heartbeat every 1 ms (1017h): 1000 frames/s from one node; "
        "below 10 ms needs confirm"
    ]
    refused = load(client, 3, fast.encode())
    assert refused.status_code == 428
    assert refused.json()["error"] == "confirmation_required"
    assert "nothing was written" in refused.json()["message"]
    assert (value(client, 3, "1017"), value(client, 3, "6081")) == (before, velocity)
    loaded = load(client, 3, fast.encode(), confirm="true")
    assert loaded.status_code == 200, loaded.text
    assert (value(client, 3, "1017"), value(client, 3, "6081")) == (1, 888)
    client.put("/api/nodes/3/heartbeat", json={"producer_ms": before, "confirm": True})


def test_compare_shows_the_identity_and_keeps_status_apart(client: TestClient) -> None:
    mdi_set = saved_set(client, 1, 4321)
    result = client.post("/api/nodes/3/compare", files={"file": ("mdi.dcf", mdi_set)}).json()
    assert result["identity"]["matches"] is False
    assert "vendor 0x0000026C" in result["identity"]["device"]
    configuration = {(row["index"], row["subindex"]) for row in result["rows"]}
    status = {(row["index"], row["subindex"]): row for row in result["read_only"]}
    assert (0x6041, 0) not in configuration  # Statusword: not part of a parameter set
    assert (0x6041, 0) in status
    assert not any(row["differs_from_file"] for row in result["read_only"])
    assert (0x6081, 0) in configuration


@pytest.mark.parametrize(
    ("node", "settable", "supported"),
    [
        (1, True, [1_000_000, 500_000, 250_000, 125_000, 100_000, 50_000, 20_000]),
        (2, True, [1_000_000, 500_000, 250_000, 125_000, 50_000, 20_000]),
        (3, False, []),
    ],
)
def test_bitrates_offered_are_the_drives_own(
    client: TestClient, node: int, settable: bool, supported: list[int]
) -> None:
    options = client.get(f"/api/nodes/{node}/bitrates").json()
    assert options["settable"] is settable
    assert options["supported"] == supported
    if settable:
        assert options["current"] in supported
        assert "kbit/s" in options["note"]
    else:
        assert "outside CANopen" in options["note"]
