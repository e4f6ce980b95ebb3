"""The built-in scenarios: a table of overrides of the defaults of :mod:`lubelink.params`, and their constants.

Pure data (no import), so that the command line can name the scenarios in its help without loading
NumPy; :mod:`lubelink.config` resolves them.
"""

#: Pad length [m], viscosity [Pa s] and clearance [m] of the ``paper-impact`` scenario (paper Fig. 9):
#: the paper's model (wedge film, no cavitation, 1 mode) puts the first impact at its t = 1.273 s
#: (1.27324 s) with these values. The clearance is the centre of the window of clearances whose
#: first impact is within 2 ms of 1.273 s (5.49141-5.50537 mm, 14 um wide, 7 um from the jumps of
#: the first-impact time at either side), found with ``lubelink.paper.branch_map`` over the pad length
#: and the clearance (docs/branch_map.py); the reproduction needs tension in the oil. See docs/paper.md.
PAPER_IMPACT_PAD_LENGTH = 0.12
PAPER_IMPACT_VISCOSITY = 0.014
PAPER_IMPACT_CLEARANCE = 5.4984e-3

#: The ``guide`` scenario (docs/configuration.md): a total clearance of 40 um (a collar bored H7 over
#: a link ground g6 at 10 mm leaves 5-29 um; a guide for a sliding fit, 20-50 um); ISO VG 32
#: oil at 40 C (32 mm^2/s times 860 kg/m^3); ground steel surfaces of Ra 0.3 um each, combined RMS
#: roughness 1.25 Ra sqrt(2) ~ 0.5 um, no film floor (the mean gap bounds the film; docs/breakdown.md);
#: 15 modes, which docs/model.md section 7.5 shows converged.
GUIDE_CLEARANCE = 4.0e-5
GUIDE_VISCOSITY = 0.0275
GUIDE_ROUGHNESS = 0.5e-6
GUIDE_MODES = 15
#: The ``guide-mixed`` scenario's total clearance [m]: the ``guide`` with half its clearance, where the
#: asperities carry load and the gap stays open (docs/breakdown.md's regime map).
GUIDE_MIXED_CLEARANCE = 2.0e-5

#: The ``driven-piston`` scenario (docs/configuration.md): a motor's torque-speed line through a flywheel drives the
#: paper's mechanism against a piston load, the link's elastic motion acting back on the crank. Its slider's Coulomb
#: friction takes 4 F_f OA a turn; the line's steady mean speed over the crank angle, omega_nl (1 - 2 F_f OA /
#: (pi T_s)) (docs/model.md 3.7), is the paper's 10 pi rad/s with omega_nl = 10 pi / (1 - 2 * 20 * 0.07 / (10 pi)).
PISTON_STALL_TORQUE = 10.0
PISTON_FRICTION = 20.0
PISTON_NO_LOAD_SPEED = 34.489899841992525

#: ``beam.axial_force`` of the scenarios that reproduce the paper (``paper``, ``paper-dry``, ``paper-impact``): the
#: paper drops the axial force (docs/model.md §1.5), so they do too; every other configuration takes the
#: default, ``"auto"`` (the axial force where the model has it).
PAPER_AXIAL_FORCE = "none"

#: Wall-clock budget of every run [s] (``solver.max_wall_time`` of every scenario, hence of every
#: configuration read from a file, a dict or ``--set``): a run that would take longer stops with
#: status ``timeout`` and keeps its results so far. The CLI warns before starting a run whose
#: estimated cost (:mod:`lubelink.estimate`) exceeds it; ``max_wall_time = inf`` lifts it.
DEFAULT_MAX_WALL_TIME = 3600.0

#: Built-in scenarios as overrides of the defaults of :mod:`lubelink.params` (and of
#: :data:`DEFAULT_MAX_WALL_TIME`).
SCENARIOS: dict[str, dict] = {
    "paper": {
        "description": "Section 6 slider-crank, wedge film (paper Figs. 6-8), 1 mode, 0-2 s",
        "beam": {"axial_force": PAPER_AXIAL_FORCE},
        "film": {"model": "wedge"},
        "contact": {"law": "none"},
    },
    "paper-dry": {
        "description": "Section 6 slider-crank without lubricant (paper Fig. 7, dry curve)",
        "beam": {"axial_force": PAPER_AXIAL_FORCE},
        "film": {"model": "none"},
        "contact": {"law": "none"},
    },
    "paper-impact": {
        "description": "Film breakdown and impact, e = 0.7 (paper Fig. 9)",
        "beam": {"axial_force": PAPER_AXIAL_FORCE},
        "film": {"model": "wedge", "clearance": PAPER_IMPACT_CLEARANCE,
                 "viscosity": PAPER_IMPACT_VISCOSITY, "pad_length": PAPER_IMPACT_PAD_LENGTH},
        "contact": {"law": "restitution", "restitution": 0.7},
        # its clearance lies 7 um from a jump of its first impact's branch (docs/paper.md): the
        # figures there were checked at these tolerances, tighter than the defaults
        "solver": {"rtol": 1e-8, "atol": 1e-9},
    },
    "lubricated": {
        "description": "For engineering: the paper's mechanism with the full film (wedge and squeeze), "
                       "cavitation near ambient, rough surfaces (mixed lubrication), impacts and sustained contact",
        "film": {"model": "wedge+squeeze", "cavitation": "half-sommerfeld", "cavitation_pressure": 1.0e5,
                 "roughness": 1.0e-6, "thickness_floor": 1.0e-6},
        "contact": {"law": "restitution", "restitution": 0.7, "min_film": 2.0e-7},
    },
    "guide": {
        "description": "A real prismatic guide (docs/configuration.md): the paper's mechanism, a collar enclosing "
                       "the link with 20 um of oil on each side, ISO VG 32 oil at 40 C, cavitation near ambient, "
                       "ground surfaces with asperity contact, compliant contact, 15 modes; stiff (RODAS4)",
        "beam": {"modes": GUIDE_MODES},
        "film": {"model": "wedge+squeeze", "clearance": GUIDE_CLEARANCE, "viscosity": GUIDE_VISCOSITY, "sides": 2,
                 "cavitation": "half-sommerfeld", "cavitation_pressure": 1.0e5, "roughness": GUIDE_ROUGHNESS,
                 "thickness_floor": 0.0},
        "contact": {"law": "compliant", "min_film": 0.25 * GUIDE_ROUGHNESS},
    },
    "guide-mixed": {
        "description": "The guide with half its clearance (20 um in all, 10 um of oil a side): mixed lubrication, "
                       "the asperities carrying more than the film (54 N beside 37 N), the gap never closing to "
                       "contact (docs/breakdown.md)",
        "beam": {"modes": GUIDE_MODES},
        "film": {"model": "wedge+squeeze", "clearance": GUIDE_MIXED_CLEARANCE, "viscosity": GUIDE_VISCOSITY,
                 "sides": 2, "cavitation": "half-sommerfeld", "cavitation_pressure": 1.0e5,
                 "roughness": GUIDE_ROUGHNESS, "thickness_floor": 0.0},
        "contact": {"law": "compliant", "min_film": 0.25 * GUIDE_ROUGHNESS},
    },
    "driven-piston": {
        "description": "The paper's mechanism (wedge film) driven by a motor's torque-speed line through a flywheel "
                       "of 0.1 kg m^2 against a 0.5 kg piston with a 30 N load and 20 N of friction, the link's "
                       "elastic motion acting back on the crank (drive.coupling = two-way)",
        "film": {"model": "wedge"},
        "contact": {"law": "none"},
        "drive": {"law": "torque-speed", "stall_torque": PISTON_STALL_TORQUE, "no_load_speed": PISTON_NO_LOAD_SPEED,
                  "flywheel_inertia": 0.1, "slider_mass": 0.5, "slider_force": -30.0,
                  "slider_friction": PISTON_FRICTION, "coupling": "two-way"},
    },
    "spatial-slider-crank": {
        "description": "The spatial link (docs/spatial.md): the slider-crank with its crank axis tilted 0.2 rad "
                       "about the slider line and the slider line 5 cm out of the plane (RSSP), u1, u2, u3 "
                       "with 3 modes each, wedge film on the u2 faces, 0-0.5 s",
        "mechanism": {"crank_tilt": 0.2, "slider_offset": 0.05},
        "beam": {"model": "spatial", "modes": 3},
        "film": {"model": "wedge"},
        "contact": {"law": "none"},
        "solver": {"t_end": 0.5},
    },
}
