"""Simulated data: the shipped reconstruction and the studies that calibrate the verdicts.

Modules
-------
synthetic
    The seeded generator of the shipped synthetic reconstruction (profiles and photographs).
coverage
    How often the intervals hold the truth on data made with known parameters.
calibration
    Error rates of the claims' verdicts on reconstructed and boundary worlds.
"""
