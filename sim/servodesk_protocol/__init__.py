"""The CANopen protocol core shared by the app (servodesk) and the simulated drives
(servodesk_sim): I/O-free, one module per CiA service, as python-canopen lays it out.

Neither the app nor the simulator owns these definitions, so the tool and the simulated drives
can never disagree on a frame layout, a COB-ID or an abort code.
"""
