"""What the paper states (Fujiki et al. 2013, Secs. III A-D, IV): the numbers every
comparison in the project is made against. Angles in rad; beta is dimensionless."""

from __future__ import annotations

from dataclasses import dataclass

TRIPOD_BRANCH = 2.9  # rad, paper Fig. 5, beta = 0.62
METACHRONAL_BRANCH = 1.9  # rad, paper Fig. 5, beta = 0.70
BETA_FAST = 0.62  # Fig. 5: the tripod speed (3.6 cm/s)
BETA_SLOW = 0.70  # Fig. 5: the metachronal speed (2.5 cm/s)
BETA_BISTABLE = 0.655  # inside the paper's bistable window 0.645-0.67 (Figs. 7, 8)


@dataclass(frozen=True)
class PaperValues:
    """What the paper states (Secs. III A-D, IV), for comparison; beta is dimensionless."""

    branch_tripod_rad: float = TRIPOD_BRANCH  # Fig. 5, beta 0.62
    branch_metachronal_rad: float = METACHRONAL_BRANCH  # Fig. 5, beta 0.70
    speed_cm_s: tuple[tuple[float, float], ...] = ((0.62, 3.6), (0.70, 2.5))  # Sec. III A
    transition_down: float = 0.645  # metachronal -> tripod as beta decreases (speed up)
    transition_up: float = 0.67  # tripod -> metachronal as beta increases
    tripod_stable: tuple[float, float] = (0.62, 0.67)  # Fig. 8
    metachronal_stable: tuple[float, float] = (0.645, 0.70)  # Fig. 8
    # Fig. 7: (beta, stable/unstable pattern inside PAPER_WINDOW, gait of a lone stable point)
    fixed_points: tuple[tuple[float, str, str | None], ...] = (
        (0.64, "S", "tripod"),
        (0.655, "S U S", None),
        (0.675, "S", "metachronal"),
    )
    ghosts_rad: tuple[tuple[float, float], ...] = ((0.64, 2.0), (0.675, 2.8))  # Fig. 7


PAPER = PaperValues()

# the figures `reproduce` makes; here (no imports) so that the CLI parser loads no MuJoCo
FIGURES = ("5", "6", "7", "8", "9", "ablation")
