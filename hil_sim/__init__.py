"""hil_sim: the software-in-the-loop world (truth dynamics, sensors, boards over ptys)."""
