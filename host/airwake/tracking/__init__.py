"""Tracking: LOSA triangulation (and, later, attitude initialisation and the EKF).

- `losa`: the tracker geometry constants and `triangulate(peak_px, slot, valid)`.
"""
