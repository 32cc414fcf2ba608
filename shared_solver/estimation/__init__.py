"""Estimation under tap noise: maximum likelihood over every tap, the camera model, the plane
model, mis-tapped landmarks, uncertainty and its calibration, and ranking several roots.
"""
