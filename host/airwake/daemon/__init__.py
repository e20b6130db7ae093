"""The ship-laptop daemon (`airwake daemon`): ports -> decode -> clock mapping -> recording,
link health and the marker loop. See docs/daemon.md.
"""
