"""anytip: one learned contact model for a whole fleet of barometric fingertip sensors."""

__version__ = "0.1.0"
