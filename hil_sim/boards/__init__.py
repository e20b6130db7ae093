"""hil_sim.boards: the native firmware boards in the loop (channel.py: the sim channel)."""
