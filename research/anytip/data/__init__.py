"""Calibration run files, the registry, CSV import and training arrays."""
