"""The live scope: signals of several drives at the SYNC rate, triggers, rerun recordings."""
