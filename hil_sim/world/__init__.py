"""The truth world of the simulator.

- `kinematics`: the truth-trajectory container (`Trajectory`) every sensor samples,
  rotation helpers, and analytic trajectories (hover, constant rotation, circle).
- `ship`: ship motion, ship frame <-> inertial transforms, relative wind.
- `wind`: wind fields (still air, uniform, indoor fans, ship airwake) built from
  config dicts, and the 6-parameter local wind of eq 5.3 at the rotor hub.
- `turbulence`: frozen, seeded von Karman / Dryden turbulence boxes.

Frames everywhere: inertial NED (x north, y east, z down; D = 0 is the sea surface or
the hall floor), body FRD (x forward, y right, z down). Quaternions are scalar first
`[w, x, y, z]` and rotate body vectors into NED.

Submodules are imported explicitly (`from hil_sim.world.kinematics import Trajectory`)
so importing the package stays cheap.
"""
