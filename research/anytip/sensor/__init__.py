"""Sensor geometry, contact physics, unit variation, calibration protocols, fleet simulation."""
