"""Figures and markdown reports."""
