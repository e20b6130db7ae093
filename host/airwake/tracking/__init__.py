"""Tracking: LOSA triangulation, attitude initialisation and the pose EKF.

- `losa`: the tracker geometry constants and `triangulate(peak_px, slot, valid)`.
- `attitude`: TRIAD and Wahba (SVD, Davenport) solves from vector pairs (eq 3.5-3.6).
- `pose_ekf`: the error-state pose EKF on filterpy (eq 3.7-3.14, improved).
- `offline`: `track_streams`, the EKF over a recording's message tables.
- `marker`: the active marker's LED geometry.
"""
