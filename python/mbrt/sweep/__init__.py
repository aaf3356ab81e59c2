"""Parameter sweeps and Monte Carlo runs of a compiled model (`mbrt sweep`, docs/sweeps.md)."""
