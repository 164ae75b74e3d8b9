"""The homing methods' English words, as the server sends them, are the page's English
catalogue word for word (the page shows the catalogue's Chinese in zh-CN by method number and by
these words)."""

from __future__ import annotations

import json
from pathlib import Path

from servodesk.motion.homing import METHODS

LOCALES = Path(__file__).parents[2] / "frontend" / "src" / "i18n" / "locales"


def drive(language: str) -> dict[str, dict[str, object]]:
    tree = json.loads((LOCALES / f"drive.{language}.json").read_text(encoding="utf-8"))
    words: dict[str, dict[str, object]] = tree["drive"]
    return words


def test_the_method_names_and_descriptions_are_the_servers() -> None:
    catalogue = drive("en")["homingMethod"]
    assert catalogue == {
        f"m{number}": {"name": info.name, "description": info.description}
        for number, info in METHODS.items()
    }


def test_every_path_word_is_in_both_catalogues() -> None:
    untils = {step.until for info in METHODS.values() for step in info.path}
    assert set(drive("en")["homingUntil"].values()) == untils
    assert drive("zh-CN")["homingUntil"].keys() == drive("en")["homingUntil"].keys()
