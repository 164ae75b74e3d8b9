"""A parameter set made for another device is refused before anything is written, unless the
user confirms it; the compare view carries the identity check and keeps status values apart.
The bitrate dialog gets only what each drive supports."""

from __future__ import annotations

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
