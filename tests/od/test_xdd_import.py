"""CiA 311 XDD: attribute-style (standard) and parameter-style (CANopenEditor) objects."""

from __future__ import annotations

import pytest

from servodesk.od import DataType, OdImportError, load_od_bytes

STANDARD = b"""<?xml version="1.0" encoding="utf-8"?>
<ISO15745ProfileContainer xmlns="http://www.canopen.org/xml/1.0">
 <ISO15745Profile><ProfileBody fileName="drive.xdd" fileCreator="Vendor" fileVersion="3">
  <DeviceIdentity><vendorName>Vendor</vendorName><vendorID>0x0000009A</vendorID>
   <productName>Drive</productName><productID>0x30923</productID></DeviceIdentity>
 </ProfileBody></ISO15745Profile>
 <ISO15745Profile><ProfileBody>
  <ApplicationLayers><CANopenObjectList>
   <CANopenObject index="1000" name="Device type" objectType="7" dataType="0007"
     accessType="ro" defaultValue="0x00020192" PDOmapping="no"/>
   <CANopenObject index="1400" name="RPDO1 communication" objectType="9" subNumber="3">
    <CANopenSubObject subIndex="00" name="Highest sub-index" objectType="7" dataType="0005"
      accessType="const" defaultValue="2"/>
    <CANopenSubObject subIndex="01" name="COB-ID" objectType="7" dataType="0007"
      accessType="rw" defaultValue="$NODEID+0x200" actualValue="0x80000205"/>
   </CANopenObject>
   <CANopenObject index="607A" name="Target position" objectType="7" dataType="0004"
     accessType="rww" PDOmapping="RPDO" lowLimit="-1000" highLimit="0x3E8" defaultValue="0"/>
   <CANopenObject index="ZZZZ" name="Broken" objectType="7" dataType="0005"/>
  </CANopenObjectList></ApplicationLayers>
  <TransportLayers><PhysicalLayer><baudRate>
   <supportedBaudRate value="250 Kbps"/><supportedBaudRate value="1 Mbps"/>
  </baudRate></PhysicalLayer></TransportLayers>
  <NetworkManagement><CANopenGeneralFeatures granularity="8" nrOfRxPDO="4" nrOfTxPDO="2"
    layerSettingServiceSlave="false"/></NetworkManagement>
 </ProfileBody></ISO15745Profile>
</ISO15745ProfileContainer>
"""

EDITOR = b"""<?xml version="1.0" encoding="utf-8"?>
<ISO15745ProfileContainer xmlns="http://www.canopen.org/xml/1.1">
 <ISO15745Profile><ProfileBody xmlns:q1="http://www.canopen.org/xml/1.1" xmlns="">
  <q1:ApplicationProcess>
   <q1:dataTypeList>
    <q1:array name="Gains" uniqueID="UID_ARR_2000"><q1:subrange lowerLimit="0" upperLimit="2"/>
     <INT/></q1:array>
   </q1:dataTypeList>
   <q1:parameterList>
    <q1:parameter uniqueID="UID_OBJ_1000"><label lang="en">Device type</label><UDINT/>
     <q1:defaultValue value="0x00020192"/></q1:parameter>
    <q1:parameter uniqueID="UID_OBJ_1002"><UDINT/>
     <q1:property name="CO_disabled" value="true"/></q1:parameter>
    <q1:parameter uniqueID="UID_OBJ_2000"><q1:dataTypeIDRef uniqueIDRef="UID_ARR_2000"/>
    </q1:parameter>
    <q1:parameter uniqueID="UID_SUB_200000"><USINT/><q1:defaultValue value="2"/></q1:parameter>
    <q1:parameter uniqueID="UID_SUB_200001" access="readWriteOutput">
     <q1:defaultValue value="-3"/>
     <q1:allowedValues><q1:range><q1:minValue value="-10"/><q1:maxValue value="10"/>
     </q1:range></q1:allowedValues></q1:parameter>
    <q1:parameter uniqueID="UID_SUB_200002" access="readWrite"><REAL/>
     <q1:defaultValue value="1.5"/></q1:parameter>
   </q1:parameterList>
  </q1:ApplicationProcess>
 </ProfileBody></ISO15745Profile>
 <ISO15745Profile><ProfileBody xmlns:q2="http://www.canopen.org/xml/1.1" xmlns="">
  <ApplicationLayers><q2:CANopenObjectList>
   <CANopenObject index="1000" name="Device type" objectType="7" PDOmapping="no"
     uniqueIDRef="UID_OBJ_1000"/>
   <CANopenObject index="1002" name="Manufacturer status" objectType="7"
     uniqueIDRef="UID_OBJ_1002"/>
   <CANopenObject index="2000" name="Gains" objectType="8" uniqueIDRef="UID_OBJ_2000"
     subNumber="3">
    <CANopenSubObject subIndex="00" name="Highest sub-index" objectType="7" PDOmapping="no"
      uniqueIDRef="UID_SUB_200000"/>
    <CANopenSubObject subIndex="01" name="Gain" objectType="7" PDOmapping="optional"
      uniqueIDRef="UID_SUB_200001"/>
    <CANopenSubObject subIndex="02" name="Scale" objectType="7" PDOmapping="no"
      uniqueIDRef="UID_SUB_200002"/>
   </CANopenObject>
  </q2:CANopenObjectList></ApplicationLayers>
 </ProfileBody></ISO15745Profile>
</ISO15745ProfileContainer>
"""


def test_standard_xdd_attributes() -> None:
    model = load_od_bytes(STANDARD, "drive.XDD", node_id=5)
    assert model.format == "xdd"
    assert sorted(model.objects) == [0x1000, 0x1400, 0x607A]
    device = model.device
    assert (device.vendor_number, device.product_number, device.file_version) == (0x9A, 0x30923, 3)
    assert device.baud_rates == frozenset({250_000, 1_000_000})
    assert (device.nr_rx_pdo, device.nr_tx_pdo, device.lss_supported) == (4, 2, False)
    cob_id = model.get(0x1400, 1)
    assert cob_id is not None
    assert (cob_id.default, cob_id.relative, cob_id.value) == (0x205, True, 0x80000205)
    target = model.get(0x607A)
    assert target is not None
    assert (target.data_type, target.access, target.pdo_mappable) == (
        DataType.INTEGER32,
        "rww",
        True,
    )
    assert (target.low, target.high) == (-1000, 1000)
    [error] = [w for w in model.warnings if w.severity == "error"]
    assert "ZZZZ" in error.message
    assert error.line is not None
    assert [w.code for w in model.warnings if w.code == "subnumber-mismatch"] == [
        "subnumber-mismatch"
    ]


def test_canopen_editor_parameters_fill_in_what_the_object_list_leaves_out() -> None:
    model = load_od_bytes(EDITOR, "project.xpd")
    assert sorted(model.objects) == [0x1000, 0x2000]  # 1002h is disabled in the project
    assert [w.code for w in model.warnings] == ["disabled-object"]
    assert model.get(0x1000).access == "ro"  # type: ignore[union-attr]  # no access: read-only
    gains = model.objects[0x2000]
    assert gains.object_type == "array"
    gain = gains.subs[1]
    assert (gain.data_type, gain.access, gain.default) == (DataType.INTEGER16, "rww", -3)
    assert (gain.low, gain.high, gain.pdo_mappable) == (-10, 10, True)
    assert gains.subs[2].data_type == DataType.REAL32
    assert gains.subs[2].default == 1.5


def test_entity_declarations_are_refused() -> None:
    bomb = b"""<?xml version="1.0"?><!DOCTYPE x [<!ENTITY a "aaaaaaaaaa">
    <!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]><ISO15745ProfileContainer>&b;
    </ISO15745ProfileContainer>"""
    with pytest.raises(OdImportError, match="entities"):
        load_od_bytes(bomb, "bomb.xdd")


def test_xml_error_names_the_line() -> None:
    with pytest.raises(OdImportError, match="line 2"):
        load_od_bytes(b"<a>\n<b></a>", "bad.xdd")
