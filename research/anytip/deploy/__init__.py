"""Deployment: one unit of a model file exported to ONNX, C (float32, int8) and the firmware struct,
each verified against the trained model and measured on a Cortex-M4F (see docs/deploy.md)."""
