"""The CANopen protocol core shared by the app (servodesk) and the simulated drives
(servodesk_sim): I/O-free, one module per CiA service, as python-canopen lays it out.

- `cob_id`: COB-ID bases of the pre-defined connection set, COB-ID bits.
- `nmt`: NMT command specifiers and frames, error-control (heartbeat/boot-up/guarding) states.
- `sdo_abort`: SDO abort codes and their meanings.
- `pdo`: PDO parameter layout, mapping entries, packing, transmission types.
- `emcy`: EMCY data in the MDi, Kinco and CiA 301 formats; error register bits.
- `emcy_codes`: CiA 402 / CiA 301 EMCY codes and classes in words, error register words.
- `cia402`: controlword builders, statusword states, modes of operation.

Neither the app nor the simulator owns these definitions, so the tool and the simulated drives
can never disagree on a frame layout, a COB-ID or an abort code.
"""
