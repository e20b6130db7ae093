"""The independent blade-element truth helicopter (docs/truth-world.md).

Written from the rotorcraft literature, never from the host's model: nothing here
imports airwake.heli, airwake.calibrate, airwake.estimate or airwake.discrepancy
(tests/hil_sim/test_hidden_independence.py), and no constant is shared with them.
One module per physical part, each citing its sources:

    airframe.py      the airframe file (airframe_600.toml): every parameter and its source
    atmosphere.py    air density (ISA gas law) and WGS-84 normal gravity
    airfoil.py       NACA 0012 through 360 deg (Sheldahl & Klimas 1981)
    blade_element.py strip-theory section loads, Prandtl tip loss, teetering kinematics
    main_rotor.py    two blades on a teetering hub, Bell-Hiller pitch law
    flybar.py        the Bell-Hiller flybar, a free teetering rotor with paddles
    inflow.py        Pitt-Peters dynamic inflow, tail inflow, skewed wake, ground images
    tail_rotor.py    blade-element tail rotor geared to the main shaft
    fuselage.py      fuselage tables in angle of attack and sideslip, stabiliser and fin
    drive.py         battery, ESC governor, brushless motor, gear
    servos.py        servos, CCPM swashplate, rigging errors, the tail gyro
    dynamics.py      Kane's equations of the whole machine, its own RK4
    model.py         the assembled helicopter: trim and linearisation (captive rotor)
    flight.py        a flight through a wind field sampled where the elements are
"""
