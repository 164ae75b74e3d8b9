"""Where python-canopen 2.4.1 reads a corpus file, we read the same objects and defaults.

Where we differ on a default, we must have said so in a warning for that entry (python-canopen
drops such values silently or keeps ones that do not fit the type).
"""

from __future__ import annotations

import math
from pathlib import Path

import canopen
import pytest
from canopen.objectdictionary import ODVariable

from servodesk.od import load_od
from tests.od.corpus import corpus, corpus_files

NODE = 5
INI_FILES = [p for p in corpus_files() if p.suffix.lower() in (".eds", ".dcf")]
CANOPEN_REFUSES = {"CANopenNode_DS301_profile.eds"}  # empty VendorNumber (SOURCES.md)
DUMMIES = range(0x0001, 0x0008)  # python-canopen adds DummyUsage entries as objects


def _same(ours: object, theirs: object) -> bool:
    if isinstance(ours, float) and isinstance(theirs, float):
        return math.isclose(ours, theirs, rel_tol=1e-6)  # we round REAL32 to what it can hold
    return ours == theirs


@pytest.mark.parametrize(
    "path",
    [p for p in INI_FILES if p.name not in CANOPEN_REFUSES],
    ids=lambda p: p.name,
)
def test_same_objects_and_defaults_as_python_canopen(path: Path) -> None:
    model = load_od(path, node_id=NODE)
    # python-canopen opens with the locale's encoding; give it the one we detected
    with path.open(encoding=model.encoding) as stream:
        od = canopen.import_od(stream, node_id=NODE)
    assert set(model.objects) == set(od.indices) - set(DUMMIES)
    explained = {(w.section, w.key) for w in model.warnings}
    compared = 0
    for index in model.objects:
        obj = od[index]
        variables = [obj] if isinstance(obj, ODVariable) else [obj[s] for s in obj.subindices]
        for var in variables:
            ours = model.get(index, var.subindex)
            assert ours is not None, f"{index:04X}sub{var.subindex}"
            section = (
                f"{index:04X}" if isinstance(obj, ODVariable) else f"{index:04X}sub{var.subindex:X}"
            )
            if var.default is not None and not _same(ours.default, var.default):
                assert (section, "DefaultValue") in explained, (section, ours.default, var.default)
            assert ours.data_type == var.data_type, section
            compared += 1
    assert compared >= len(model.objects)


def test_we_load_what_python_canopen_refuses() -> None:
    path = corpus("CANopenNode_DS301_profile.eds")
    with pytest.raises(ValueError, match="invalid literal"):
        canopen.import_od(str(path))
    assert len(load_od(path).objects) == 33
