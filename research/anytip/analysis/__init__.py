"""Analyses of the system the paper describes: collision impulse ratio, end-to-end latency
by cross-correlation, zero-phase moving-average filters."""
