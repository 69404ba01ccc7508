"""Uncertainty and fault detection: heteroscedastic ensembles, conformal intervals (split, cross,
per-unit bootstrap), the adapted model's scale network, and signals that flag faulty units."""
