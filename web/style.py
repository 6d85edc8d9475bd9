"""The viewer's colours: one definition each, imported by the 3D scene and by every chart.

The legs' colours are the 3D legs' stance markers and the footfall diagram's rows, so that a
person matches a leg in the view to its row at a glance; the gaits' colours are the bifurcation
panel's and the atlas's; the ramp's direction colours are the bifurcation and ramp-path
panels'. The 3D scene's own light and floor colours sit here too, as RGB triples (what viser's
scene takes), so that no module keeps a palette of its own.
"""

from __future__ import annotations

# Fig. 4's colouring by leg pair: fore (legs 1-2) red, middle (3-4) blue, hind (5-6) green;
# right legs in the full colour, left legs in a light tint of it, so that both the pair and the
# side read at a glance: a tripod is a checkerboard (R1 L2 R3 against L1 R2 L3), a metachronal
# wave a staircase running from hind to fore on each side. Legs in the paper's order, R1 L1 R2
# L2 R3 L3 (`sim_core.contract.LEG_NAMES`).
PAIR_COLOURS = ("#d62728", "#1f77b4", "#2ca02c")
LEFT_TINTS = ("#f1a3a4", "#9cc7e8", "#9fdc9f")
LEG_COLOURS = tuple(PAIR_COLOURS[i // 2] if i % 2 == 0 else LEFT_TINTS[i // 2] for i in range(6))

# The finder's states, coloured by gait: tripod orange, metachronal green, other grey
GAIT_COLOURS = {"tripod": "#ff7f0e", "metachronal": "#2ca02c", "other": "#7f7f7f"}
# a ramp's path, drawn as it goes, one colour per direction (holds grey)
RAMP_COLOURS = {"down": "#8c564b", "up": "#9467bd", "hold": "#999999"}
# the Delta31 panel: the marks where the conditions changed, and a finished job's run beside
# the live walk's
MARK_COLOUR = "#9467bd"
JOB_COLOUR = "#e377c2"

# The 3D floor: 1 cm grid lines light, every 5th darker. Its light without viser's environment
# map: a hemisphere light (sky above, warm ground below) fills in what the default lights leave
# dark (web/scene.py says why).
FLOOR_CELL_RGB, FLOOR_SECTION_RGB = (190, 190, 190), (120, 120, 120)
SKY_RGB, GROUND_RGB = (255, 255, 255), (140, 125, 110)


def rgb(colour: str) -> tuple[int, int, int]:
    """A "#rrggbb" colour as the (r, g, b) bytes viser's scene takes."""
    c = colour.lstrip("#")
    return int(c[0:2], 16), int(c[2:4], 16), int(c[4:6], 16)
