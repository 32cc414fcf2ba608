"""Taps and the answer they give (the solver called with both phones' taps)."""
