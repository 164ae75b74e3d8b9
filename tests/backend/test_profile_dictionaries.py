"""Profile dictionaries are parsed once, in the parser's worker process, and shared by every
node of the profile; each node sees its own $NODEID entries."""

from __future__ import annotations

import pytest

from servodesk.nodes.profile_dictionaries import ProfileDictionaries
from servodesk.od import load_od
from servodesk.od.parser import OdParser
from servodesk.profiles import load_known, match

pytestmark = pytest.mark.anyio

CIA402_DEVICE_TYPE = 0x00020192  # CiA 402 drive (1000h)
CONTROLWORD = 0x6040
TPDO1_COMMUNICATION = 0x1800  # :01 COB-ID = $NODEID+0x180


async def test_nodes_of_one_profile_share_one_parse() -> None:
    parser = OdParser()
    try:
        dictionaries = ProfileDictionaries(parser)
        profile = match(CIA402_DEVICE_TYPE, None, None, known=load_known())
        assert profile.eds_path is not None
        one, five = await dictionaries.model(profile, 1), await dictionaries.model(profile, 5)
    finally:
        parser.close()
    # what a node-by-node parse gave, object for object
    assert one == load_od(profile.eds_path, node_id=1)
    assert five == load_od(profile.eds_path, node_id=5)
    assert five.get(TPDO1_COMMUNICATION, 1).default == 0x185  # type: ignore[union-attr]
    # but one parse: entries without $NODEID are the same objects for both nodes
    assert one.objects[CONTROLWORD] is five.objects[CONTROLWORD]
