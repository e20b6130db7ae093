"""The evaluation pipeline's fixed frame: the stages an effect may implement, in the order
they run (within a stage, in the model's order of effects), and the effect whose states
are the body states (eq 5.1-5.2). Read by the effects' base class, the model and the code
generator alike; see `airwake.heli.effects.base` for what each stage may do.
"""

STAGES = (
    "environment",
    "inputs",
    "rotor_speed",
    "rotor_setup",
    "blade_pitch",
    "rotor_loading",
    "inflow",
    "forces",
    "state_rates",
    "body_dynamics",
    "measurement",
)

# position, velocity (3:6), Euler angles (6:9) and body rates (9:12) are its first states
BODY_EFFECT = "rigid_body"
