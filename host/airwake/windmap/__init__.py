"""Anemometer wind maps (reference §3.4): motion compensation, linear wind models, grid."""
