"""Motion: the CiA 402 drive panel (state, "why won't it enable"), moves in every mode the
drive supports, homing and interpolated streams — a service over pure cores."""
