"""The PDO SYNC rule in the browser: node 3's recommended PP+PV+PT+IP mapping is synchronous;
with no SYNC produced or heard the page warns, and once the user says SYNC comes from the
machine's controller it is written and the drive holds it."""

from __future__ import annotations

from typing import Any

from playwright.sync_api import Page, expect

from tests.e2e.conftest import SCREENSHOTS


def mapped(pdos: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
    """What the drive holds, without the names and words the server adds."""
    return sorted(
        (
            p["kind"],
            p["number"],
            p["cob_id"],
            p["valid"],
            p["transmission_type"],
            tuple((m["index"], m["subindex"], m["bits"]) for m in p["mapping"]),
        )
        for p in pdos
    )


def test_synchronous_mapping_written_for_the_machines_controller(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/3/pdos")
    expect(page.get_by_label("Profile position (PP)")).to_be_checked()
    for mode in ("Profile velocity (PV)", "Profile torque (PT)", "Interpolated position (IP)"):
        page.get_by_label(mode).check()
    page.get_by_role("button", name="Recommend mapping").click()
    expect(page.get_by_role("region", name="RPDO1 draft")).to_be_visible()

    page.get_by_role("button", name="Validate").click()
    expect(page.get_by_text("No SYNC on the bus")).to_be_visible()
    choice = page.get_by_role("group", name="SYNC for the synchronous PDOs")
    expect(choice.get_by_role("alert")).to_contain_text(
        "synchronous but no SYNC is produced or heard on the bus"
    )
    expect(choice.get_by_role("button", name="Produce SYNC")).to_be_visible()

    choice.get_by_label("SYNC comes from the machine's controller (PLC)").check()
    expect(page.get_by_text("Checked: no problems")).to_be_visible()
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    page.get_by_role("region", name="Draft", exact=True).screenshot(
        path=str(SCREENSHOTS / "pdo_sync.png")
    )

    page.get_by_role("button", name="Apply…").click()
    dialog = page.get_by_role("dialog")
    expect(dialog.get_by_text("SYNC comes from the machine's controller (PLC).")).to_be_visible()
    dialog.get_by_role("button", name="Apply", exact=True).click()
    expect(page.get_by_text("Read back from the device", exact=False)).to_be_visible()

    wanted = page.request.get(
        f"{server}/api/nodes/3/pdos/recommended", params={"modes": "pp,pv,pt,ip"}
    ).json()["pdos"]
    held = page.request.get(f"{server}/api/nodes/3/pdos").json()
    assert mapped(held) == mapped(wanted)
    assert any(p["valid"] and p["transmission_type"] == 1 for p in held)  # synchronous
    sync = page.request.get(f"{server}/api/sync").json()
    assert sync["producing"] is False  # written without ServoDesk producing SYNC
